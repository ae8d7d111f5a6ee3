// Generates the assets the examples use (no third-party images or models): an earth-like planet
// and a moon in the spherical UV layout, a dice in the unfolded-cube cross layout, marble floor
// tiles (from the project's own Perlin noise), and a torus OBJ with normals and UVs.
// Usage: make_assets EXAMPLES_DIR (writes EXAMPLES_DIR/textures/*.png and models/torus.obj).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "render/image_io.h"
#include "render/texture.h"

namespace {

using wsd::render::Color;
using wsd::render::Film;
using wsd::render::Vec3;

constexpr double pi = 3.14159265358979323846;

double fbm(Vec3 p, int octaves) {
    double sum = 0, amp = 0.5;
    for (int i = 0; i < octaves; ++i, p *= 2.0, amp *= 0.5)
        sum += amp * wsd::render::perlin_noise(p.x, p.y, p.z);
    return sum;
}

// The unit normal that the language's sphere mapping sends to (u, v).
Vec3 sphere_dir(double u, double v) {
    double lat = (0.5 - v) * pi, lon = (u - 0.5) * 2 * pi;
    return {std::cos(lat) * std::sin(lon), std::sin(lat), -std::cos(lat) * std::cos(lon)};
}

Color mix(const Color& a, const Color& b, double t) {
    return a + (b - a) * std::clamp(t, 0.0, 1.0);
}

void set(Film& f, int x, int y, const Color& c) {
    float* px = &f.rgb[3 * (size_t(y) * size_t(f.width) + size_t(x))];
    px[0] = float(c.r), px[1] = float(c.g), px[2] = float(c.b);
}

Film make(int w, int h) {
    return Film{w, h, std::vector<float>(size_t(w) * size_t(h) * 3)};
}

Film earth() {
    Film f = make(512, 256);
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            Vec3 n = sphere_dir((x + 0.5) / f.width, (y + 0.5) / f.height);
            double land = fbm(n * 1.8 + Vec3(3.1, 0.7, 5.2), 6);
            double lat = std::abs(n.y);
            Color c = land > 0.05 ? mix(Color(0.05, 0.25, 0.04), Color(0.35, 0.28, 0.12), (land - 0.05) * 4)
                                  : mix(Color(0.01, 0.04, 0.25), Color(0.02, 0.10, 0.40), land + 0.5);
            if (lat > 0.85 + 0.05 * fbm(n * 6.0, 3)) c = Color(0.9, 0.92, 0.95);
            double cloud = fbm(n * 4.0 + Vec3(9, 1, 4), 5);
            set(f, x, y, mix(c, Color(1, 1, 1), (cloud - 0.15) * 2.5));
        }
    return f;
}

Film moon() {
    Film f = make(512, 256);
    const Vec3 craters[] = {{0.3, 0.4, -0.86}, {-0.5, 0.1, -0.86}, {0.1, -0.6, -0.79},
                            {0.7, -0.2, 0.68}, {-0.2, 0.8, 0.56},  {-0.6, -0.5, 0.62}};
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            Vec3 n = sphere_dir((x + 0.5) / f.width, (y + 0.5) / f.height);
            double g = 0.45 + 0.25 * fbm(n * 3.0, 6);
            for (const Vec3& c : craters) {
                double d = glm::length(n - glm::normalize(c));
                if (d < 0.25) g *= 0.75 + 0.25 * (d / 0.25);
                if (std::abs(d - 0.25) < 0.015) g *= 1.3;
            }
            set(f, x, y, Color(g, g, g * 0.97));
        }
    return f;
}

// Cross layout: middle row −x, −z, +x, +z; +y above −z, −y below it. Opposite faces sum to 7.
Film dice() {
    const int s = 128;
    Film f = make(4 * s, 3 * s);
    struct Face {
        int col, row, pips;
    };
    const Face faces[] = {{0, 1, 2}, {1, 1, 1}, {2, 1, 5}, {3, 1, 6}, {1, 0, 3}, {1, 2, 4}};
    const double spots[7][6][2] = {{},
                                   {{.5, .5}},
                                   {{.25, .25}, {.75, .75}},
                                   {{.25, .25}, {.5, .5}, {.75, .75}},
                                   {{.25, .25}, {.75, .25}, {.25, .75}, {.75, .75}},
                                   {{.25, .25}, {.75, .25}, {.5, .5}, {.25, .75}, {.75, .75}},
                                   {{.25, .25}, {.75, .25}, {.25, .5}, {.75, .5}, {.25, .75}, {.75, .75}}};
    const Color rainbow[6] = {{0.8, 0.1, 0.1},  {0.9, 0.5, 0.05}, {0.85, 0.8, 0.1},
                              {0.1, 0.6, 0.15}, {0.1, 0.25, 0.8}, {0.45, 0.1, 0.6}};
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) set(f, x, y, Color(0.05));
    for (int i = 0; i < 6; ++i) {
        const Face& fc = faces[i];
        for (int y = 0; y < s; ++y)
            for (int x = 0; x < s; ++x) {
                double u = (x + 0.5) / s, v = (y + 0.5) / s;
                Color c = mix(Color(0.95), rainbow[i], 0.35);
                if (u < 0.04 || v < 0.04 || u > 0.96 || v > 0.96) c = rainbow[i];
                for (int k = 0; k < fc.pips; ++k) {
                    double du = u - spots[fc.pips][k][0], dv = v - spots[fc.pips][k][1];
                    if (du * du + dv * dv < 0.09 * 0.09) c = Color(0.03);
                }
                set(f, fc.col * s + x, fc.row * s + y, c);
            }
    }
    return f;
}

