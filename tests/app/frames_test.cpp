// `wsd render --frames A-B [--frame N]` and `--clock X` through the real binary: the clock and
// frame each frame sees, output names ('#' runs, padding, wider numbers, a still's literal '#',
// the defaults), a farm task's frame equal to the same frame of the whole run, tiles of a frame
// that merge into the frame, a failing frame that stops the run, and every usage error.
#include "app/frames.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "app_test_util.h"
#include "render/image_io.h"

using namespace wsd::test;

namespace {

// The sky's colour is <clock, frame / 1000, 0.5>: a render of it says which clock and frame the
// scene saw, exactly (a PFM stores the floats).
const char* clock_scene =
    "settings { width 2  height 2  background <clock, frame / 1000, 0.5> }\n"
    "camera { position <0, 0, -5>  look_at <0, 0, 0> }\n";

// tiny_scene with a sphere that moves with clock and grows with frame.
std::string moving_scene(int size = 16) {
    return tiny_scene(3, size) +
           "sphere { center <-1 + 2 * clock, 1.5, 0.5>  radius 0.3 + frame / 100\n"
           "         material { color <0.2, 0.9, 0.3> } }\n";
}

// The first pixel of a PFM file.
std::array<float, 3> first_pixel(const std::string& path) {
    wsd::render::Film film;
    std::string error;
    REQUIRE(wsd::render::decode_pfm(read_file(path), film, error) != 0);
    return {film.rgb[0], film.rgb[1], film.rgb[2]};
}

std::vector<std::string> sorted_files(const TempDir& dir) {
    std::vector<std::string> files = list_files(dir);
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

TEST_CASE("each frame sees frame = n and clock = (n - A) / (B - A)", "[frames]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --frames 3-7 -o 'f-#.pfm'").status == 0);
    for (int n = 3; n <= 7; ++n) {
        INFO("frame " << n);
        const auto p = first_pixel(dir / ("f-" + std::to_string(n) + ".pfm"));
        CHECK(p[0] == static_cast<float>((n - 3) / 4.0));
        CHECK(p[1] == static_cast<float>(n / 1000.0));
    }
    // One frame (A = B): clock 0.
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --frames 9-9 -o one.pfm").status == 0);
    CHECK(first_pixel(dir / "one.pfm")[0] == 0.0f);
    CHECK(first_pixel(dir / "one.pfm")[1] == 0.009f);
    // A still: 0 and 0, or --clock X.
    REQUIRE(run_wsd(dir, "render c.wsd --quiet -o still.pfm").status == 0);
    CHECK(first_pixel(dir / "still.pfm") == std::array<float, 3>{0.0f, 0.0f, 0.5f});
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --clock 0.25 -o quarter.pfm").status == 0);
    CHECK(first_pixel(dir / "quarter.pfm") == std::array<float, 3>{0.25f, 0.0f, 0.5f});
    // --define values see the frame's clock too.
    write_file(dir / "d.wsd",
               "settings { width 2  height 2  background <param(\"r\", 0), 0, 0> }\n"
               "camera { position <0, 0, -5>  look_at <0, 0, 0> }\n");
    REQUIRE(run_wsd(dir, "render d.wsd --quiet --frames 0-2 -D r=clock -o 'd-#.pfm'").status == 0);
    CHECK(first_pixel(dir / "d-1.pfm")[0] == 0.5f);
}

TEST_CASE("'#' runs in -o become the zero-padded frame number; a still's '#' is literal", "[frames][names]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --frames 98-101 -o 'out-##.pfm'").status == 0);
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --frames 7-8 -o 'pad-####.pfm'").status == 0);
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --frames 7-8 --frame 8 -o 'two-###-#.pfm'").status == 0);
    REQUIRE(run_wsd(dir, "render c.wsd --quiet -o 'still-##.pfm'").status == 0);
    CHECK(sorted_files(dir) == std::vector<std::string>{"c.wsd", "out-100.pfm", "out-101.pfm", "out-98.pfm",
                                                        "out-99.pfm", "pad-0007.pfm", "pad-0008.pfm",
                                                        "still-##.pfm", "two-008-8.pfm"});
}

TEST_CASE("frames of a scene read from stdin: the text is read once", "[frames]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    const int raw =
        std::system(("cd " + shell_quote(dir.path().string()) + " && cat c.wsd | " + shell_quote(WSD_BINARY) +
                     " render - --frames 0-2 -o in-#.pfm --quiet 2>err.txt")
                        .c_str());
    CHECK(WEXITSTATUS(raw) == 0);
    CHECK(first_pixel(dir / "in-2.pfm")[0] == 1.0f);
}

