// Formatting of bench results. The CSV has one row per setting with raw numbers (PSNR `inf`
// when the error is zero); the Markdown repeats it for humans with the settings used; the SVG
// goes through svg_plot with one series per knob in the order the knobs were swept.
#include "app/bench_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/svg_plot.h"

namespace wsd::app {

namespace {

std::string fmt(const char* format, double v) {
    if (std::isinf(v)) return "inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

std::string estimate(const BenchRow& r, const char* format) {
    return r.estimated_rmse ? fmt(format, *r.estimated_rmse) : std::string("-");
}

}  // namespace

void mark_pareto(std::vector<BenchRow>& rows) {
    for (BenchRow& a : rows) {
        a.pareto = true;
        for (const BenchRow& b : rows) {
            const bool no_worse = b.wall_seconds <= a.wall_seconds && b.error.rmse <= a.error.rmse;
            const bool better = b.wall_seconds < a.wall_seconds || b.error.rmse < a.error.rmse;
            if (no_worse && better) {
                a.pareto = false;
                break;
            }
        }
    }
}

std::string bench_table(const std::vector<BenchRow>& rows) {
    std::ostringstream out;
    // The knob column is as wide as its longest name (exact_area_lights is longer than "knob" pads to).
    int knob = 16;
    for (const BenchRow& r : rows) knob = std::max(knob, static_cast<int>(r.knob.size()));
    char buf[512];
    std::snprintf(buf, sizeof buf, "%-*s %6s %10s %10s %12s %12s %10s %10s %9s %8s %s\n", knob, "knob",
                  "value", "wall s", "cpu s", "ray queries", "shadow rays", "RMSE", "est. RMSE", "PSNR dB",
                  "SSIM", "pareto");
    out << buf;
    for (const BenchRow& r : rows) {
        std::snprintf(buf, sizeof buf, "%-*s %6s %10.4f %10.4f %12llu %12llu %10.6f %10s %9s %8.5f %s\n",
                      knob, r.knob.c_str(), r.value.c_str(), r.wall_seconds, r.cpu_seconds,
                      static_cast<unsigned long long>(r.stats.ray_queries()),
                      static_cast<unsigned long long>(r.stats.shadow_rays), r.error.rmse,
                      estimate(r, "%.6f").c_str(), fmt("%.2f", r.error.psnr).c_str(), r.error.ssim,
                      r.pareto ? "*" : "");
        out << buf;
    }
    return out.str();
}

std::string bench_csv(const std::vector<BenchRow>& rows) {
    std::ostringstream out;
    out << "knob,value,wall_seconds,cpu_seconds,camera_rays,shadow_rays,reflection_rays,"
           "refraction_rays,ray_queries,rmse,psnr,max_abs_error,ssim,pareto,estimated_rmse\n";
    for (const BenchRow& r : rows)
        out << r.knob << ',' << r.value << ',' << fmt("%.6f", r.wall_seconds) << ','
            << fmt("%.6f", r.cpu_seconds) << ',' << r.stats.camera_rays << ',' << r.stats.shadow_rays << ','
            << r.stats.reflection_rays << ',' << r.stats.refraction_rays << ',' << r.stats.ray_queries()
            << ',' << fmt("%.9g", r.error.rmse) << ',' << fmt("%.6g", r.error.psnr) << ','
            << fmt("%.9g", r.error.max_abs_error) << ',' << fmt("%.9g", r.error.ssim) << ','
            << (r.pareto ? 1 : 0) << ',' << estimate(r, "%.9g") << '\n';
    return out.str();
}

std::string bench_markdown(const std::vector<BenchRow>& rows, const BenchInfo& info) {
    std::ostringstream out;
    out << "# wsd bench: " << info.scene << "\n\n"
        << "- image: " << info.width << " x " << info.height << " pixels\n"
        << "- scene's own settings: " << info.scene_settings << "\n"
        << "- reference: " << info.reference_settings << " (" << fmt("%.3f", info.reference_seconds)
        << " s)\n"
        << "- times: median of " << info.repeat << " run" << (info.repeat == 1 ? "" : "s")
        << "; CPU time is the whole process (all threads)\n"
        << "- each knob is varied alone; the others keep the scene's settings\n"
        << "- target_error rows render progressively (`wsd render --target-error`); their estimated "
           "RMSE is the render's own, beside the RMSE measured against the reference\n";
    for (const std::string& note : info.notes) out << "- " << note << "\n";
    out << "\n| knob | value | wall s | CPU s | camera rays | shadow rays | reflection rays | refraction "
           "rays "
           "| RMSE | estimated RMSE | PSNR dB | SSIM | Pareto |\n"
        << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|\n";
    for (const BenchRow& r : rows)
        out << "| " << r.knob << " | " << r.value << " | " << fmt("%.4f", r.wall_seconds) << " | "
            << fmt("%.4f", r.cpu_seconds) << " | " << r.stats.camera_rays << " | " << r.stats.shadow_rays
            << " | " << r.stats.reflection_rays << " | " << r.stats.refraction_rays << " | "
            << fmt("%.6f", r.error.rmse) << " | " << estimate(r, "%.6f") << " | " << fmt("%.2f", r.error.psnr)
            << " | " << fmt("%.5f", r.error.ssim) << " | " << (r.pareto ? "*" : "") << " |\n";
    out << "\n![error against time](bench.svg)\n";
    return out.str();
}

std::string bench_svg(const std::vector<BenchRow>& rows, const BenchInfo& info) {
    std::vector<PlotSeries> series;
    for (const BenchRow& r : rows) {
        if (series.empty() || series.back().name != r.knob) series.push_back({r.knob, {}});
        series.back().points.push_back({r.wall_seconds, r.error.rmse, r.value});
    }
    PlotLabels labels;
    labels.title = "wsd bench: " + info.scene + " (" + std::to_string(info.width) + "x" +
                   std::to_string(info.height) + ")";
    labels.x_axis = "render time (s, wall, median)";
    labels.y_axis = "RMSE against the reference";
    return svg_log_log_plot(series, labels);
}

}  // namespace wsd::app