Film marble_tiles() {
    Film f = make(512, 512);
    const int tiles = 8;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            int tx = x * tiles / f.width, ty = y * tiles / f.height;
            bool cream = (tx + ty) % 2 == 0;
            Vec3 p(x / 64.0, y / 64.0, cream ? 0.3 : 7.7);
            double t = 0;
            for (int l = 1; l <= 6; ++l)
                t += std::abs(wsd::render::perlin_noise(l * p.x, l * p.y, l * p.z)) / l;
            double vein = 0.5 + 0.5 * std::sin(3 * p.x + 2 * p.y + 6 * t);
            Color base = cream ? Color(0.85, 0.78, 0.6) : Color(0.08, 0.3, 0.15);
            Color dark = cream ? Color(0.55, 0.48, 0.35) : Color(0.02, 0.12, 0.05);
            Color c = mix(dark, base, std::pow(vein, 0.4));
            int gx = x % (f.width / tiles), gy = y % (f.height / tiles);
            if (gx == 0 || gy == 0) c = Color(0.2, 0.2, 0.18);
            set(f, x, y, c);
        }
    return f;
}

// A torus (major radius R, minor r) in the xz-plane, with per-vertex normals and UVs; the seam
// vertices are duplicated so the UVs wrap cleanly.
bool write_torus(const std::string& path, double R, double r, int nu, int nv) {
    FILE* f = std::fopen(path.c_str(), "w");
    if (!f) return false;
    std::fprintf(f, "# torus R=%g r=%g, %d x %d quads, written by tools/make_assets.cpp\no torus\n", R, r, nu,
                 nv);
    for (int i = 0; i <= nu; ++i)
        for (int j = 0; j <= nv; ++j) {
            double a = 2 * pi * i / nu, b = 2 * pi * j / nv;
            Vec3 n(std::cos(b) * std::cos(a), std::sin(b), std::cos(b) * std::sin(a));
            Vec3 p = Vec3(R * std::cos(a), 0, R * std::sin(a)) + r * n;
            std::fprintf(f, "v %.6f %.6f %.6f\nvn %.6f %.6f %.6f\nvt %.6f %.6f\n", p.x, p.y, p.z, n.x, n.y,
                         n.z, double(i) / nu * 3, double(j) / nv);
        }
    auto id = [&](int i, int j) { return i * (nv + 1) + j + 1; };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            std::fprintf(f, "f %d/%d/%d %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, d, d, d, c, c, c, b, b, b);
        }
    return std::fclose(f) == 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_assets EXAMPLES_DIR\n");
        return 2;
    }
    const std::string dir = argv[1];
    std::error_code ec;
    std::filesystem::create_directories(dir + "/textures", ec);
    std::filesystem::create_directories(dir + "/models", ec);
    const std::pair<const char*, Film> outputs[] = {{"earth.png", earth()},
                                                    {"moon.png", moon()},
                                                    {"dice.png", dice()},
                                                    {"marble-tiles.png", marble_tiles()}};
    for (const auto& [name, film] : outputs) {
        std::string error;
        if (!wsd::render::write_image(dir + "/textures/" + name, film, error)) {
            std::fprintf(stderr, "make_assets: %s\n", error.c_str());
            return 3;
        }
        std::printf("wrote %s/textures/%s (%dx%d)\n", dir.c_str(), name, film.width, film.height);
    }
    if (!write_torus(dir + "/models/torus.obj", 1.0, 0.35, 64, 32)) {
        std::fprintf(stderr, "make_assets: cannot write %s/models/torus.obj\n", dir.c_str());
        return 3;
    }
    std::printf("wrote %s/models/torus.obj\n", dir.c_str());
    return 0;
}
