// Unit tests of the library-like parts of app/: image metrics (RMSE, PSNR, SSIM, heat map), the
// tile file format, and the SVG plot writer with its Pareto front.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "app/image_metrics.h"
#include "app/svg_plot.h"
#include "app/tile_file.h"
#include "render/image_io.h"

using namespace wsd::app;

namespace {

DisplayImage pattern(int w, int h, double offset = 0) {
    DisplayImage img;
    img.width = w;
    img.height = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                img.rgb.push_back(0.1 + 0.6 * ((x * 7 + y * 13 + c * 5) % 17) / 17.0 + offset);
    return img;
}

// Counts `<name` opening tags (not `</name`).
size_t count_tags(const std::string& xml, const std::string& name) {
    size_t n = 0;
    for (size_t at = xml.find("<" + name); at != std::string::npos; at = xml.find("<" + name, at + 1)) {
        const char next = xml[at + 1 + name.size()];
        if (next == ' ' || next == '>' || next == '/') ++n;
    }
    return n;
}

}  // namespace

TEST_CASE("identical images: zero error, infinite PSNR, SSIM exactly 1", "[metrics]") {
    const DisplayImage a = pattern(20, 13);
    const ImageMetrics m = compare(a, a);
    CHECK(m.rmse == 0);
    CHECK(m.max_abs_error == 0);
    CHECK(std::isinf(m.psnr));
    CHECK(m.ssim == 1.0);
}

TEST_CASE("a constant offset gives that offset as RMSE and max error", "[metrics]") {
    const DisplayImage a = pattern(9, 7), b = pattern(9, 7, 0.05);
    const ImageMetrics m = compare(a, b);
    CHECK(m.rmse == Approx(0.05).epsilon(1e-12));
    CHECK(m.max_abs_error == Approx(0.05).epsilon(1e-12));
    CHECK(m.psnr == Approx(10 * std::log10(1 / (0.05 * 0.05))).epsilon(1e-12));
    // A brightness shift leaves structure alone: SSIM drops, but only a little, and stays symmetric.
    CHECK(m.ssim < 1.0);
    CHECK(m.ssim > 0.9);
    CHECK(ssim(a, b) == Approx(ssim(b, a)).epsilon(1e-12));
}

TEST_CASE("SSIM falls for structural damage and works below the window size", "[metrics]") {
    const DisplayImage a = pattern(32, 32);
    DisplayImage noisy = a;
    for (size_t i = 0; i < noisy.rgb.size(); ++i)
        noisy.rgb[i] = static_cast<double>(i * 2654435761u % 1000) / 1000.0;
    CHECK(ssim(a, noisy) < 0.5);
    const DisplayImage small = pattern(3, 2);
    CHECK(ssim(small, small) == 1.0);
    CHECK(compare(small, pattern(3, 2, 0.1)).rmse == Approx(0.1));
}

TEST_CASE("to_display clamps, encodes, and quantizes 8-bit values", "[metrics]") {
    wsd::render::Film film;
    film.width = 2;
    film.height = 1;
    film.rgb = {-1.0f, 0.0f, 2.0f, 1.0f, std::nanf(""), 0.5f};
    const DisplayImage d = to_display(film, true);
    CHECK(d.rgb[0] == 0.0);
    CHECK(d.rgb[2] == 1.0);
    CHECK(d.rgb[4] == 0.0);
    const double q = d.rgb[5] * 255;
    CHECK(q == Approx(std::round(q)).margin(1e-9));
    CHECK(d.rgb[5] > 0.7);  // sRGB encoding brightens mid-tones
}

TEST_CASE("the heat map is black where equal and white at the largest error", "[metrics]") {
    DisplayImage a = pattern(4, 4), b = a;
    b.rgb[3 * 5 + 1] += 0.2;  // pixel 5
    b.rgb[3 * 9] += 0.1;      // pixel 9
    double scale = 0;
    const DisplayImage heat = error_heatmap(a, b, scale);
    CHECK(scale == Approx(0.2));
    CHECK(heat.rgb[0] == 0.0);
    CHECK(heat.rgb[3 * 5] == 1.0);
    CHECK(heat.rgb[3 * 5 + 2] == 1.0);
    CHECK(heat.rgb[3 * 9] > 0.0);
    CHECK(heat.rgb[3 * 9 + 2] < 1.0);
}