TEST_CASE("frames are named NAME-####.png, and their tiles NAME-####.tile-I-of-N.pfm", "[frames][names]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --frames 0-1").status == 0);
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --frames 0-12 --frame 12 --tile 2/2").status == 0);
    REQUIRE(
        run_wsd(dir, "render c.wsd --quiet --frames 3-4 --region 0,0,1,2 --stats-json 's-#.json'").status ==
        0);
    CHECK(sorted_files(dir) == std::vector<std::string>{"c-0000.png", "c-0001.png",
                                                        "c-0003.region-0-0-1-2.pfm",
                                                        "c-0004.region-0-0-1-2.pfm", "c-0012.tile-2-of-2.pfm",
                                                        "c.wsd", "s-3.json", "s-4.json"});
}

TEST_CASE("--frame N equals frame N of the whole run, and a still at the same clock", "[frames]") {
    TempDir dir;
    write_file(dir / "m.wsd", moving_scene());
    REQUIRE(run_wsd(dir, "render m.wsd --quiet --frames 0-4 -o 'all-#.png'").status == 0);
    REQUIRE(run_wsd(dir, "render m.wsd --quiet --frames 0-4 --frame 2 -o 'one-#.png'").status == 0);
    CHECK(read_file(dir / "one-2.png") == read_file(dir / "all-2.png"));
    CHECK(read_file(dir / "all-1.png") != read_file(dir / "all-2.png"));  // the sphere moves
    // The sampling pattern does not depend on the frame: frame 0 of 0-4 is the still.
    REQUIRE(run_wsd(dir, "render m.wsd --quiet -o still.png").status == 0);
    CHECK(read_file(dir / "still.png") == read_file(dir / "all-0.png"));
}

TEST_CASE("frames that share texture images still equal their own single renders", "[frames][textures]") {
    TempDir dir;
    const std::string scene = shell_quote(std::string(WSD_SOURCE_DIR) + "/examples/cornell.wsd");
    const std::string opts = " --quiet --width 24 --height 24 --light-samples 1 --supersamples 1";
    REQUIRE(run_wsd(dir, "render " + scene + opts + " --frames 0-2 -o 'all-#.png'").status == 0);
    REQUIRE(run_wsd(dir, "render " + scene + opts + " --frames 0-2 --frame 2 -o one.png").status == 0);
    REQUIRE(run_wsd(dir, "render " + scene + opts + " -o still.png").status == 0);
    CHECK(read_file(dir / "one.png") == read_file(dir / "all-2.png"));
    CHECK(read_file(dir / "still.png") == read_file(dir / "all-1.png"));  // cornell.wsd does not move
}

TEST_CASE("the tiles of a frame merge into that frame; merge refuses tiles of other frames",
          "[frames][tiles]") {
    TempDir dir;
    write_file(dir / "m.wsd", moving_scene(18));
    REQUIRE(run_wsd(dir, "render m.wsd --quiet --frames 1-3 -o 'f-#.pfm'").status == 0);
    for (int i = 1; i <= 3; ++i)
        REQUIRE(run_wsd(dir, "render m.wsd --quiet --frames 1-3 --frame 2 --tile " + std::to_string(i) + "/3")
                    .status == 0);
    RunResult r = run_wsd(dir,
                          "merge m-0002.tile-1-of-3.pfm m-0002.tile-2-of-3.pfm m-0002.tile-3-of-3.pfm "
                          "-o merged.pfm");
    REQUIRE(r.status == 0);
    CHECK(read_file(dir / "merged.pfm") == read_file(dir / "f-2.pfm"));

    // A tile of frame 3 (same scene, settings and seed) does not belong to frame 2.
    REQUIRE(run_wsd(dir, "render m.wsd --quiet --frames 1-3 --frame 3 --tile 2/3 -o other.pfm").status == 0);
    r = run_wsd(dir, "merge m-0002.tile-1-of-3.pfm other.pfm m-0002.tile-3-of-3.pfm -o bad.pfm");
    CHECK(r.status == 1);
    CHECK(r.err.find("other.pfm") != std::string::npos);
    CHECK(r.err.find("frame 3") != std::string::npos);
    // Nor does frame 2 of another range (another clock), nor a still's tile.
    REQUIRE(run_wsd(dir, "render m.wsd --quiet --frames 0-3 --frame 2 --tile 2/3 -o range.pfm").status == 0);
    CHECK(run_wsd(dir, "merge m-0002.tile-1-of-3.pfm range.pfm m-0002.tile-3-of-3.pfm -o bad.pfm").status ==
          1);
    REQUIRE(run_wsd(dir, "render m.wsd --quiet --tile 2/3 -o still.pfm").status == 0);
    CHECK(run_wsd(dir, "merge m-0002.tile-1-of-3.pfm still.pfm m-0002.tile-3-of-3.pfm -o bad.pfm").status ==
          1);
    CHECK_FALSE(fs::exists(dir / "bad.pfm"));
}

