// The whole front end in one call: read → lex → parse → evaluate → lower → build, stopping after
// any stage that reported errors. This is what `wsd check` and `wsd render` run.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lang/diagnostics.h"
#include "lang/params.h"
#include "render/renderer.h"
#include "render/scene_spec.h"

namespace wsd::lang {

struct CheckSummary {
    size_t objects = 0;    // evaluated object statements; a mesh counts once
    size_t triangles = 0;  // triangle objects plus mesh triangles
    size_t lights = 0;
    size_t materials = 0;  // distinct material values used by objects
    // What the scene stores (distinct geometry): shapes and triangles outside instances plus those
    // of each prototype once, and the instances that place prototypes.
    size_t stored_shapes = 0, stored_triangles = 0, instances = 0;
};

// Reads an included file into `text`; false with the reason (lower case) when it cannot. An
// editor's reader gives its unsaved text. (The same alias is declared in lang/interpreter.h.)
using IncludeReader = std::function<bool(const std::string& path, std::string& text, std::string& reason)>;

// How included files are read from disk when no reader is given: a reader that wraps another
// source (an editor's buffers, a list of the files tried) falls back to it.
bool read_include_file(const std::string& path, std::string& text, std::string& reason);

struct LoadOptions {
    bool fragment = false;  // a `.wsdi` file: no camera required, nothing is built
    bool build = true;      // build the render scene (loads textures, validates geometry)
    bool use_bvh = true;
    int threads = 0;
    std::function<void(render::SceneSpec&)> adjust;  // command-line overrides, before building
    const ParamTable* params = nullptr;              // --define values that param() returns
    AnimationTime time;                              // `clock` and `frame` (0 and 0: a still)
    render::ImageCache* images = nullptr;            // texture images kept across loads (frames)
    IncludeReader read_include;                      // empty: included files are read from disk
    // Set: the path of each mesh file the scene reads is added to it, also when the file is
    // missing or broken (what a preview watches to see the fix).
    std::vector<std::string>* mesh_files = nullptr;
    // Set: the evaluation stops at the next loop iteration or call once it holds true (a signal),
    // and so does shooting caustic photons; load_scene then returns no scene and reports nothing.
    const std::atomic<bool>* cancel = nullptr;
};

struct LoadedScene {
    render::SceneSpec spec;
    std::shared_ptr<const render::Scene> scene;  // null unless options.build
    CheckSummary summary;
    std::vector<Span> shape_spans;  // where each of spec.shapes is written (its keyword or OBJ path)
    double parse_seconds = 0;       // read + lex + parse + evaluate + lower
    double build_seconds = 0;
};

// `path` is used for messages and to resolve relative paths; `text` is the file's contents
// (the caller reads it, so that I/O errors on command-line files stay the caller's).
std::optional<LoadedScene> load_scene(const std::string& path, std::string text, SourceManager& sources,
                                      Diagnostics& diags, const LoadOptions& options);

}  // namespace wsd::lang