TEST_CASE("PSNR follows 10 log10(1/MSE)", "[metrics]") {
    CHECK(std::isinf(psnr_from_mse(0)));
    CHECK(psnr_from_mse(0.01) == Approx(20.0));
    CHECK(psnr_from_mse(1e-4) == Approx(40.0));
}

TEST_CASE("a tile file round-trips its pixels and metadata", "[tiles]") {
    wsd::render::Film film;
    film.width = 3;
    film.height = 2;
    for (int i = 0; i < 18; ++i) film.rgb.push_back(0.1f * static_cast<float>(i) - 0.3f);
    TileMeta meta;
    meta.full_width = 3;
    meta.full_height = 7;
    meta.region = {0, 2, 3, 4};
    meta.scene_hash = "0123456789abcdef";
    meta.settings_hash = "fedcba9876543210";
    meta.seed = 4294967295u;
    meta.tile_index = 2;
    meta.tile_count = 3;
    meta.scene = "dir/a \"quoted\" scene.wsd";
    const std::string bytes = encode_tile(film, {}, meta);
    REQUIRE(bytes.rfind("PF\n3 2\n-1.0\n", 0) == 0);
    // The pixels are the PFM file `wsd render -o x.pfm` writes, and the trailer keeps its keys.
    CHECK(bytes.rfind(wsd::render::encode_pfm(film), 0) == 0);
    CHECK(bytes.substr(bytes.find("\nWSDTILE ")) ==
          "\nWSDTILE {\"format\":1,\"width\":3,\"height\":7,\"region\":[0,2,3,4],\"tile\":[2,3],"
          "\"seed\":4294967295,\"scene_hash\":\"0123456789abcdef\",\"settings_hash\":\"fedcba9876543210\","
          "\"scene\":\"dir/a \\\"quoted\\\" scene.wsd\"}\n");

    wsd::render::Film back;
    wsd::render::AovFilm aovs_back;
    TileMeta meta_back;
    std::string error;
    REQUIRE(decode_tile(bytes, back, aovs_back, meta_back, error));
    CHECK(back.width == 3);
    CHECK(back.height == 2);
    CHECK(back.rgb == film.rgb);
    CHECK(meta_back.full_height == 7);
    CHECK(meta_back.region.y0 == 2);
    CHECK(meta_back.region.y1 == 4);
    CHECK(meta_back.seed == 4294967295u);
    CHECK(meta_back.scene_hash == meta.scene_hash);
    CHECK(meta_back.settings_hash == meta.settings_hash);
    CHECK(meta_back.tile_index == 2);
    CHECK(meta_back.scene == meta.scene);
}

TEST_CASE("a scene path that is not UTF-8 still gives a readable tile", "[tiles]") {
    wsd::render::Film film;
    film.width = film.height = 1;
    film.rgb.assign(3, 1.0f);
    TileMeta meta;
    meta.full_width = meta.full_height = 1;
    meta.region = {0, 0, 1, 1};
    meta.scene = "caf\xe9.wsd";  // Latin-1
    wsd::render::Film back;
    wsd::render::AovFilm aovs_back;
    TileMeta meta_back;
    std::string error;
    REQUIRE(decode_tile(encode_tile(film, {}, meta), back, aovs_back, meta_back, error));
    CHECK(meta_back.scene == "caf\xEF\xBF\xBD.wsd");  // the bad byte becomes U+FFFD
}

