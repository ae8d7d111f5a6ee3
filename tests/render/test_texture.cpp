// Textures: image decoding (sRGB curve, HDR), the bilinear lookup and its addressing at every
// awkward uv (robustness.md, safe texture lookup, R49; run under ASan in CI), the image cache and its errors,
// checker cells, Perlin colours and the bump normal (R33, R34).
#include <stb_image_write.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>

#include "render/image_io.h"
#include "render/noise.h"
#include "render/texture.h"

using namespace wsd::render;
namespace fs = std::filesystem;

namespace {

double srgb_formula(int v) {
    const double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// A directory of its own for each test binary run, removed when the binary exits.
struct TempDir {
    fs::path path = fs::temp_directory_path() / ("wsd_test_texture_" + std::to_string(getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

fs::path temp_dir() {
    static const TempDir dir;
    return dir.path;
}

// 4×4 pixels, quadrants of 2×2: top-left, top-right, bottom-left, bottom-right.
const unsigned char kQuad[4][3] = {{200, 30, 60}, {10, 220, 90}, {40, 70, 250}, {128, 128, 0}};

Color quad_color(int q) {
    return Color(srgb_formula(kQuad[q][0]), srgb_formula(kQuad[q][1]), srgb_formula(kQuad[q][2]));
}

std::string write_quadrant_png() {
    unsigned char pixels[4 * 4 * 3];
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 3; ++c) pixels[(y * 4 + x) * 3 + c] = kQuad[(y / 2) * 2 + x / 2][c];
    const std::string path = (temp_dir() / "quadrants.png").string();
    REQUIRE(stbi_write_png(path.c_str(), 4, 4, 3, pixels, 4 * 3) != 0);
    return path;
}

void check_color(const Color& got, const Color& want, double margin = 1e-6) {
    INFO("got " << got.r << " " << got.g << " " << got.b << ", want " << want.r << " " << want.g << " "
                << want.b);
    CHECK(got.r == Approx(want.r).margin(margin));
    CHECK(got.g == Approx(want.g).margin(margin));
    CHECK(got.b == Approx(want.b).margin(margin));
}

SurfaceHit hit_at(Vec3 p_object) {
    SurfaceHit s;
    s.p = s.p_object = p_object;
    s.ng = s.ns = Vec3(0, 0, 1);
    return s;
}

}  // namespace

TEST_CASE("8-bit values decode through the exact sRGB curve", "[texture]") {
    for (int v = 0; v < 256; ++v)
        REQUIRE(srgb8_to_linear(static_cast<uint8_t>(v)) == Approx(srgb_formula(v)).margin(1e-7));
    CHECK(srgb8_to_linear(0) == 0.0f);
    CHECK(srgb8_to_linear(255) == 1.0f);
    CHECK(srgb8_to_linear(10) == Approx(10 / 255.0 / 12.92));  // the linear segment
}

TEST_CASE("a PNG loads top row first, sRGB-decoded", "[texture]") {
    std::string error;
    auto image = load_image(write_quadrant_png(), error);
    REQUIRE(image);
    CHECK(error.empty());
    REQUIRE(image->width == 4);
    REQUIRE(image->height == 4);
    REQUIRE(image->rgb.size() == 48);
    check_color(Color(image->rgb[0], image->rgb[1], image->rgb[2]), quad_color(0));
    const size_t last = (3 * 4 + 3) * 3;
    check_color(Color(image->rgb[last], image->rgb[last + 1], image->rgb[last + 2]), quad_color(3));
}

TEST_CASE("an HDR image loads as linear floats", "[texture]") {
    // RGBE with a shared exponent stores these exactly: 2.5 = 0.625·2², 0.5 and 0.25 likewise.
    const float pixels[6] = {2.5f, 0.5f, 0.25f, 0.0f, 1.0f, 0.0f};
    const std::string path = (temp_dir() / "two.hdr").string();
    REQUIRE(stbi_write_hdr(path.c_str(), 2, 1, 3, pixels) != 0);
    std::string error;
    auto image = load_image(path, error);
    REQUIRE(image);
    REQUIRE(image->width == 2);
    REQUIRE(image->height == 1);
    for (int i = 0; i < 6; ++i) CHECK(image->rgb[static_cast<size_t>(i)] == Approx(pixels[i]).margin(1e-6));
}

TEST_CASE("bilinear lookup: centres, weights, wrap in u, clamp in v", "[texture]") {
    std::string error;
    auto image = load_image(write_quadrant_png(), error);
    REQUIRE(image);
    const Image& im = *image;
    // Quadrant centres fall between two texels of the same colour.
    check_color(sample_image(im, {0.25, 0.25}, false), quad_color(0));
    check_color(sample_image(im, {0.75, 0.25}, false), quad_color(1));
    check_color(sample_image(im, {0.25, 0.75}, false), quad_color(2));
    check_color(sample_image(im, {0.75, 0.75}, false), quad_color(3));
    // Texel centres are at (i + ½)/4: u = 3/8 is exactly texel 1 (top-left quadrant).
    check_color(sample_image(im, {0.375, 0.125}, false), quad_color(0));
    // Between texel 1 and 2 (x = 1.25): weights ¾ and ¼.
    check_color(sample_image(im, {0.4375, 0.125}, false), 0.75 * quad_color(0) + 0.25 * quad_color(1));
    // Between rows 1 and 2, columns 1 and 2: all four quadrants, equally.
    check_color(sample_image(im, {0.5, 0.5}, false),
                0.25 * (quad_color(0) + quad_color(1) + quad_color(2) + quad_color(3)));
    // u = 0 sits between the last column and the first: a 50/50 blend across the seam.
    const Color seam = 0.5 * (quad_color(0) + quad_color(1));
    check_color(sample_image(im, {0.0, 0.125}, false), seam);
    check_color(sample_image(im, {1.0, 0.125}, false), seam);
    check_color(sample_image(im, {-0.0, 0.125}, false), seam);
    check_color(sample_image(im, {2.375, 0.125}, false), quad_color(0));
    check_color(sample_image(im, {-0.625, 0.125}, false), quad_color(0));
    // v is clamped: above the top row is the top row; planes (wrap_v) blend with the bottom.
    check_color(sample_image(im, {0.125, -3.0}, false), quad_color(0));
    check_color(sample_image(im, {0.125, 0.0}, false), quad_color(0));
    check_color(sample_image(im, {0.125, 1.0}, false), quad_color(2));
    check_color(sample_image(im, {0.125, 0.0}, true), 0.5 * (quad_color(0) + quad_color(2)));
    check_color(sample_image(im, {0.125, 1.125}, true), quad_color(0));
}

TEST_CASE("R49: lookups at extreme uv stay inside the image", "[texture]") {
    std::string error;
    auto image = load_image(write_quadrant_png(), error);
    REQUIRE(image);
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double den = std::numeric_limits<double>::denorm_min();
    const double values[] = {0.0,
                             -0.0,
                             1.0,
                             std::nextafter(1.0, 0.0),
                             std::nextafter(1.0, 2.0),
                             -den,
                             den,
                             1e30,
                             -1e30,
                             1e300,
                             inf,
                             -inf,
                             nan,
                             0.5};
    for (bool wrap_v : {false, true})
        for (double u : values)
            for (double v : values) {
                const Color c = sample_image(*image, {u, v}, wrap_v);
                INFO(u << ", " << v);
                for (int k = 0; k < 3; ++k) {
                    REQUIRE(std::isfinite(c[k]));
                    REQUIRE(c[k] >= 0.0);
                    REQUIRE(c[k] <= 1.0);
                }
            }
    // NaN is a defined colour: that of coordinate 0.
    CHECK(sample_image(*image, {nan, nan}, false) == sample_image(*image, {0.0, 0.0}, false));
    // A 1×1 image is constant everywhere, seam included.
    Image one;
    one.width = one.height = 1;
    one.rgb = {0.1f, 0.2f, 0.3f};
    for (double u : values) check_color(sample_image(one, {u, 0.5}, true), Color(0.1f, 0.2f, 0.3f), 0);
    // An empty image gives black rather than reading anything.
    CHECK(sample_image(Image{}, {0.5, 0.5}, false) == Color(0.0));
}

TEST_CASE("a PFM image, as wsd writes it, loads as linear floats", "[texture]") {
    // 3×2, with values above 1 and one that no 8-bit format could hold.
    Film film;
    film.width = 3;
    film.height = 2;
    film.rgb = {0.0f,  0.25f,  1.0f, 7.5f,  0.001f, 0.5f, 1e-7f,   2.0f, 3.0f,
                0.75f, 0.125f, 4.0f, 0.25f, 0.125f, 0.5f, 0.0625f, 0.3f, 1.0f};
    const std::string path = (temp_dir() / "written.pfm").string();
    std::string error;
    REQUIRE(write_image(path, film, error));
    auto image = load_image(path, error);
    INFO(error);
    REQUIRE(image);
    REQUIRE(image->width == 3);
    REQUIRE(image->height == 2);
    CHECK(image->rgb == film.rgb);
    // The lookup at a texel's centre returns it exactly (top row first, like every image).
    const Color c = sample_image(*image, Vec2(1.5 / 3.0, 0.25), false);
    CHECK(c.r == Approx(7.5).margin(1e-6));
    CHECK(c.g == Approx(0.001).margin(1e-6));

    // NaN, infinities and negative values are not colours: the file is refused, at the pixel.
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::pair<float, std::string> bad[] = {
        {nan, "NaN"}, {inf, "+inf"}, {-inf, "-inf"}, {-1.0f, "negative"}};
    for (const auto& [value, word] : bad) {
        Film b = film;
        b.rgb[3 * 4 + 1] = value;  // pixel (1, 1), green
        REQUIRE(write_image(path, b, error));
        error.clear();
        CHECK_FALSE(load_image(path, error));
        CHECK(error == "image '" + path + "' holds a " + word +
                           " green value at pixel (1, 1); texture values must be finite and at least 0");
    }

    const std::string cut = (temp_dir() / "cut.pfm").string();
    std::ofstream(cut, std::ios::binary) << "PF\n3 2\n-1.0\n" << std::string(10, '\0');
    error.clear();
    CHECK_FALSE(load_image(cut, error));
    CHECK(error.find(cut) != std::string::npos);
    CHECK(error.find("malformed PFM") != std::string::npos);
}

TEST_CASE("a truncated GIF is corrupt, not too large", "[texture]") {
    const std::string path = (temp_dir() / "cut.gif").string();
    std::ofstream(path, std::ios::binary) << "GIF89a";
    std::string error;
    CHECK_FALSE(load_image(path, error));
    CHECK(error == "cannot decode image '" + path +
                       "': the file is corrupt or in an unsupported format (its header gives the size 0x0)");
}

TEST_CASE("image errors name the path; the cache loads a file once", "[texture]") {
    std::string error;
    const std::string missing = (temp_dir() / "no_such_texture.png").string();
    CHECK_FALSE(load_image(missing, error));
    CHECK(error.find(missing) != std::string::npos);
    CHECK(error.find("No such file") != std::string::npos);

    const std::string garbage = (temp_dir() / "garbage.jpg").string();
    std::ofstream(garbage) << "this is not an image at all";
    error.clear();
    CHECK_FALSE(load_image(garbage, error));
    CHECK(error.find(garbage) != std::string::npos);
    CHECK(error.find("cannot decode") != std::string::npos);

    error.clear();
    CHECK_FALSE(load_image(temp_dir().string(), error));
    CHECK(error.find("not a regular file") != std::string::npos);

    ImageCache cache;
    const std::string path = write_quadrant_png();
    auto a = cache.get(path, error);
    REQUIRE(a);
    fs::remove(path);  // a second load would now fail: the cache must not need the file
    auto b = cache.get(path, error);
    CHECK(a == b);

    TextureSpec spec;
    spec.kind = TextureKind::Image;
    spec.image_path = missing;
    error.clear();
    CHECK_FALSE(Texture::create(spec, cache, error));
    CHECK(error.find(missing) != std::string::npos);
}

TEST_CASE("an image texture counts its lookups and wraps v only on planes", "[texture]") {
    ImageCache cache;
    TextureSpec spec;
    spec.kind = TextureKind::Image;
    spec.image_path = write_quadrant_png();
    std::string error;
    auto tex = Texture::create(spec, cache, error);
    REQUIRE(tex);
    RayStats stats;
    SurfaceHit s = hit_at(Vec3(0));
    s.uv = Vec2(0.125, 0.0);
    check_color(tex->eval(s, stats), quad_color(0));
    s.planar = true;
    check_color(tex->eval(s, stats), 0.5 * (quad_color(0) + quad_color(2)));
    CHECK(stats.texture_evals == 2);
}

TEST_CASE("checker: solid cells of side `scale`, c1 where the parity is even", "[texture]") {
    ImageCache cache;
    TextureSpec spec;
    spec.kind = TextureKind::Checker;
    spec.checker_scale = 0.5;
    spec.color1 = Color(1, 0, 0);
    spec.color2 = Color(0, 0, 1);
    std::string error;
    auto tex = Texture::create(spec, cache, error);
    REQUIRE(tex);
    RayStats stats;
    const auto at = [&](Vec3 p) { return tex->eval(hit_at(p), stats); };
    CHECK(at({0.25, 0.25, 0.25}) == spec.color1);
    CHECK(at({0.75, 0.25, 0.25}) == spec.color2);
    CHECK(at({0.75, 0.75, 0.25}) == spec.color1);
    CHECK(at({0.75, 0.75, 0.75}) == spec.color2);
    CHECK(at({-0.25, 0.25, 0.25}) == spec.color2);  // floor, not truncation
    CHECK(at({-0.75, 0.25, 0.25}) == spec.color1);
    CHECK(at({1e12 + 0.25, 0.25, 0.25}) == spec.color1);
    CHECK(at({std::numeric_limits<double>::quiet_NaN(), 0.25, 0.25}) == spec.color1);
    // A box face on a cell boundary is one colour, whichever side the hit point rounds to.
    CHECK(at({std::nextafter(1.0, 0.0), 0.25, 0.25}) == at({std::nextafter(1.0, 2.0), 0.25, 0.25}));
    CHECK(at({std::nextafter(-1.0, 0.0), 0.25, 0.25}) == at({std::nextafter(-1.0, -2.0), 0.25, 0.25}));
    CHECK(stats.texture_evals == 12);

    // On a plane the 2-D plane coordinates decide, not the 3-D point.
    SurfaceHit s = hit_at({0.25, 0.25, 0.25});
    s.planar = true;
    s.plane_xy = Vec2(0.25, 0.75);
    CHECK(tex->eval(s, stats) == spec.color2);
    s.plane_xy = Vec2(-0.25, 0.75);
    CHECK(tex->eval(s, stats) == spec.color1);

    spec.checker_scale = 0.0;
    CHECK_FALSE(Texture::create(spec, cache, error));
    CHECK(error.find("checker scale") != std::string::npos);
}

TEST_CASE("a Perlin texture mixes coef·c1 + (1 − coef)·c2 at the object-frame point", "[texture]") {
    ImageCache cache;
    TextureSpec spec;
    spec.kind = TextureKind::Perlin;
    spec.perlin = PerlinKind::Marble;
    spec.perlin_scale = Vec3(0.5, 0.7, 0.9);
    spec.octaves = 4;
    spec.color1 = Color(1, 0.5, 0);
    spec.color2 = Color(0, 0.25, 1);
    std::string error;
    auto tex = Texture::create(spec, cache, error);
    REQUIRE(tex);
    RayStats stats;
    for (const Vec3& p : {Vec3(0.3, -1.2, 4.4), Vec3(-7.1, 2.2, 0.05)}) {
        SurfaceHit s = hit_at(p);
        s.p = p + Vec3(100.0);  // the world point must not matter
        uint64_t calls = 0;
        const double c = perlin_pattern(spec.perlin, spec.perlin_scale, spec.octaves, p, calls);
        check_color(tex->eval(s, stats), c * spec.color1 + (1 - c) * spec.color2, 1e-15);
        CHECK(tex->coef(p, stats) == c);
    }
    CHECK(stats.noise_evals == 4 * 4);
    CHECK(stats.texture_evals == 0);

    spec.octaves = -1;
    CHECK_FALSE(Texture::create(spec, cache, error));
}

namespace {

std::unique_ptr<Texture> bump_texture(double scale) {
    ImageCache cache;
    TextureSpec spec;
    spec.kind = TextureKind::Perlin;
    spec.perlin = PerlinKind::Noise;
    spec.perlin_scale = Vec3(scale);
    std::string error;
    return Texture::create(spec, cache, error);
}

void require_unit(const Vec3& n) {
    REQUIRE(std::isfinite(n.x));
    REQUIRE(std::isfinite(n.y));
    REQUIRE(std::isfinite(n.z));
    REQUIRE(glm::length(n) == Approx(1.0).margin(1e-6));
}

}  // namespace

TEST_CASE("bump: the spec's formula in the object frame", "[texture][bump]") {
    auto bump = bump_texture(3.0);
    REQUIRE(bump);
    RayStats stats;
    const Vec3 n = glm::normalize(Vec3(0.2, 0.3, 1.0));
    const Vec3 q(0.31, -0.42, 0.77);
    SurfaceHit s = hit_at(q);
    s.ns = n;
    const auto f = [&](Vec3 p) {
        uint64_t calls = 0;
        return 2 * perlin_pattern(PerlinKind::Noise, Vec3(3.0), 9, p, calls) - 1;
    };
    const Vec3 d(f(q), f(Vec3(q.y, q.z, q.x)), f(Vec3(q.z, q.x, q.y)));
    const Vec3 want = glm::normalize(n + 0.3 * d);
    const Vec3 got = bump_normal(*bump, 0.3, s, n, Mat4(1.0), stats);
    CHECK(glm::length(got - want) < 1e-12);
    CHECK(stats.noise_evals == 3);

    // A rotated object: the same object-frame point gives the rotated result.
    const Mat4 rot = glm::rotate(Mat4(1.0), 0.7, Vec3(1, 2, 3));
    const glm::dmat3 r(rot);
    const Vec3 rotated = bump_normal(*bump, 0.3, s, r * n, rot, stats);
    CHECK(glm::length(rotated - r * want) < 1e-12);
    // A uniform scale (and a translation) does not change how far the normal bends.
    const Mat4 scaled = glm::scale(glm::translate(Mat4(1.0), Vec3(5, 6, 7)), Vec3(100.0));
    CHECK(glm::length(bump_normal(*bump, 0.3, s, n, scaled, stats) - want) < 1e-12);
}

TEST_CASE("R33: bump: zero strength and constant height are identities", "[texture][bump]") {
    RayStats stats;
    const Vec3 n = glm::normalize(Vec3(0.1, -0.7, 0.4));
    SurfaceHit s = hit_at(Vec3(0.3, 0.6, 0.9));
    auto bump = bump_texture(2.0);
    CHECK(bump_normal(*bump, 0.0, s, n, Mat4(1.0), stats) == n);
    // Scale 0 evaluates N at the lattice origin: f = 2·½ − 1 = 0 everywhere.
    auto flat = bump_texture(0.0);
    CHECK(bump_normal(*flat, 5.0, s, n, Mat4(1.0), stats) == n);
    // A checker has no scalar pattern (coef ½): no bending either.
    ImageCache cache;
    TextureSpec checker;
    std::string error;
    auto tex = Texture::create(checker, cache, error);
    REQUIRE(tex);
    CHECK(bump_normal(*tex, 1.0, s, n, Mat4(1.0), stats) == n);
}

TEST_CASE("R34: bump: extreme strength, frequency and non-finite input stay unit and finite",
          "[texture][bump]") {
    RayStats stats;
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> coord(-5.0, 5.0);
    for (double freq : {1.0, 1e3, 1e9}) {
        auto bump = bump_texture(freq);
        for (double strength : {0.3, 1e6, 1e300, inf, nan, -1.0}) {
            for (int i = 0; i < 200; ++i) {
                SurfaceHit s = hit_at(Vec3(coord(rng), coord(rng), coord(rng)));
                require_unit(bump_normal(*bump, strength, s, s.ns, Mat4(1.0), stats));
            }
        }
        for (const Vec3& p : {Vec3(nan, 0, 0), Vec3(inf, inf, -inf), Vec3(1e300)}) {
            SurfaceHit s = hit_at(p);
            require_unit(bump_normal(*bump, 1e6, s, s.ns, Mat4(1.0), stats));
        }
        // A broken incoming normal or a singular transform still gives a unit vector.
        SurfaceHit s = hit_at(Vec3(0.3, 0.2, 0.1));
        require_unit(bump_normal(*bump, 0.5, s, Vec3(nan), Mat4(1.0), stats));
        require_unit(bump_normal(*bump, 0.5, s, Vec3(0.0), Mat4(0.0), stats));
        require_unit(bump_normal(*bump, 0.5, s, Vec3(0, 0, 1), Mat4(1.0), stats));
    }
}
