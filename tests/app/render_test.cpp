// `wsd render` and `wsd merge` through the real binary: outputs and overrides, statistics,
// atomic output (nothing partial after any failure), interruption, and tiles that merge into
// exactly the single render, with every merge error naming the tile at fault.
#include <sys/stat.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "app_test_util.h"

using namespace wsd::test;

namespace {

// "PF\nW H\n" → W, H.
std::pair<int, int> pfm_size(const std::string& bytes) {
    std::istringstream in(bytes);
    std::string magic;
    int w = 0, h = 0;
    in >> magic >> w >> h;
    return {w, h};
}

bool no_temporaries(const TempDir& dir) {
    const auto files = list_files(dir);
    return std::none_of(files.begin(), files.end(),
                        [](const std::string& f) { return f.find(".tmp") != std::string::npos; });
}

}  // namespace

TEST_CASE("render writes ./NAME.png by default and honours -o and the overrides", "[render]") {
    TempDir dir;
    fs::create_directory(dir.path() / "scenes");
    write_file(dir / "scenes/s.wsd", tiny_scene());
    RunResult r = run_wsd(dir, "render scenes/s.wsd --quiet");
    REQUIRE(r.status == 0);
    CHECK(r.out.empty());
    CHECK(r.err.empty());
    CHECK(read_file(dir / "s.png").rfind("\x89PNG", 0) == 0);

    r = run_wsd(dir,
                "render scenes/s.wsd -o small.pfm --width 8 --height 6 --supersamples 1 --max-depth 0 "
                "--light-samples 1 --seed 9 --threads 1 --no-bvh --quiet");
    REQUIRE(r.status == 0);
    CHECK(pfm_size(read_file(dir / "small.pfm")) == std::make_pair(8, 6));
    for (const char* ext : {"hdr", "bmp", "tga", "jpg"}) {
        CHECK(run_wsd(dir, std::string("render scenes/s.wsd --quiet -o out.") + ext).status == 0);
        CHECK(fs::file_size(dir / (std::string("out.") + ext)) > 0);
    }
    CHECK(no_temporaries(dir));
}

TEST_CASE("render reads the scene from stdin", "[render]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    const int raw = std::system(("cd " + shell_quote(dir.path().string()) + " && cat s.wsd | " +
                                 shell_quote(WSD_BINARY) + " render - -o in.pfm --quiet 2>err.txt")
                                    .c_str());
    CHECK(WEXITSTATUS(raw) == 0);
    CHECK(pfm_size(read_file(dir / "in.pfm")) == std::make_pair(16, 16));
}

TEST_CASE("progress goes to stderr unless --quiet; --stats prints a table", "[render]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    RunResult r = run_wsd(dir, "render s.wsd -o a.png --stats --quiet");
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    for (const char* row : {"Camera rays", "Shadow rays", "Sphere", "Triangle", "Render time", "Peak memory"})
        CHECK(r.out.find(row) != std::string::npos);
    r = run_wsd(dir, "render s.wsd -o a.png");
    REQUIRE(r.status == 0);
    CHECK(r.out.empty());
}

TEST_CASE("--stats-json writes the named keys", "[render]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    const RunResult r = run_wsd(dir, "render s.wsd -o a.png --quiet --stats-json stats.json");
    REQUIRE(r.status == 0);
    const std::string json = read_file(dir / "stats.json");
    for (const char* key :
         {"camera_rays", "shadow_rays", "reflection_rays", "refraction_rays", "triangle_tests",
          "triangle_hits", "sphere_tests", "sphere_hits", "box_tests", "parse_seconds", "build_seconds",
          "render_seconds", "mrays_per_second", "peak_memory_bytes", "nonfinite_samples", "effects"})
        CHECK(json.find(std::string("\"") + key + "\":") != std::string::npos);
    CHECK(json.find("\"camera_rays\": 1024,") != std::string::npos);  // 16×16 pixels × 4 supersamples
    CHECK(json.find("\"nonfinite_samples\": 0,") != std::string::npos);
    CHECK(json.find("\"peak_memory_bytes\": 0,") == std::string::npos);
}

