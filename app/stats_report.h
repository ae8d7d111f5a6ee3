// The statistics of one render: a POV-Ray-like table for `--stats` (stdout) and the JSON of
// `--stats-json FILE` (docs/wsd-cli.md: every counter).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "render/stats.h"

namespace wsd::app {

struct RenderReport {
    std::string scene;
    std::optional<long long> frame;           // the frame of a --frames run (none for a still)
    double clock = 0;                         // the scene's `clock`
    int width = 0, height = 0;                // the full image
    int region_width = 0, region_height = 0;  // the pixels rendered (a tile's size)
    int supersamples = 1;
    int threads = 0;
    render::RayStats stats;
    double parse_seconds = 0, build_seconds = 0, render_seconds = 0;
    double photon_seconds = 0;  // the caustic photon map's part of build_seconds
    uint64_t peak_memory_bytes = 0;
    std::vector<std::string> effects;
    render::ProgressiveReport progressive;  // used: a progressive render's passes and estimate
    std::optional<double> target_error, time_limit;
};

std::string stats_table(const RenderReport& report);
std::string stats_json(const RenderReport& report);

}  // namespace wsd::app
