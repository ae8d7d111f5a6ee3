// What `wsd check`, `wsd render` and `wsd bench` share: reading a scene named on the command line,
// running lang::load_scene with the command-line overrides, and printing its diagnostics.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lang/load.h"
#include "render/limits.h"
#include "render/scene_spec.h"

namespace wsd::app {

// Command-line replacements for scene settings (wsd-cli.md, `wsd render`).
struct SceneOverrides {
    std::optional<int> width, height, supersamples, max_depth;
    std::optional<int> light_samples;  // every area light becomes an N×N grid
    std::optional<uint32_t> seed;
    std::optional<bool> adaptive_supersampling;
    std::optional<bool> adaptive_lights;  // every area light's own `adaptive` flag
    std::optional<double> bailout;        // adaptive depth: settings.bailout
    std::optional<int> indirect_samples, indirect_bounces;
    std::optional<int> caustic_photons;     // settings.caustic_photons
    std::optional<bool> exact_area_lights;  // settings.exact_area_lights

    void apply(render::SceneSpec& spec) const;
};

// Limits of the values the overrides accept (wsd-language.md §4); usage errors beyond them.
constexpr int max_image_side = render::kMaxImageSide;
constexpr long long max_image_pixels = render::kMaxPixels;
constexpr int max_supersamples = render::kMaxSupersamples;
constexpr int max_depth_limit = render::kMaxDepth;
constexpr int max_light_grid_side = render::kMaxSquareLightGridSide;  // N×N grids

// What every command that loads scenes (check, render, bench) takes from the command line.
struct SceneInputArgs {
    std::vector<std::string> defines;  // NAME=EXPR, from --define/-D, in order
    bool no_warnings = false;
};

// The values of the --define options, evaluated once per command (lang::evaluate_define).
// Returns an exit status: 0, or 2 (usage) with a message naming the bad define.
// `time`: the `clock` and `frame` the expressions see (a still's by default).
int evaluate_defines(const std::vector<std::string>& defines, lang::ParamTable& params,
                     const lang::AnimationTime& time = {});

// After a successful load: a warning for each --define that no param() call read (none with
// --no-warnings). The messages, and the function that prints them on stderr.
std::vector<std::string> unread_define_warnings(const lang::ParamTable& params, const SceneInputArgs& input);
void warn_unread_defines(const lang::ParamTable& params, const SceneInputArgs& input);
// The same for the names that no frame of a run read.
void warn_unread_defines(const std::vector<std::string>& unread, const SceneInputArgs& input);

// The name used in messages for a scene read from stdin ("-").
std::string display_path(const std::string& path);

// Reads `path` ("-" = stdin) and loads it. Diagnostics go to stderr (errors only unless
// `warnings`). Returns an exit status: 0 with `scene` set, 1 for scene errors, 3 when the file
// cannot be read.
int load_scene_file(const std::string& path, const lang::LoadOptions& options, lang::SourceManager& sources,
                    std::optional<lang::LoadedScene>& scene, bool warnings = true);

// Same, from text already read (bench loads one text many times). `shown`, when given, holds the
// warnings printed by earlier loads of the same scene (the frames of an animation): those are not
// printed again.
int load_scene_text(const std::string& path, const std::string& text, const lang::LoadOptions& options,
                    lang::SourceManager& sources, std::optional<lang::LoadedScene>& scene,
                    bool warnings = true, std::set<std::string>* shown = nullptr);

// FNV-1a 64 of every source file the load read (the scene and its includes), in order.
uint64_t scene_text_hash(const lang::SourceManager& sources);

// A canonical text of the --define values: for each name, the last NAME=EXPR given (the one
// `param` reads), in name order; "" without any.
std::string defines_fingerprint(const std::vector<std::string>& defines);

// A canonical text of every setting that changes pixels, except the seed: the scene's settings
// with the command line's overrides, --adaptive-lights and the progressive options
// (--target-error, --time-limit).
std::string settings_fingerprint(const render::SceneSpec& spec, bool adaptive_lights,
                                 const std::optional<double>& target_error,
                                 const std::optional<double>& time_limit);

}  // namespace wsd::app