TEST_CASE("a failing frame stops the run; the frames before it stay", "[frames][atomic]") {
    TempDir dir;
    write_file(dir / "m.wsd", moving_scene() + "if frame == 3 { sphere { center <0, 0, 0>  radius -1 } }\n");
    const RunResult r = run_wsd(dir, "render m.wsd --quiet --frames 1-5 -o 'f-#.png'");
    CHECK(r.status == 1);
    CHECK(r.err.find("radius") != std::string::npos);
    CHECK(r.err.find("stopped at frame 3; frames 1 to 2 were written") != std::string::npos);
    CHECK(sorted_files(dir) == std::vector<std::string>{"f-1.png", "f-2.png", "m.wsd"});
    // The frames written are whole: each equals its own render.
    REQUIRE(run_wsd(dir, "render m.wsd --quiet --frames 1-5 --frame 2 -o again.png").status == 0);
    CHECK(read_file(dir / "again.png") == read_file(dir / "f-2.png"));
}

TEST_CASE("a --define that fails only at a later frame fails that frame", "[frames][define]") {
    TempDir dir;
    write_file(dir / "p.wsd",
               "settings { width 2  height 2  background <param(\"r\", 0), 0, 0> }\n"
               "camera { position <0, 0, -5>  look_at <0, 0, 0> }\n");
    RunResult r = run_wsd(dir, "render p.wsd --quiet --frames 1-3 -o 'f-#.pfm' -D 'r=0.3/(3-frame)'");
    CHECK(r.status == 1);
    CHECK(r.err.find("--define r: division by zero") != std::string::npos);
    CHECK(r.err.find("stopped at frame 3; frames 1 to 2 were written") != std::string::npos);
    CHECK(sorted_files(dir) == std::vector<std::string>{"f-1.pfm", "f-2.pfm", "p.wsd"});
    // At the run's first frame nothing has rendered: a usage error, as for a still, and wsd says
    // where it stopped as for any frame.
    r = run_wsd(dir, "render p.wsd --quiet --frames 3-4 -o 'g-#.pfm' -D 'r=0.3/(3-frame)'");
    CHECK(r.status == 2);
    CHECK(r.err.find("stopped at frame 3; no frame was written") != std::string::npos);
    CHECK(run_wsd(dir, "render p.wsd --quiet -o still.pfm -D 'r=0.3/(3-3)'").status == 2);
}

TEST_CASE("a run whose first frame fails says where it stopped", "[frames][atomic]") {
    TempDir dir;
    write_file(dir / "m.wsd", moving_scene() + "if frame == 1 { sphere { center <0, 0, 0>  radius -1 } }\n");
    const RunResult r = run_wsd(dir, "render m.wsd --quiet --frames 1-5 -o 'f-#.png'");
    CHECK(r.status == 1);
    CHECK(r.err.find("stopped at frame 1; no frame was written") != std::string::npos);
    CHECK(sorted_files(dir) == std::vector<std::string>{"m.wsd"});
}

TEST_CASE("a frame whose --stats-json cannot be written leaves none of its output", "[frames][atomic]") {
    if (!fs::exists("/dev/full")) return;  // writes to it fail with ENOSPC
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    // The image and its auxiliary images are written first, then the JSON fails: they go too.
    RunResult r = run_wsd(
        dir, "render c.wsd --quiet --frames 1-3 --frame 2 -o 'f-#.png' --aov depth --stats-json /dev/full");
    CHECK(r.status == 3);
    CHECK(r.err.find("cannot write '/dev/full'") != std::string::npos);
    CHECK(r.err.find("stopped at frame 2; no frame was written") != std::string::npos);
    CHECK(sorted_files(dir) == std::vector<std::string>{"c.wsd"});
    // The same for a still, an .exr and a tile file.
    CHECK(run_wsd(dir, "render c.wsd --quiet -o s.exr --aov albedo --stats-json /dev/full").status == 3);
    CHECK(run_wsd(dir, "render c.wsd --quiet --tile 1/2 --aov normal --stats-json /dev/full").status == 3);
    CHECK(sorted_files(dir) == std::vector<std::string>{"c.wsd"});
    CHECK(fs::exists("/dev/full"));  // a device written in place is never removed
}

