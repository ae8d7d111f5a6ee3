// Formatting of render statistics. Percentages guard against zero tests; the JSON is written by
// nlohmann-json.
#include "app/stats_report.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/io_util.h"

namespace wsd::app {

namespace {

std::string fixed(double value, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
    return buf;
}

std::string percent(uint64_t part, uint64_t whole) {
    if (whole == 0) return "-";
    return fixed(100.0 * static_cast<double>(part) / static_cast<double>(whole), 2) + "%";
}

std::string fixed_digits(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

double mrays_per_second(const RenderReport& r) {
    return r.render_seconds > 0 ? static_cast<double>(r.stats.ray_queries()) / r.render_seconds / 1e6 : 0.0;
}

void row(std::ostringstream& out, const char* name, uint64_t tests, uint64_t hits, bool has_hits) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%-24s %16llu %16s %12s\n", name, static_cast<unsigned long long>(tests),
                  has_hits ? std::to_string(hits).c_str() : "-",
                  has_hits ? percent(hits, tests).c_str() : "-");
    out << buf;
}

void line(std::ostringstream& out, const char* name, const std::string& value) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%-28s %s\n", name, value.c_str());
    out << buf;
}

}  // namespace

std::string stats_table(const RenderReport& r) {
    const std::string rule(72, '-');
    const render::RayStats& s = r.stats;
    std::ostringstream out;
    out << rule << '\n' << "Render statistics: " << r.scene;
    if (r.frame) out << ", frame " << *r.frame;
    if (r.frame || r.clock != 0) out << ", clock " << r.clock;
    out << '\n' << "Image resolution " << r.width << " x " << r.height;
    if (r.region_width != r.width || r.region_height != r.height)
        out << " (rendered " << r.region_width << " x " << r.region_height << ")";
    out << '\n' << rule << '\n';
    const uint64_t pixels = static_cast<uint64_t>(r.region_width) * static_cast<uint64_t>(r.region_height);
    line(out, "Pixels:", std::to_string(pixels));
    line(out, "Camera rays:",
         std::to_string(s.camera_rays) + "  (" +
             (pixels ? fixed(static_cast<double>(s.camera_rays) / static_cast<double>(pixels), 2)
                     : std::string("-")) +
             " per pixel)");
    line(out, "Shadow rays:", std::to_string(s.shadow_rays));
    line(out, "  answered by shaft alone:", std::to_string(s.shaft_answered_rays));
    line(out, "Reflected rays:", std::to_string(s.reflection_rays));
    line(out, "Refracted rays:", std::to_string(s.refraction_rays));
    line(out, "Indirect paths:",
         std::to_string(s.indirect_paths) + "  (bounces " + std::to_string(s.indirect_bounces) + ", mean " +
             (s.indirect_paths ? fixed(double(s.indirect_bounces) / double(s.indirect_paths), 2)
                               : std::string("-")) +
             ")");
    line(out, "  their rays:", std::to_string(s.indirect_rays));
    line(out, "Emitter samples:", std::to_string(s.emitter_samples));
    line(out, "Ray queries (total):", std::to_string(s.ray_queries()));
    out << rule << '\n';
    char head[160];
    std::snprintf(head, sizeof head, "%-24s %16s %16s %12s\n", "Ray->Shape Intersection", "Tests",
                  "Succeeded", "Percentage");
    out << head << rule << '\n';
    row(out, "Sphere", s.sphere_tests, s.sphere_hits, true);
    row(out, "Triangle", s.triangle_tests, s.triangle_hits, true);
    row(out, "Box", s.shape_box_tests, 0, false);
    row(out, "Plane", s.plane_tests, 0, false);
    row(out, "Bounding box (BVH)", s.box_tests, 0, false);
    out << rule << '\n';
    line(out, "Fresnel evaluations:", std::to_string(s.fresnel_evals));
    line(out, "Texture lookups:", std::to_string(s.texture_evals));
    line(out, "Noise evaluations:", std::to_string(s.noise_evals));
    line(out, "Adaptive full-grid pixels:", std::to_string(s.adaptive_pixels));
    line(out, "Rejected rays (NaN/Inf):", std::to_string(s.rejected_rays));
    line(out, "Non-finite samples:", std::to_string(s.nonfinite_samples));
    line(out, "Caustic photons:",
         std::to_string(s.photons_shot) + " shot, " + std::to_string(s.photons_stored) + " stored");
    line(out, "Caustic lookups:",
         std::to_string(s.photon_lookups) + "  (" +
             (s.photon_lookups
                  ? fixed(static_cast<double>(s.photons_visited) / static_cast<double>(s.photon_lookups), 1)
                  : std::string("-")) +
             " photons visited each)");
    std::string effects;
    for (const std::string& e : r.effects) effects += (effects.empty() ? "" : ", ") + e;
    line(out, "Effects:", effects.empty() ? "-" : effects);
    out << rule << '\n';
    if (const render::ProgressiveReport& p = r.progressive; p.used) {
        line(out, "Progressive passes:",
             std::to_string(p.passes) + (p.deadline_reached ? "  (time limit reached)" : ""));
        line(out, "Estimated RMSE:",
             fixed_digits(p.estimated_rmse) + (r.target_error
                                                   ? "  (target " + fixed_digits(*r.target_error) +
                                                         (p.target_reached ? ", reached)" : ", not reached)")
                                                   : std::string()));
        line(out, "Samples per pixel:",
             "min " + std::to_string(p.samples_min) + ", median " + std::to_string(p.samples_median) +
                 ", max " + std::to_string(p.samples_max));
        out << rule << '\n';
    }
    line(out, "Parse time:", fixed(r.parse_seconds, 3) + " s");
    line(out, "Build time:", fixed(r.build_seconds, 3) + " s");
    if (s.photons_shot > 0) line(out, "  caustic photon map:", fixed(r.photon_seconds, 3) + " s");
    line(out, "Render time:",
         fixed(r.render_seconds, 3) + " s  (" +
             (r.threads > 0 ? counted(static_cast<uint64_t>(r.threads), "thread")
                            : std::string("all threads")) +
             ")");
    line(out, "Speed:", fixed(mrays_per_second(r), 3) + " Mrays/s");
    line(out,
         "Peak memory:", fixed(static_cast<double>(r.peak_memory_bytes) / (1024.0 * 1024.0), 1) + " MiB");
    out << rule << '\n';
    return out.str();
}