TEST_CASE("--stats-json writes into a pipe or a device in place, never replacing it", "[render]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    // A FIFO stands for /dev/null or /dev/stdout: a new file renamed over it would replace it.
    REQUIRE(::mkfifo((dir / "pipe").c_str(), 0644) == 0);
    RunResult r = run_wsd(dir, "render s.wsd -o a.png --quiet --stats-json pipe",
                          "(timeout 20 cat pipe > got.json &);");
    CHECK(r.status == 0);
    CHECK(fs::is_fifo(dir / "pipe"));
    std::string got;
    for (int i = 0; i < 200 && got.find("\"camera_rays\"") == std::string::npos; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        got = read_file(dir / "got.json");
    }
    CHECK(got.find("\"camera_rays\": 1024,") != std::string::npos);
    // /dev/fd/1 (as /dev/stdout) is this process's standard output, after the table printed there.
    r = run_wsd(dir, "render s.wsd -o a.png --quiet --stats --stats-json /dev/fd/1");
    CHECK(r.status == 0);
    const size_t table = r.out.find("Render statistics"), json = r.out.find("\"camera_rays\": 1024,");
    CHECK(table != std::string::npos);
    CHECK(json != std::string::npos);
    CHECK(table < json);
    // `-` is standard output too, as /dev/stdout is: no file named '-' is written.
    r = run_wsd(dir, "render s.wsd -o a.png --quiet --stats --stats-json -");
    CHECK(r.status == 0);
    CHECK(r.out.find("Render statistics") < r.out.find("\"camera_rays\": 1024,"));
    CHECK(r.out.find("\"camera_rays\": 1024,") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "-"));
}

TEST_CASE("--stats-json that would overwrite the image, or names a directory, fails before rendering",
          "[render]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    fs::create_directory(dir / "d.json");
    RunResult r = run_wsd(dir, "render s.wsd -o a.png --quiet --stats-json ./a.png");
    CHECK(r.status == 2);
    CHECK(r.err.find("--stats-json names the image's own output") != std::string::npos);
    r = run_wsd(dir, "render s.wsd -o a.png --quiet --stats-json d.json");
    CHECK(r.status == 3);
    CHECK(r.err.find("it is a directory") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "a.png"));
    // Nor may it replace the scene, for a still or for any frame.
    const std::string scene = read_file(dir / "s.wsd");
    r = run_wsd(dir, "render s.wsd -o a.png --quiet --stats-json ./s.wsd");
    CHECK(r.status == 2);
    CHECK(r.err.find("--stats-json names the scene 's.wsd'") != std::string::npos);
    CHECK(read_file(dir / "s.wsd") == scene);
    CHECK_FALSE(fs::exists(dir / "a.png"));
    write_file(dir / "s1.wsd", scene);
    r = run_wsd(dir, "render s1.wsd -o 'a-#.png' --frames 0-1 --quiet --stats-json 's#.wsd'");
    CHECK(r.status == 2);
    CHECK(r.err.find("--stats-json names the scene 's1.wsd'") != std::string::npos);
    CHECK(read_file(dir / "s1.wsd") == scene);
    CHECK_FALSE(fs::exists(dir / "a-1.png"));
}

