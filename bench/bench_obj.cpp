// Mesh file loading speed: writes 1,000,000-triangle grids to /tmp — OBJ with plain `f a b c`,
// OBJ with `f a/a/a` corners with vt and vn (which exercises the unwelding map), ASCII PLY and
// binary PLY — then times load_mesh_file on each, median of 3 runs. Prints only what it measured.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "render/mesh_file.h"

namespace {

constexpr int kColumns = 1000, kRows = 500;  // 1000 × 500 quads = 1,000,000 triangles

std::string write_grid(const std::string& path, bool with_vt_vn) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return {};
    for (int r = 0; r <= kRows; ++r)
        for (int c = 0; c <= kColumns; ++c)
            std::fprintf(f, "v %.6f %.6f %.6f\n", c * 0.01, r * 0.01, 0.001 * ((c * 7 + r * 13) % 17));
    if (with_vt_vn) {
        for (int r = 0; r <= kRows; ++r)
            for (int c = 0; c <= kColumns; ++c)
                std::fprintf(f, "vt %.6f %.6f\n", c / double(kColumns), r / double(kRows));
        for (int r = 0; r <= kRows; ++r)
            for (int c = 0; c <= kColumns; ++c) std::fprintf(f, "vn 0 0 1\n");
    }
    const auto index = [](int r, int c) { return r * (kColumns + 1) + c + 1; };
    for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kColumns; ++c) {
            const int a = index(r, c), b = index(r, c + 1), d = index(r + 1, c), e = index(r + 1, c + 1);
            if (with_vt_vn)
                std::fprintf(f, "f %d/%d/%d %d/%d/%d %d/%d/%d\nf %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, b, b,
                             b, e, e, e, a, a, a, e, e, e, d, d, d);
            else
                std::fprintf(f, "f %d %d %d\nf %d %d %d\n", a, b, e, a, e, d);
        }
    std::fclose(f);
    return path;
}

// The same grid as PLY: float positions, uchar-counted int index lists.
std::string write_grid_ply(const std::string& path, bool binary) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return {};
    std::fprintf(
        f,
        "ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
        "element face %d\nproperty list uchar int vertex_indices\nend_header\n",
        binary ? "binary_little_endian" : "ascii", (kRows + 1) * (kColumns + 1), 2 * kRows * kColumns);
    for (int r = 0; r <= kRows; ++r)
        for (int c = 0; c <= kColumns; ++c) {
            const float v[3] = {static_cast<float>(c * 0.01), static_cast<float>(r * 0.01),
                                static_cast<float>(0.001 * ((c * 7 + r * 13) % 17))};
            if (binary)
                std::fwrite(v, sizeof v, 1, f);
            else
                std::fprintf(f, "%.6f %.6f %.6f\n", c * 0.01, r * 0.01, 0.001 * ((c * 7 + r * 13) % 17));
        }
    const auto index = [](int r, int c) { return r * (kColumns + 1) + c; };
    for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kColumns; ++c) {
            const int a = index(r, c), b = index(r, c + 1), d = index(r + 1, c), e = index(r + 1, c + 1);
            if (binary) {
                const unsigned char three = 3;
                const int t0[3] = {a, b, e}, t1[3] = {a, e, d};
                std::fwrite(&three, 1, 1, f);
                std::fwrite(t0, sizeof t0, 1, f);
                std::fwrite(&three, 1, 1, f);
                std::fwrite(t1, sizeof t1, 1, f);
            } else {
                std::fprintf(f, "3 %d %d %d\n3 %d %d %d\n", a, b, e, a, e, d);
            }
        }
    std::fclose(f);
    return path;
}

int run(const char* label, const std::string& path) {
    if (path.empty()) {
        std::fprintf(stderr, "bench_obj: cannot write the test file\n");
        return 1;
    }
    std::vector<double> seconds, cpu_seconds;
    size_t triangles = 0, vertices = 0;
    for (int i = 0; i < 3; ++i) {
        const std::clock_t c0 = std::clock();
        const auto t0 = std::chrono::steady_clock::now();
        const wsd::render::MeshFileResult r = wsd::render::load_mesh_file(path);
        const auto t1 = std::chrono::steady_clock::now();
        cpu_seconds.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
        if (!r.mesh) {
            std::fprintf(stderr, "bench_obj: %s\n", r.error.c_str());
            return 1;
        }
        triangles = r.mesh->faces.size();
        vertices = r.mesh->vertices.size();
        seconds.push_back(std::chrono::duration<double>(t1 - t0).count());
    }
    std::sort(seconds.begin(), seconds.end());
    std::sort(cpu_seconds.begin(), cpu_seconds.end());
    const double mb = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
    // CPU time alongside wall time: on a shared machine the wall time includes waiting.
    std::printf(
        "%-10s %8zu triangles %8zu vertices %6.1f MB  load median %.3f s wall (min %.3f, max %.3f), "
        "%.3f s CPU\n",
        label, triangles, vertices, mb, seconds[1], seconds[0], seconds[2], cpu_seconds[1]);
    return 0;
}

}  // namespace

int main() {
    const std::string plain = write_grid("/tmp/wsd_bench_obj_plain.obj", false);
    const std::string full = write_grid("/tmp/wsd_bench_obj_vt_vn.obj", true);
    const std::string ascii = write_grid_ply("/tmp/wsd_bench_ply_ascii.ply", false);
    const std::string binary = write_grid_ply("/tmp/wsd_bench_ply_binary.ply", true);
    int rc = run("f v", plain);
    rc |= run("f v/vt/vn", full);
    rc |= run("ply ascii", ascii);
    rc |= run("ply binary", binary);
    for (const std::string& p : {plain, full, ascii, binary}) std::filesystem::remove(p);
    return rc;
}