TEST_CASE("each frame's statistics name the frame and its clock", "[frames][stats]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    const RunResult r =
        run_wsd(dir, "render c.wsd --quiet --frames 2-6 --stats --stats-json 'j-#.json' -o 'f-#.pfm'");
    REQUIRE(r.status == 0);
    for (int n = 2; n <= 6; ++n) {
        INFO("frame " << n);
        std::string name = "j-";
        name.append(std::to_string(n)).append(".json");
        const auto json = nlohmann::json::parse(read_file(dir / name), nullptr, false);
        REQUIRE_FALSE(json.is_discarded());
        CHECK(json["frame"] == n);
        CHECK(json["clock"] == (n - 2) / 4.0);
    }
    CHECK(r.out.find("Render statistics: c.wsd, frame 3, clock 0.25\n") != std::string::npos);
    // A still has no frame; its clock is 0 or --clock's.
    REQUIRE(run_wsd(dir, "render c.wsd --quiet --clock 0.75 --stats-json s.json -o s.pfm").status == 0);
    const auto still = nlohmann::json::parse(read_file(dir / "s.json"), nullptr, false);
    REQUIRE_FALSE(still.is_discarded());
    CHECK(still["frame"].is_null());
    CHECK(still["clock"] == 0.75);
}

TEST_CASE("a warning that every frame gives is printed once per run", "[frames][warnings]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);  // no lights: a warning at every frame
    const RunResult r = run_wsd(dir, "render c.wsd --quiet --frames 0-3 -o 'f-#.pfm' -D unused=1");
    REQUIRE(r.status == 0);
    const auto count = [&](const std::string& text) {
        size_t n = 0;
        for (size_t at = r.err.find(text); at != std::string::npos; at = r.err.find(text, at + 1)) ++n;
        return n;
    };
    CHECK(count("warning: no lights") == 1);
    CHECK(count("--define unused was not used") == 1);
}

TEST_CASE("a --define that a later frame reads is used", "[frames][define]") {
    TempDir dir;
    write_file(dir / "p.wsd", std::string(clock_scene) + "if frame == 2 { let r = param(\"r\", 1) }\n");
    RunResult r = run_wsd(dir, "render p.wsd --quiet --frames 1-3 -o 'f-#.pfm' -D r=3 -D s=4");
    REQUIRE(r.status == 0);
    CHECK(r.err.find("--define r was not used") == std::string::npos);
    CHECK(r.err.find("--define s was not used") != std::string::npos);
    // One frame that does not read it: it was not used.
    r = run_wsd(dir, "render p.wsd --quiet --frames 1-3 --frame 1 -o 'g-#.pfm' -D r=3");
    REQUIRE(r.status == 0);
    CHECK(r.err.find("--define r was not used") != std::string::npos);
}

TEST_CASE("an interrupted run keeps the frames written before it, and nothing partial", "[frames][signal]") {
    TempDir dir;
    // Frame 0 is 8×8; frame 1 is far too much work to finish within the timeout.
    std::string scene = tiny_scene(1, 8);
    const std::string size = "width 8  height 8";
    REQUIRE(scene.find(size) != std::string::npos);
    scene.replace(scene.find(size), size.size(),
                  "width 8 + 1992 * min(frame, 1)  height 8 + 1992 * min(frame, 1)");
    write_file(dir / "s.wsd", scene);
    const RunResult r = run_wsd(dir, "render s.wsd --frames 0-3 -o 'f-#.png' --supersamples 64 --quiet",
                                "timeout --preserve-status -s INT 2");
    CHECK(r.status == 130);
    CHECK(sorted_files(dir) == std::vector<std::string>{"f-0.png", "s.wsd"});
}