TEST_CASE("--stats-json that would overwrite an auxiliary image fails before rendering", "[render][aov]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene(3, 4));
    RunResult r = run_wsd(dir, "render s.wsd -o c2.png --quiet --aov depth --stats-json c2.depth.pfm");
    CHECK(r.status == 2);
    CHECK(r.err.find("--stats-json names the auxiliary image 'c2.depth.pfm' of 'c2.png'") !=
          std::string::npos);
    r = run_wsd(dir, "render s.wsd -o c2.png --quiet --aov albedo,normal --stats-json ./c2.normal.pfm");
    CHECK(r.status == 2);
    // The names of frames too.
    r = run_wsd(dir,
                "render s.wsd -o 'f-#.png' --frames 1-2 --quiet --aov depth --stats-json 'f-#.depth.pfm'");
    CHECK(r.status == 2);
    CHECK(r.err.find("'f-1.depth.pfm'") != std::string::npos);
    CHECK(list_files(dir) == std::vector<std::string>{"s.wsd"});
    // A tile file carries its auxiliary images: no sibling is written, so the name is free.
    r = run_wsd(dir, "render s.wsd --tile 1/2 -o t.pfm --quiet --aov depth --stats-json t.depth.pfm");
    CHECK(r.status == 0);
    CHECK(read_file(dir / "t.depth.pfm").find("\"camera_rays\"") != std::string::npos);
}

TEST_CASE("samples that overflow single precision are named in a warning, even with --quiet", "[render]") {
    TempDir dir;
    // Each value fits a float; their product (ambient × colour) does not.
    write_file(
        dir / "o.wsd",
        "settings { width 8  height 8  ambient 1e20 }\ncamera { position <0, 0, -2>  look_at <0, 0, 0> }\n"
        "sphere { center <0, 0, 0>  radius 1  material { color <1e20, 1e20, 1e20> } }\n");
    RunResult r = run_wsd(dir, "render o.wsd -o o.pfm --quiet");
    CHECK(r.status == 0);
    CHECK(r.err.find("samples were not finite or too large for single precision") != std::string::npos);
    write_file(dir / "fine.wsd", tiny_scene());
    r = run_wsd(dir, "render fine.wsd -o f.pfm --quiet");
    CHECK(r.status == 0);
    CHECK(r.err.find("not finite") == std::string::npos);
}

TEST_CASE("--stats-json is valid JSON even for a scene path that is not UTF-8", "[render]") {
    TempDir dir;
    write_file(dir / "caf\xe9 \"1\".wsd", tiny_scene());  // Latin-1 é and quotes
    const RunResult r = run_wsd(dir, "render 'caf\xe9 \"1\".wsd' -o a.png --quiet --stats-json stats.json");
    REQUIRE(r.status == 0);
    const auto json = nlohmann::json::parse(read_file(dir / "stats.json"), nullptr, false);
    REQUIRE_FALSE(json.is_discarded());
    CHECK(json["scene"] == "caf\xEF\xBF\xBD \"1\".wsd");
    CHECK(json["camera_rays"] == 1024);
    CHECK(json["render_seconds"].is_number());
    CHECK(json["effects"].is_array());
}

TEST_CASE("a failed render leaves no output and no temporary file", "[render][atomic]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    write_file(dir / "bad.wsd", tiny_scene() + "sphere { center <0,0,0> }\n");
    RunResult r = run_wsd(dir, "render bad.wsd -o out.png --quiet");
    CHECK(r.status == 1);
    CHECK_FALSE(fs::exists(dir / "out.png"));
    CHECK_FALSE(fs::exists(dir / "bad.png"));

    r = run_wsd(dir, "render missing.wsd -o out.png --quiet");
    CHECK(r.status == 3);

    r = run_wsd(dir, "render s.wsd -o no/such/dir/out.png --quiet");
    CHECK(r.status == 3);
    CHECK_FALSE(fs::exists(dir / "no"));
    r = run_wsd(dir, "render s.wsd -o out.png --stats-json no/such/stats.json --quiet");
    CHECK(r.status == 3);
    CHECK_FALSE(fs::exists(dir / "out.png"));
    // A file where the output's directory should be is named as such.
    r = run_wsd(dir, "render s.wsd -o s.wsd/x.png --quiet");
    CHECK(r.status == 3);
    CHECK(r.err.find("'s.wsd' is not a directory") != std::string::npos);
    r = run_wsd(dir, "render s.wsd -o s.wsd/sub/x.png --quiet");
    CHECK(r.err.find("'s.wsd' is not a directory") != std::string::npos);
    r = run_wsd(dir, "render s.wsd -o no/x.png --quiet");
    CHECK(r.err.find("directory 'no' does not exist") != std::string::npos);

    // An existing output is replaced whole or not at all.
    write_file(dir / "keep.png", "old");
    r = run_wsd(dir, "render bad.wsd -o keep.png --quiet");
    CHECK(r.status == 1);
    CHECK(read_file(dir / "keep.png") == "old");
    CHECK(no_temporaries(dir));
}