TEST_CASE("malformed tile files are refused with a reason", "[tiles]") {
    wsd::render::Film film;
    film.width = 2;
    film.height = 2;
    film.rgb.assign(12, 0.5f);
    TileMeta meta;
    meta.full_width = 2;
    meta.full_height = 4;
    meta.region = {0, 0, 2, 2};
    meta.scene_hash = meta.settings_hash = "0";
    const std::string good = encode_tile(film, {}, meta);
    wsd::render::Film f;
    wsd::render::AovFilm a;
    TileMeta m;
    std::string error;
    CHECK_FALSE(decode_tile("", f, a, m, error));
    CHECK_FALSE(decode_tile("P6\n2 2\n255\n", f, a, m, error));
    CHECK_FALSE(decode_tile(good.substr(0, 20), f, a, m, error));  // truncated floats
    CHECK(error.find("truncated") != std::string::npos);
    CHECK_FALSE(decode_tile(good.substr(0, good.find("\nWSDTILE")), f, a, m, error));  // a plain PFM
    CHECK(error.find("WSDTILE") != std::string::npos);
    std::string bad_json = good;
    bad_json.replace(bad_json.find("\"region\""), 8, "\"regio\"");
    CHECK_FALSE(decode_tile(bad_json, f, a, m, error));
    CHECK(error.find("'region'") != std::string::npos);                         // says which field is wrong
    CHECK_FALSE(decode_tile(good.substr(0, good.size() - 5), f, a, m, error));  // JSON cut short
    CHECK(error.find("malformed WSDTILE metadata") != std::string::npos);
    std::string bad_seed = good;
    bad_seed.replace(bad_seed.find("\"seed\":0"), 8, "\"seed\":-1");
    CHECK_FALSE(decode_tile(bad_seed, f, a, m, error));
    CHECK(error.find("'seed'") != std::string::npos);
    TileMeta outside = meta;
    outside.region = {0, 3, 2, 5};  // beyond the 4 rows of the image
    CHECK_FALSE(decode_tile(encode_tile(film, {}, outside), f, a, m, error));
    TileMeta wrong_size = meta;
    wrong_size.region = {0, 0, 2, 3};  // 3 rows claimed, 2 stored
    CHECK_FALSE(decode_tile(encode_tile(film, {}, wrong_size), f, a, m, error));
}

TEST_CASE("the Pareto front keeps exactly the undominated points", "[svg]") {
    std::vector<PlotSeries> series{{"a", {{1, 10, ""}, {2, 5, ""}, {4, 1, ""}}},
                                   {"b", {{1.5, 20, ""}, {3, 2, ""}, {5, 0.5, ""}}}};
    const auto front = pareto_front(series);
    std::vector<std::pair<size_t, size_t>> expected{{0, 0}, {0, 1}, {1, 1}, {0, 2}, {1, 2}};
    CHECK(front == expected);
}

TEST_CASE("the SVG plot is balanced XML with one path per series", "[svg]") {
    std::vector<PlotSeries> series{
        {"super<samples>", {{0.01, 0.1, "1"}, {0.04, 0.05, "4"}, {0.16, 0.0, "16"}}},
        {"depth & more", {{0.02, 0.2, "0"}, {0.03, 0.08, "1"}}},
        {"third", {{0.5, 0.01, "x"}}}};
    const std::string svg = svg_log_log_plot(series, {"t \"title\"", "time", "error"});
    CHECK(count_tags(svg, "path") == 3);
    CHECK(count_tags(svg, "polyline") == 1);
    CHECK(svg.find("super&lt;samples&gt;") != std::string::npos);
    CHECK(svg.find("depth &amp; more") != std::string::npos);
    CHECK(svg.find("nan") == std::string::npos);
    CHECK(svg.find("inf") == std::string::npos);
    // Every element either closes itself or is closed, in order.
    std::vector<std::string> stack;
    size_t pos = 0;
    while ((pos = svg.find('<', pos)) != std::string::npos) {
        const size_t end = svg.find('>', pos);
        REQUIRE(end != std::string::npos);
        const std::string tag = svg.substr(pos + 1, end - pos - 1);
        pos = end + 1;
        if (tag[0] == '?' || tag[0] == '!') continue;
        if (tag[0] == '/') {
            REQUIRE_FALSE(stack.empty());
            CHECK(stack.back() == tag.substr(1));
            stack.pop_back();
        } else if (tag.back() != '/') {
            stack.push_back(tag.substr(0, tag.find(' ')));
        }
    }
    CHECK(stack.empty());
}