TEST_CASE("bad frame options are usage errors, found before anything renders", "[frames][usage]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    struct Case {
        const char* args;
        const char* message;
    };
    const Case cases[] = {
        {"--frame 3", "--frame 3 needs --frames A-B"},
        {"--frames 1-4 --frame 5", "--frame 5 is not in --frames 1-4"},
        {"--frames 1-4 --frame 0", "--frame 0 is not in --frames 1-4"},
        {"--frames 1-4 --clock 0.5", "--clock cannot be used with --frames"},
        {"--frames 5-2", "the first frame is after the last"},
        {"--frames 5", "expected A-B"},
        {"--frames 1-", "expected A-B"},
        {"--frames -1-3", "expected A-B"},
        {"--frames 1-2-3", "expected A-B"},
        {"--frames a-b", "expected A-B"},
        {"--frames ' 1-3'", "expected A-B"},
        {"--frames 1-9999999999", "frame numbers go up to"},
        {"--frames 1-3 -o out.png", "several frames need a run of '#'"},
        {"--frames 1-3 -o 'f-#.png' --stats-json s.json", "several frames need a run of '#'"},
        {"--frames 1-3 -o 'f-#.xyz'", "unknown image format"},
        {"--clock nan", "--clock must be a finite number"},
        {"--clock abc", "--clock"},
        {"--frames 1-3 --frame x", "--frame"},
    };
    for (const Case& c : cases) {
        INFO(c.args);
        const RunResult r = run_wsd(dir, std::string("render c.wsd ") + c.args);
        CHECK(r.status == 2);
        CHECK(r.err.find(c.message) != std::string::npos);
    }
    CHECK(sorted_files(dir) == std::vector<std::string>{"c.wsd"});
    // One frame needs no '#'; a frame's directory must exist (checked before the first frame).
    CHECK(run_wsd(dir, "render c.wsd --quiet --frames 1-3 --frame 2 -o two.png").status == 0);
    CHECK(run_wsd(dir, "render c.wsd --quiet --frames 1-3 -o 'd#/f.png'").status == 3);
    CHECK_FALSE(fs::exists(dir / "d1"));
}

TEST_CASE("the checks before the first frame cost the same for any length of range", "[frames][usage]") {
    TempDir dir;
    write_file(dir / "c.wsd", clock_scene);
    // A billion frames: a missing directory fails at once, within a small address space (not
    // under the sanitizers, which reserve more address space than the limit; the time limit stays).
    const char* sanitized = std::getenv("WSD_SANITIZED");
    const std::string limits =
        sanitized && std::string(sanitized) == "1" ? "timeout 20" : "ulimit -v 1000000 && timeout 20";
    RunResult r = run_wsd(dir, "render c.wsd --quiet --frames 0-999999999 -o 'zz#/x-#.png'", limits);
    CHECK(r.status == 3);
    CHECK(r.err.find("zz0") != std::string::npos);
    r = run_wsd(dir, "render c.wsd --quiet --frames 0-999999999 -o 'big/x-#.png'", limits);
    CHECK(r.status == 3);
    CHECK(r.err.find("'big' does not exist") != std::string::npos);
    r = run_wsd(dir, "render c.wsd --quiet --frames 0-999999999 -o 'x-#.xyz'", limits);
    CHECK(r.status == 2);
    CHECK(sorted_files(dir) == std::vector<std::string>{"c.wsd"});

    // A frame's own directory is checked just before that frame: the frames before it stay.
    fs::create_directory(dir / "d1");
    r = run_wsd(dir, "render c.wsd --quiet --frames 1-3 -o 'd#/f.pfm'");
    CHECK(r.status == 3);
    CHECK(r.err.find("directory 'd2' does not exist") != std::string::npos);
    CHECK(r.err.find("stopped at frame 2; frame 1 was written\n") != std::string::npos);
    CHECK(fs::exists(dir / "d1/f.pfm"));
    CHECK_FALSE(fs::exists(dir / "d2"));
}

TEST_CASE("the progress label names the frame and the run's fraction counts whole frames",
          "[frames][progress]") {
    wsd::app::FrameJob job;
    CHECK(job.progress_label() == "render");
    job.animated = true;
    job.time.frame = 7;
    CHECK(job.progress_label() == "frame 7");
    job.index = 2;
    job.count = 4;
    CHECK(job.progress_label() == "frame 7 (3/4)");
    CHECK(job.run_fraction(0.0) == 0.5);
    CHECK(job.run_fraction(1.0) == 0.75);
}

TEST_CASE("frame_path replaces every run of '#'", "[frames][names]") {
    using wsd::app::frame_path;
    CHECK(frame_path("out-####.png", 7) == "out-0007.png");
    CHECK(frame_path("out-#.png", 12345) == "out-12345.png");
    CHECK(frame_path("a##/b###.pfm", 5) == "a05/b005.pfm");
    CHECK(frame_path("plain.png", 5) == "plain.png");
}