TEST_CASE("SIGINT and SIGTERM stop the render with 130 and 143 and write nothing", "[render][signal]") {
    TempDir dir;
    // Far too much work to finish within the timeout, even in a fast build.
    write_file(dir / "slow.wsd", tiny_scene(1, 2000));
    RunResult r = run_wsd(dir, "render slow.wsd -o out.png --supersamples 64 --light-samples 4 --quiet",
                          "timeout --preserve-status -s INT 1");
    CHECK(r.status == 130);
    r = run_wsd(dir, "render slow.wsd -o out.png --supersamples 64 --light-samples 4 --quiet",
                "timeout --preserve-status -s TERM 1");
    CHECK(r.status == 143);
    CHECK(list_files(dir) == std::vector<std::string>{"slow.wsd"});

    // While the scene is still being evaluated (a loop of 10^8 steps takes far longer than the
    // timeout): the evaluation stops at the next iteration.
    write_file(dir / "loop.wsd", tiny_scene() + "for i in 0 .. 99000000 { let a = i * 2 }\n");
    const auto start = std::chrono::steady_clock::now();
    r = run_wsd(dir, "render loop.wsd -o out.png --quiet", "timeout --preserve-status -s TERM 1");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(r.status == 143);
    CHECK(r.err.find("interrupted; no image written") != std::string::npos);
    // Not a speed measurement: without the check the loop runs to its end, 10 s or more.
    CHECK(seconds < 6);
    CHECK_FALSE(fs::exists(dir / "out.png"));
}

