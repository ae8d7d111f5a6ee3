// The results of `wsd bench` and their four forms: the table on stdout, bench.csv, bench.md and
// bench.svg (error against time, one line per knob, the Pareto front marked).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "app/image_metrics.h"
#include "render/stats.h"

namespace wsd::app {

struct BenchRow {
    std::string knob;   // "supersamples", "light_samples", "max_depth", "adaptive_aa", "adaptive_lights",
                        // "bailout", "target_error", "indirect_samples", "indirect_bounces"
    std::string value;  // as the user would type it ("16", "on")
    double wall_seconds = 0;  // median over the repeats
    double cpu_seconds = 0;   // median over the repeats (process CPU time: all threads)
    render::RayStats stats;
    ImageMetrics error;                    // against the reference
    std::optional<double> estimated_rmse;  // the render's own estimate (progressive rows)
    bool pareto = false;                   // no other row is both faster and more accurate
};

struct BenchInfo {
    std::string scene;
    int width = 0, height = 0;
    int repeat = 1;
    std::string scene_settings;  // e.g. "supersamples 16, light samples 4x4, max depth 8"
    std::string reference_settings;
    double reference_seconds = 0;
    std::vector<std::string> notes;  // knobs skipped and why
};

void mark_pareto(std::vector<BenchRow>& rows);
std::string bench_table(const std::vector<BenchRow>& rows);
std::string bench_csv(const std::vector<BenchRow>& rows);
std::string bench_markdown(const std::vector<BenchRow>& rows, const BenchInfo& info);
std::string bench_svg(const std::vector<BenchRow>& rows, const BenchInfo& info);

}  // namespace wsd::app
