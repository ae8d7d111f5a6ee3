// Front-end throughput: generates a 1,000,000-triangle inline mesh scene (about 45 MB of text),
// a 100,000-sphere `for` loop scene and 100,000 spheres written out one by one, in memory; times
// lex+parse and the whole load_scene (build = false), and reports MB/s and the peak resident
// memory (per triangle for the mesh).
// Usage: bench_parse [triangles]   (prints measured numbers only)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "app/io_util.h"
#include "bench/memory_probe.h"
#include "lang/load.h"
#include "lang/parser.h"

namespace {

using Clock = std::chrono::steady_clock;
using wsd::lang::Diagnostics;
using wsd::lang::SourceManager;

void append_number(std::string& out, double v) {
    char buf[32];
    const int n = std::snprintf(buf, sizeof buf, "%.9g", v);
    out.append(buf, static_cast<size_t>(n));
}

// A wavy grid of (n+1)² shared vertices and 2n² triangles, one element per line.
std::string mesh_scene(size_t triangles) {
    const auto n = static_cast<size_t>(std::ceil(std::sqrt(static_cast<double>(triangles) / 2)));
    std::string s;
    s.reserve(triangles * 50);
    s += "settings { width 64  height 64 }\n"
         "camera { position <0, 40, -80>  look_at <0, 0, 0> }\n"
         "light point { position <0, 100, -100> }\n"
         "mesh {\n  vertices [\n";
    for (size_t j = 0; j <= n; ++j) {
        for (size_t i = 0; i <= n; ++i) {
            const double x = (static_cast<double>(i) - static_cast<double>(n) / 2) * 0.1371;
            const double z = (static_cast<double>(j) - static_cast<double>(n) / 2) * 0.1371;
            s += "    <";
            append_number(s, x);
            s += ", ";
            append_number(s, std::sin(x * 0.7) * std::cos(z * 0.3));
            s += ", ";
            append_number(s, z);
            s += ">,\n";
        }
    }
    s += "  ]\n  faces [\n";
    size_t written = 0;
    for (size_t j = 0; j < n && written < triangles; ++j) {
        for (size_t i = 0; i < n && written < triangles; ++i) {
            const size_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            s += "    <" + std::to_string(a) + ", " + std::to_string(b) + ", " + std::to_string(d) + ">,";
            ++written;
            if (written < triangles) {
                s += " <" + std::to_string(a) + ", " + std::to_string(d) + ", " + std::to_string(c) + ">,";
                ++written;
            }
            s += "\n";
        }
    }
    s += "  ]\n  material { color <0.8, 0.8, 0.8> }\n}\n";
    return s;
}

std::string sphere_loop_scene(size_t spheres) {
    return "settings { width 64  height 64 }\n"
           "camera { position <0, 0, -500>  look_at <0, 0, 0> }\n"
           "light point { position <0, 500, -500> }\n"
           "let n = " +
           std::to_string(spheres) +
           "\n"
           "let red = material { color <0.9, 0.2, 0.1>  specular 0.5 }\n"
           "for i in 0 .. n {\n"
           "    let a = i * 0.01\n"
           "    sphere { center <cos(a) * (100 + i % 97), sin(a) * 50, i % 13 * 10>  radius 0.5 + i % 7 * "
           "0.1\n"
           "             material red }\n"
           "}\n";
}

// `spheres` sphere statements written out one by one with computed values: a syntax tree of
// many small nodes (about 40 a statement), where the node representation shows.
std::string sphere_list_scene(size_t spheres) {
    std::string s =
        "settings { width 64  height 64 }\n"
        "camera { position <0, 0, -500>  look_at <0, 0, 0> }\n"
        "light point { position <0, 500, -500> }\n"
        "let red = material { color <0.9, 0.2, 0.1>  specular 0.5 }\n"
        "let k = 0.25\n";
    for (size_t i = 0; i < spheres; ++i) {
        const std::string n = std::to_string(i);
        s += "sphere { center <cos(" + n + " * 0.01) * (100 + " + n + " % 97), -sin(" + n +
             " * 0.01) * 50, " + n + " % 13 * 10 - k>  radius 0.5 + " + n +
             " % 7 * 0.1  material red  translate <k, 0, 0> }\n";
    }
    return s;
}

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Lex + parse only; returns false on errors.
bool bench_parse(const char* name, std::string text, size_t triangles) {
    const double mb = static_cast<double>(text.size()) / 1e6;
    wsd::bench::reset_peak_memory();
    const long long base = wsd::bench::resident_bytes() - static_cast<long long>(text.size());
    SourceManager sources;
    Diagnostics diags;
    const auto t0 = Clock::now();
    const uint32_t file = sources.add(name, std::move(text));
    const wsd::lang::Program program = wsd::lang::parse(file, sources, diags);
    const double secs = seconds_since(t0);
    const auto peak = static_cast<long long>(wsd::app::peak_memory_bytes());
    if (diags.has_errors()) {
        std::fputs(wsd::lang::format_diagnostics(diags, sources).c_str(), stderr);
        return false;
    }
    std::printf("%-14s lex+parse   %8.1f MB  %8.3f s  %8.1f MB/s", name, mb, secs, mb / secs);
    if (triangles > 0 && peak > 0)
        std::printf("  peak %6.1f bytes/triangle (source text included)",
                    static_cast<double>(peak - base) / static_cast<double>(triangles));
    else if (peak > 0)
        std::printf("  peak %.1f MB (source text included)", static_cast<double>(peak - base) / 1e6);
    std::printf("\n");
    return true;
}

bool bench_load(const char* name, std::string text, size_t triangles) {
    const double mb = static_cast<double>(text.size()) / 1e6;
    wsd::bench::reset_peak_memory();
    const long long base = wsd::bench::resident_bytes() - static_cast<long long>(text.size());
    SourceManager sources;
    Diagnostics diags;
    wsd::lang::LoadOptions options;
    options.build = false;
    const auto t0 = Clock::now();
    const auto loaded = wsd::lang::load_scene(name, std::move(text), sources, diags, options);
    const double secs = seconds_since(t0);
    const auto peak = static_cast<long long>(wsd::app::peak_memory_bytes());
    if (!loaded || diags.has_errors()) {
        std::fputs(wsd::lang::format_diagnostics(diags, sources).c_str(), stderr);
        return false;
    }
    std::printf("%-14s load_scene  %8.1f MB  %8.3f s  %8.1f MB/s  %zu objects (%.0f/s), %zu triangles", name,
                mb, secs, mb / secs, loaded->summary.objects,
                static_cast<double>(loaded->summary.objects) / secs, loaded->summary.triangles);
    if (triangles > 0 && peak > 0)
        std::printf("  peak %6.1f bytes/triangle",
                    static_cast<double>(peak - base) / static_cast<double>(triangles));
    std::printf("\n");
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    const size_t triangles = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1'000'000;
    const size_t spheres = 100'000;
    bool ok = bench_parse("mesh.wsd", mesh_scene(triangles), triangles);
    ok = bench_load("mesh.wsd", mesh_scene(triangles), triangles) && ok;
    ok = bench_parse("spheres.wsd", sphere_loop_scene(spheres), 0) && ok;
    ok = bench_load("spheres.wsd", sphere_loop_scene(spheres), 0) && ok;
    ok = bench_parse("list.wsd", sphere_list_scene(spheres), 0) && ok;
    ok = bench_load("list.wsd", sphere_list_scene(spheres), 0) && ok;
    return ok ? 0 : 1;
}