std::string stats_json(const RenderReport& r) {
    const render::RayStats& s = r.stats;
    // Seconds keep 9 significant digits (timings are not more precise); non-finite values are null.
    auto seconds = [](double v) {
        return std::isfinite(v) ? std::strtod(fixed_digits(v).c_str(), nullptr) : v;
    };
    nlohmann::ordered_json json = {
        {"scene", r.scene},
        {"frame", r.frame ? nlohmann::ordered_json(*r.frame) : nullptr},
        {"clock", r.clock},
        {"width", r.width},
        {"height", r.height},
        {"rendered_pixels", static_cast<uint64_t>(r.region_width) * static_cast<uint64_t>(r.region_height)},
        {"supersamples", r.supersamples},
        {"camera_rays", s.camera_rays},
        {"shadow_rays", s.shadow_rays},
        {"shaft_answered_rays", s.shaft_answered_rays},
        {"reflection_rays", s.reflection_rays},
        {"refraction_rays", s.refraction_rays},
        {"indirect_paths", s.indirect_paths},
        {"indirect_bounces", s.indirect_bounces},
        {"indirect_bounces_mean",
         s.indirect_paths ? double(s.indirect_bounces) / double(s.indirect_paths) : 0.0},
        {"indirect_rays", s.indirect_rays},
        {"emitter_samples", s.emitter_samples},
        {"ray_queries", s.ray_queries()},
        {"triangle_tests", s.triangle_tests},
        {"triangle_hits", s.triangle_hits},
        {"sphere_tests", s.sphere_tests},
        {"sphere_hits", s.sphere_hits},
        {"box_tests", s.box_tests},
        {"shape_box_tests", s.shape_box_tests},
        {"plane_tests", s.plane_tests},
        {"fresnel_evals", s.fresnel_evals},
        {"texture_evals", s.texture_evals},
        {"noise_evals", s.noise_evals},
        {"rejected_rays", s.rejected_rays},
        {"adaptive_pixels", s.adaptive_pixels},
        {"nonfinite_samples", s.nonfinite_samples},
        {"photons_shot", s.photons_shot},
        {"photons_stored", s.photons_stored},
        {"photon_lookups", s.photon_lookups},
        {"photons_visited", s.photons_visited},
        {"parse_seconds", seconds(r.parse_seconds)},
        {"build_seconds", seconds(r.build_seconds)},
        {"photon_map_seconds", seconds(r.photon_seconds)},
        {"render_seconds", seconds(r.render_seconds)},
        {"mrays_per_second", seconds(mrays_per_second(r))},
        {"peak_memory_bytes", r.peak_memory_bytes},
        {"effects", r.effects}};
    if (const render::ProgressiveReport& p = r.progressive; p.used) {
        json["estimated_rmse"] = p.estimated_rmse;
        json["passes"] = p.passes;
        json["samples_per_pixel"] = {
            {"min", p.samples_min}, {"median", p.samples_median}, {"max", p.samples_max}};
        json["samples_total"] = p.samples_total;
        json["target_error"] = r.target_error ? nlohmann::ordered_json(*r.target_error) : nullptr;
        json["target_reached"] = p.target_reached;
        json["time_limit"] = r.time_limit ? nlohmann::ordered_json(*r.time_limit) : nullptr;
        json["time_limit_reached"] = p.deadline_reached;
        json["first_pass_over_time_limit"] = p.first_pass_over;
    }
    // A scene path that is not UTF-8 is only a label: its bad bytes become U+FFFD.
    return json.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace wsd::app
