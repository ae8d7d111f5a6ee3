// `wsd render --target-error` and `--time-limit` through the real binary: the limits of both
// options as usage errors, the statistics and the samples map, tiles that merge into exactly the
// whole targeted render, and a time limit shorter than the first pass.
#include <algorithm>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "app_test_util.h"
#include "render/image_io.h"

using namespace wsd::test;

namespace {

// The values of a one-channel PFM (the samples map), top row first.
std::vector<float> grey_pfm(const std::string& bytes, int& width) {
    wsd::render::Film film;
    std::string error;
    if (wsd::render::decode_pfm(bytes, film, error) == 0) return {};
    width = film.width;
    std::vector<float> out;
    for (size_t i = 0; i < film.rgb.size(); i += 3) out.push_back(film.rgb[i]);
    return out;
}

}  // namespace

TEST_CASE("--target-error and --time-limit: zero, negative, NaN, infinite and huge values", "[progressive]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    for (const char* bad : {"0", "-0.01", "-1", "nan", "inf", "1e10", "abc", "0.01x"}) {
        INFO(bad);
        RunResult r = run_wsd(dir, std::string("render s.wsd --quiet --target-error ") + bad);
        CHECK(r.status == 2);
        CHECK(r.err.find("--target-error") != std::string::npos);
        r = run_wsd(dir, std::string("render s.wsd --quiet --time-limit ") + bad);
        CHECK(r.status == 2);
        CHECK(r.err.find("--time-limit") != std::string::npos);
    }
    CHECK(list_files(dir).size() == 1);  // nothing rendered
    // --aov samples only exists for progressive renders.
    RunResult r = run_wsd(dir, "render s.wsd --quiet --aov samples");
    CHECK(r.status == 2);
    CHECK(r.err.find("--target-error") != std::string::npos);
    // A huge target is met by every pixel at its first pass (samples never differ by more than 1).
    r = run_wsd(dir, "render s.wsd --quiet --target-error 1e9 --stats-json s.json -o huge.png");
    REQUIRE(r.status == 0);
    const auto json = nlohmann::json::parse(read_file(dir / "s.json"));
    CHECK(json["samples_per_pixel"]["min"] == 4);
    CHECK(json["samples_per_pixel"]["max"] == 4);
    CHECK(json["target_reached"] == true);
}

TEST_CASE("a targeted render: statistics, samples map, and tiles that merge byte for byte", "[progressive]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene(5, 18));
    RunResult r = run_wsd(dir,
                          "render s.wsd --target-error 0.03 -o whole.pfm --threads 1 --aov samples "
                          "--stats-json s.json --stats");
    REQUIRE(r.status == 0);
    CHECK(r.out.find("Estimated RMSE:") != std::string::npos);
    CHECK(r.err.find("progressive: ") != std::string::npos);
    const auto json = nlohmann::json::parse(read_file(dir / "s.json"));
    CHECK(json["estimated_rmse"].get<double>() > 0);
    // The reported estimate comes from the samples that did not decide; the deciding one is
    // conservative, so it lies below the target.
    CHECK(json["estimated_rmse"].get<double>() <= 0.03 * 1.5);
    CHECK(json["passes"].get<int>() >= 2);
    CHECK(json["target_error"] == 0.03);
    CHECK(json["time_limit"].is_null());
    const int lo = json["samples_per_pixel"]["min"], hi = json["samples_per_pixel"]["max"];
    CHECK(lo >= 4);  // the first pass
    CHECK(hi > lo);
    int width = 0;
    const std::vector<float> samples = grey_pfm(read_file(dir / "whole.samples.pfm"), width);
    REQUIRE(width == 18);
    double total = 0;
    for (const float v : samples) total += v;
    CHECK(total == json["samples_total"].get<double>());

    REQUIRE(run_wsd(dir, "render s.wsd --target-error 0.03 -o whole3.pfm --threads 3 --quiet").status == 0);
    CHECK(read_file(dir / "whole3.pfm") == read_file(dir / "whole.pfm"));
    for (int i = 1; i <= 3; ++i)
        REQUIRE(run_wsd(dir, "render s.wsd --quiet --target-error 0.03 --aov samples --tile " +
                                 std::to_string(i) + "/3 -o t" + std::to_string(i) + ".pfm")
                    .status == 0);
    r = run_wsd(dir, "merge t2.pfm t1.pfm t3.pfm -o merged.pfm");
    REQUIRE(r.status == 0);
    CHECK(read_file(dir / "merged.pfm") == read_file(dir / "whole.pfm"));
    CHECK(read_file(dir / "merged.samples.pfm") == read_file(dir / "whole.samples.pfm"));
}

TEST_CASE("a target that the pixels at the sample cap do not meet is reported as not reached",
          "[progressive]") {
    TempDir dir;
    write_file(dir / "s.wsd",
               "settings { width 16  height 12  supersamples 1  background <0.2, 0.3, 0.4> }\n"
               "camera { position <0, 1, -5>  look_at <0, 0.5, 0>  fov 45 }\n"
               "light point { position <3, 5, -4> }\n"
               "light area { position <-3, 6, -4>  u <1, 0, 0>  v <0, 0, 1>  samples 2 }\n"
               "sphere { center <0, 0.6, 0>  radius 0.6  material { color <0.9, 0.2, 0.1> } }\n"
               "plane { normal <0, 1, 0>  distance 0  material { color <0.8, 0.8, 0.8> } }\n");
    const RunResult r =
        run_wsd(dir, "render s.wsd --target-error 0.0001 -o s.pfm --stats --stats-json s.json");
    REQUIRE(r.status == 0);
    const auto json = nlohmann::json::parse(read_file(dir / "s.json"));
    CHECK(json["samples_per_pixel"]["max"] == 1024);
    CHECK(json["time_limit_reached"] == false);
    CHECK(json["target_reached"] == false);
    CHECK(r.out.find("(target 0.0001, not reached)") != std::string::npos);
    CHECK(r.err.find("the target was not reached") != std::string::npos);
}

TEST_CASE("a time limit shorter than the first pass gives the first pass, complete", "[progressive]") {
    TempDir dir;
    // 2 × 10⁻⁹ s: over before the first pass has begun.
    write_file(dir / "s.wsd", tiny_scene(5, 18));
    RunResult r = run_wsd(dir, "render s.wsd --time-limit 2e-9 -o t.pfm --aov samples --stats-json s.json");
    REQUIRE(r.status == 0);
    CHECK(r.err.find("the first pass alone took longer than the time limit") != std::string::npos);
    const auto json = nlohmann::json::parse(read_file(dir / "s.json"));
    CHECK(json["passes"] == 1);
    CHECK(json["time_limit_reached"] == true);
    CHECK(json["first_pass_over_time_limit"] == true);
    int width = 0;
    const std::vector<float> samples = grey_pfm(read_file(dir / "t.samples.pfm"), width);
    REQUIRE(samples.size() == 18u * 18u);
    CHECK(std::all_of(samples.begin(), samples.end(), [](float v) { return v == 4; }));
}