TEST_CASE("four tiles merge into exactly the single render", "[tiles]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene(5, 18));  // 18 rows: tiles of 4 and 5 rows
    REQUIRE(run_wsd(dir, "render s.wsd -o whole.png --quiet").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -o whole.pfm --quiet --threads 1").status == 0);
    for (int i = 1; i <= 4; ++i) {
        // Built with append: GCC 12's -Wrestrict misreads "t" + std::to_string(i) once inlined here.
        const std::string tile = std::string("t").append(std::to_string(i)).append(".pfm");
        REQUIRE(
            run_wsd(dir, "render s.wsd --tile " + std::to_string(i) + "/4 -o " + tile + " --quiet").status ==
            0);
        const int y0 = (i - 1) * 18 / 4, y1 = i * 18 / 4;
        CHECK(pfm_size(read_file(dir / tile)) == std::make_pair(18, y1 - y0));
    }
    RunResult r = run_wsd(dir, "merge t3.pfm t1.pfm t4.pfm t2.pfm -o merged.png");
    REQUIRE(r.status == 0);
    CHECK(read_file(dir / "merged.png") == read_file(dir / "whole.png"));
    r = run_wsd(dir, "merge t1.pfm t2.pfm t3.pfm t4.pfm -o merged.pfm");
    REQUIRE(r.status == 0);
    CHECK(read_file(dir / "merged.pfm") == read_file(dir / "whole.pfm"));

    // Regions: a 2×2 grid of rectangles merges just as well; the default tile name is used.
    for (const char* region : {"0,0,7,9", "7,0,18,9", "0,9,7,18", "7,9,18,18"})
        REQUIRE(run_wsd(dir, std::string("render s.wsd --quiet --region ") + region).status == 0);
    r = run_wsd(dir,
                "merge s.region-0-0-7-9.pfm s.region-7-0-18-9.pfm s.region-0-9-7-18.pfm "
                "s.region-7-9-18-18.pfm -o grid.png");
    REQUIRE(r.status == 0);
    CHECK(read_file(dir / "grid.png") == read_file(dir / "whole.png"));
}

TEST_CASE("merge refuses missing, duplicate, overlapping, foreign and reseeded tiles", "[tiles]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene(5, 16));
    write_file(dir / "other.wsd", tiny_scene(5, 16) + "// a different scene text\n");
    for (int i = 1; i <= 4; ++i)
        REQUIRE(run_wsd(dir, "render s.wsd --quiet --tile " + std::to_string(i) + "/4 -o t" +
                                 std::to_string(i) + ".pfm")
                    .status == 0);
    REQUIRE(run_wsd(dir, "render other.wsd --quiet --tile 2/4 -o foreign.pfm").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd --quiet --tile 2/4 --seed 6 -o seeded.pfm").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd --quiet --tile 2/4 --supersamples 1 -o cheap.pfm").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd --quiet --region 0,2,16,6 -o overlap.pfm").status == 0);
    write_file(dir / "junk.pfm", "PF\n16 4\n-1.0\nshort");
    {
        // A valid tile whose metadata holds a value nested 100,000 deep: an error, not a crash.
        std::string tile = read_file(dir / "t2.pfm");
        const size_t at = tile.find("\"seed\":");
        REQUIRE(at != std::string::npos);
        tile.insert(at, "\"x\":" + std::string(100000, '[') + std::string(100000, ']') + ",");
        write_file(dir / "deep.pfm", tile);
    }

    struct Case {
        const char* tiles;
        const char* named;  // the tile the message must name
        const char* what;
    };
    const Case cases[] = {
        {"t1.pfm t2.pfm t4.pfm", "3/4", "missing"},
        {"t1.pfm t2.pfm t2.pfm t3.pfm t4.pfm", "t2.pfm", "duplicate"},
        {"t1.pfm t2.pfm t3.pfm t4.pfm overlap.pfm", "overlap.pfm", "overlap"},
        {"t1.pfm foreign.pfm t3.pfm t4.pfm", "foreign.pfm", "foreign scene"},
        {"t1.pfm seeded.pfm t3.pfm t4.pfm", "seeded.pfm", "seed"},
        {"t1.pfm cheap.pfm t3.pfm t4.pfm", "cheap.pfm", "settings"},
        {"t1.pfm t2.pfm t3.pfm t4.pfm junk.pfm", "junk.pfm", "malformed"},
        {"t1.pfm deep.pfm t3.pfm t4.pfm", "deep.pfm", "nested too deep"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        const RunResult r = run_wsd(dir, std::string("merge ") + c.tiles + " -o merged.png");
        CHECK(r.status == 1);
        CHECK(r.err.find(c.named) != std::string::npos);
        CHECK_FALSE(fs::exists(dir / "merged.png"));
    }
    CHECK(run_wsd(dir, "merge t1.pfm t2.pfm nope.pfm t4.pfm -o merged.png").status == 3);
    CHECK(run_wsd(dir, "merge t1.pfm t2.pfm t3.pfm t4.pfm -o merged.xyz").status == 2);
    CHECK(run_wsd(dir, "merge t1.pfm t2.pfm t3.pfm t4.pfm -o nodir/merged.png").status == 3);
    {
        // -o naming one of the tiles would replace it with the merged image: refused, tile intact.
        const std::string tile = read_file(dir / "t4.pfm");
        const RunResult r = run_wsd(dir, "merge t1.pfm t2.pfm t3.pfm t4.pfm -o ./t4.pfm");
        CHECK(r.status == 2);
        CHECK(r.err.find("-o './t4.pfm' names the tile 't4.pfm'") != std::string::npos);
        CHECK(read_file(dir / "t4.pfm") == tile);
    }
    CHECK(run_wsd(dir, "merge t1.pfm t2.pfm t3.pfm t4.pfm -o merged.png").status == 0);

    // A failed merge leaves an existing output as it was, and no temporary file behind.
    const std::string good = read_file(dir / "merged.png");
    REQUIRE_FALSE(good.empty());
    auto before = list_files(dir);
    CHECK(run_wsd(dir, "merge t1.pfm t2.pfm t4.pfm -o merged.png").status == 1);
    CHECK(read_file(dir / "merged.png") == good);
    auto after = list_files(dir);
    std::sort(before.begin(), before.end());
    std::sort(after.begin(), after.end());
    CHECK(after == before);
}

TEST_CASE("merge refuses tiles rendered with other progressive options", "[tiles][progressive]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene(5, 8));
    const auto tile = [&](int i, const std::string& options, const std::string& name) {
        REQUIRE(
            run_wsd(dir, "render s.wsd --quiet --tile " + std::to_string(i) + "/2 " + options + " -o " + name)
                .status == 0);
    };
    tile(1, "--target-error 0.01", "e1.pfm");
    tile(2, "--target-error 0.01", "e2.pfm");
    tile(2, "--target-error 0.02", "other-target.pfm");
    tile(2, "", "grid.pfm");
    tile(2, "--time-limit 100", "timed.pfm");
    tile(2, "--target-error 0.01 --time-limit 100", "both.pfm");
    CHECK(run_wsd(dir, "merge e1.pfm e2.pfm -o merged.pfm").status == 0);
    for (const char* other : {"other-target.pfm", "grid.pfm", "timed.pfm", "both.pfm"}) {
        INFO(other);
        const RunResult r = run_wsd(dir, std::string("merge e1.pfm ") + other + " -o bad.pfm");
        CHECK(r.status == 1);
        CHECK(r.err.find(std::string("tile '") + other + "' was rendered with different settings") !=
              std::string::npos);
    }
    CHECK_FALSE(fs::exists(dir / "bad.pfm"));
}

TEST_CASE("merge refuses tiles rendered with other --define values", "[tiles][define]") {
    TempDir dir;
    write_file(dir / "p.wsd", tiny_scene(5, 8) +
                                  "sphere { center <1, 0.5, 0>  radius 0.5  material { color param(\"c\", "
                                  "<0, 1, 0>) } }\n");
    const auto tile = [&](int i, const std::string& defines, const std::string& name) {
        REQUIRE(
            run_wsd(dir, "render p.wsd --quiet --tile " + std::to_string(i) + "/2 " + defines + " -o " + name)
                .status == 0);
    };
    tile(1, "-D 'c=<1,0,0>'", "red1.pfm");
    tile(2, "-D 'c=<1,0,0>'", "red2.pfm");
    tile(2, "-D 'c=<0,0,1>'", "blue2.pfm");
    tile(2, "", "none2.pfm");
    tile(2, "-D 'c=<0,0,1>' -D 'c=<1,0,0>'", "last2.pfm");  // the last value of a name is the one read
    CHECK(run_wsd(dir, "merge red1.pfm red2.pfm -o merged.pfm").status == 0);
    CHECK(run_wsd(dir, "merge red1.pfm last2.pfm -o merged.pfm").status == 0);
    for (const char* other : {"blue2.pfm", "none2.pfm"}) {
        INFO(other);
        const RunResult r = run_wsd(dir, std::string("merge red1.pfm ") + other + " -o bad.pfm");
        CHECK(r.status == 1);
        CHECK(r.err.find(std::string("tile '") + other + "' was rendered with other --define values") !=
              std::string::npos);
    }
    CHECK_FALSE(fs::exists(dir / "bad.pfm"));
    // A tile without --define keeps the trailer it always had.
    CHECK(read_file(dir / "none2.pfm").find("defines_hash") == std::string::npos);
}
