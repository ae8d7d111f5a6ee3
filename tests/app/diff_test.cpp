// `wsd diff` through the real binary, on 8-bit images written byte by byte (TGA) and on
// renders: identical images, a known constant offset, the heat map, and every failure status.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "app_test_util.h"

using namespace wsd::test;

namespace {

std::vector<uint8_t> gradient(int w, int h, int offset) {
    std::vector<uint8_t> rgb;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            rgb.push_back(static_cast<uint8_t>(20 + 10 * x + offset));
            rgb.push_back(static_cast<uint8_t>(30 + 12 * y + offset));
            rgb.push_back(static_cast<uint8_t>(100 + offset));
        }
    return rgb;
}

}  // namespace

TEST_CASE("diff of an image with itself: RMSE 0, PSNR inf, SSIM 1", "[diff]") {
    TempDir dir;
    write_tga(dir / "a.tga", 12, 10, gradient(12, 10, 0));
    const RunResult r = run_wsd(dir, "diff a.tga a.tga");
    CHECK(r.status == 0);
    CHECK(field(r.out, "RMSE") == "0");
    CHECK(field(r.out, "PSNR") == "inf");
    CHECK(field(r.out, "max abs error") == "0");
    CHECK(field(r.out, "SSIM") == "1");
}

TEST_CASE("diff tells 8-bit images by their content, not their file name", "[diff]") {
    // The same bytes under a name without an image extension are the same 8-bit image.
    TempDir dir;
    write_tga(dir / "a.tga", 12, 10, gradient(12, 10, 0));
    write_file(dir / "copy", read_file(dir / "a.tga"));
    write_file(dir / "copy.hdr", read_file(dir / "a.tga"));
    for (const char* other : {"copy", "copy.hdr"}) {
        INFO(other);
        const RunResult r = run_wsd(dir, std::string("diff a.tga ") + other);
        CHECK(r.status == 0);
        CHECK(field(r.out, "RMSE") == "0");
        CHECK(field(r.out, "PSNR") == "inf");
        CHECK(field(r.out, "max abs error") == "0");
    }
}

TEST_CASE("diff of a constant offset of 10 levels reports exactly 10/255", "[diff]") {
    TempDir dir;
    write_tga(dir / "a.tga", 12, 10, gradient(12, 10, 0));
    write_tga(dir / "b.tga", 12, 10, gradient(12, 10, 10));
    const RunResult r = run_wsd(dir, "diff a.tga b.tga -o heat.png");
    CHECK(r.status == 0);
    const double rmse = std::stod(field(r.out, "RMSE"));
    CHECK(rmse == Approx(10.0 / 255).epsilon(1e-5));
    CHECK(std::stod(field(r.out, "max abs error")) == Approx(10.0 / 255).epsilon(1e-5));
    CHECK(std::stod(field(r.out, "PSNR")) == Approx(10 * std::log10(255.0 * 255.0 / 100.0)).epsilon(1e-5));
    const double ssim = std::stod(field(r.out, "SSIM"));
    CHECK(ssim < 1.0);
    CHECK(ssim > 0.5);
    CHECK(read_file(dir / "heat.png").rfind("\x89PNG", 0) == 0);
}

TEST_CASE("diff compares renders in any format on display values", "[diff]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    REQUIRE(run_wsd(dir, "render s.wsd -o a.pfm --quiet").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -o a.png --quiet").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -o b.png --quiet --supersamples 1").status == 0);
    RunResult r = run_wsd(dir, "diff a.pfm a.png");
    CHECK(r.status == 0);
    // 8-bit rounding only: at most half a level per channel.
    CHECK(std::stod(field(r.out, "max abs error")) <= 0.5 / 255 + 1e-6);
    r = run_wsd(dir, "diff a.png b.png");
    CHECK(r.status == 0);
    CHECK(std::stod(field(r.out, "RMSE")) > 0);
    CHECK(std::stod(field(r.out, "SSIM")) < 1);
}

TEST_CASE("diff failures: sizes 1, malformed 1, missing or not a file 3, bad heat map name 2", "[diff]") {
    TempDir dir;
    write_tga(dir / "a.tga", 12, 10, gradient(12, 10, 0));
    write_tga(dir / "small.tga", 6, 10, gradient(6, 10, 0));
    write_file(dir / "junk.png", "this is not a png");
    RunResult r = run_wsd(dir, "diff a.tga small.tga -o heat.png");
    CHECK(r.status == 1);
    CHECK(r.err.find("12x10") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "heat.png"));
    CHECK(run_wsd(dir, "diff a.tga junk.png").status == 1);
    CHECK(run_wsd(dir, "diff a.tga nothing.png").status == 3);
    // A file that is not a regular one cannot be read as an image: 3, as for `check`.
    r = run_wsd(dir, "diff /dev/zero a.tga");
    CHECK(r.status == 3);
    CHECK(r.err.find("wsd: error: cannot read '/dev/zero': it is not a regular file") != std::string::npos);
    CHECK(run_wsd(dir, "diff a.tga a.tga -o heat.xyz").status == 2);
    CHECK(run_wsd(dir, "diff a.tga a.tga -o no/dir/heat.png").status == 3);
    // A heat map that would replace one of the compared images is refused, that image untouched.
    const std::string before = read_file(dir / "a.tga");
    write_tga(dir / "b.tga", 12, 10, gradient(12, 10, 5));
    r = run_wsd(dir, "diff b.tga a.tga -o ./a.tga");
    CHECK(r.status == 2);
    CHECK(r.err.find("-o './a.tga' names the compared image 'a.tga'") != std::string::npos);
    CHECK(read_file(dir / "a.tga") == before);
}

TEST_CASE("diff notes the values of an image that are not finite, and how it compares them", "[diff]") {
    TempDir dir;
    // A 2×1 PFM (little-endian): one pixel NaN, one black.
    std::string pfm = "PF\n2 1\n-1.0\n";
    const float values[6] = {std::nanf(""), std::nanf(""), std::nanf(""), 0, 0, 0};
    pfm.append(reinterpret_cast<const char*>(values), sizeof values);
    write_file(dir / "nan.pfm", pfm);
    const float zeros[6] = {};
    write_file(dir / "zero.pfm",
               "PF\n2 1\n-1.0\n" + std::string(reinterpret_cast<const char*>(zeros), sizeof zeros));
    const RunResult r = run_wsd(dir, "diff nan.pfm zero.pfm");
    CHECK(r.status == 0);
    CHECK(r.err.find("'nan.pfm' holds 3 values that are not finite: NaN and -inf are compared as black") !=
          std::string::npos);
    CHECK(r.err.find("zero.pfm") == std::string::npos);

    // One such value is said in the singular.
    const float one[6] = {0, std::numeric_limits<float>::infinity(), 0, 0, 0, 0};
    write_file(dir / "inf.pfm",
               "PF\n2 1\n-1.0\n" + std::string(reinterpret_cast<const char*>(one), sizeof one));
    const RunResult single = run_wsd(dir, "diff inf.pfm zero.pfm");
    CHECK(single.status == 0);
    CHECK(single.err.find("'inf.pfm' holds 1 value that is not finite:") != std::string::npos);
}
