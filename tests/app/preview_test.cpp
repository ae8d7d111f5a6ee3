// `wsd preview` without a browser: its startup errors through the real binary (a missing scene, a
// port in use), the stages of the progressive render, the PNG it serves, the watcher (saves in
// place and by rename) and the render loop publishing images and diagnostics. The page itself is
// tested in headless chromium (preview_browser.sh).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "app/preview_render.h"
#include "app/preview_state.h"
#include "app/preview_watch.h"
#include "app_test_util.h"

using namespace wsd::test;

namespace {

const char* const kScene = R"(settings { width 64 height 48 }
camera { position <0, 0, -5>  look_at <0, 0, 0>  up <0, 1, 0>  fov 50 }
light point { position <4, 6, -8> }
sphere { center <0, 0, 0>  radius 1.5  material material { color <1, 0, 0> } }
)";

// A socket listening on a free port of 127.0.0.1 (the port another server would find in use).
struct Listener {
    int fd = -1;
    int port = 0;
    Listener() {
        fd = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t size = sizeof address;
        if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&address), size) != 0 || ::listen(fd, 1) != 0 ||
            ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size) != 0)
            throw std::runtime_error("cannot listen on a free port");
        port = ntohs(address.sin_port);
    }
    ~Listener() { ::close(fd); }
};

// Waits (up to 20 s) until `done(snapshot)`; the last snapshot.
template <class Predicate>
wsd::app::PreviewSnapshot wait_until(const wsd::app::PreviewState& state, Predicate done) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    wsd::app::PreviewSnapshot s = state.snapshot();
    while (!done(s) && std::chrono::steady_clock::now() < deadline) {
        bool stopping = false;
        s = state.wait_change(s.version, 200, stopping);
    }
    return s;
}

}  // namespace

TEST_CASE("preview: a missing scene and a port in use are clear errors", "[preview]") {
    TempDir dir;
    RunResult r = run_wsd(dir, "preview missing.wsd --port 0", "timeout 20");
    CHECK(r.status == 3);
    CHECK(r.err.find("missing.wsd") != std::string::npos);

    write_file(dir / "s.wsd", kScene);
    Listener taken;
    r = run_wsd(dir, "preview s.wsd --port " + std::to_string(taken.port), "timeout 20");
    CHECK(r.status == 3);
    CHECK(r.err.find("127.0.0.1:" + std::to_string(taken.port)) != std::string::npos);
    CHECK(r.err.find("in use") != std::string::npos);

    r = run_wsd(dir, "preview s.wsd --port 70000");
    CHECK(r.status == 2);
}

TEST_CASE("preview stages go from an eighth of the size to the full size", "[preview]") {
    const std::vector<wsd::app::PreviewStage> big = wsd::app::preview_stages(1200, 800);
    REQUIRE(big.size() == 4);
    CHECK(big[0].divisor == 8);
    CHECK(big[0].coarse);
    CHECK(big[2].divisor == 2);
    CHECK(big[3].divisor == 1);
    CHECK_FALSE(big[3].coarse);
    // A side below 8 pixels has no coarse stage.
    const std::vector<wsd::app::PreviewStage> small = wsd::app::preview_stages(40, 20);
    REQUIRE(small.size() == 2);
    CHECK(small[0].divisor == 2);
    CHECK(wsd::app::preview_stages(10, 10).size() == 1);
}

TEST_CASE("preview PNG encoding is sRGB 8-bit", "[preview]") {
    const std::string png = wsd::app::encode_png(2, 1, {1.0f, 0.0f, 0.5f, 0.0f, 2.0f, -1.0f});
    REQUIRE(png.size() > 8);
    CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
}

TEST_CASE("the watcher sees saves in place and by rename, of watched files only", "[preview]") {
    TempDir dir;
    write_file(dir / "a.wsd", "1");
    write_file(dir / "b.wsdi", "1");
    write_file(dir / "other.txt", "1");
    wsd::app::FileWatcher watcher;
    REQUIRE(watcher.ok());
    watcher.watch({dir / "a.wsd", dir / "b.wsdi"}, false);
    CHECK_FALSE(watcher.wait(0));

    write_file(dir / "a.wsd", "2");
    CHECK(watcher.wait(5000));
    write_file(dir / "b.wsdi.tmp", "2");
    CHECK_FALSE(watcher.wait(50));  // another name
    fs::rename(dir / "b.wsdi.tmp", dir / "b.wsdi");
    CHECK(watcher.wait(5000));
    write_file(dir / "other.txt", "2");
    CHECK_FALSE(watcher.wait(50));

    watcher.watch({dir / "a.wsd"}, true);  // a failed load: any file of the directory counts
    write_file(dir / "other.txt", "3");
    CHECK(watcher.wait(5000));
}

TEST_CASE("the preview render loop publishes stages, diagnostics and the last good image", "[preview]") {
    TempDir dir;
    const std::string scene = dir / "s.wsd";
    write_file(scene, kScene);
    wsd::app::PreviewState state;
    wsd::app::PreviewRenderer renderer(state, scene, 2);
    std::thread loop([&] { renderer.run(); });
    renderer.request();
    wsd::app::PreviewSnapshot s =
        wait_until(state, [](const auto& x) { return x.generation == 1 && x.phase == "done"; });
    CHECK(s.phase == "done");
    CHECK(s.stage == 3);  // 16×12, 32×24, then 64×48
    CHECK(s.stages == 3);
    CHECK(s.image_width == 64);
    CHECK(s.image_height == 48);
    CHECK(s.diagnostics.empty());
    CHECK(s.stats_json.find("\"camera_rays\": 3072") != std::string::npos);
    const std::string first = state.image_png();
    std::vector<std::string> files;
    bool whole = true;
    CHECK(renderer.take_watch_list(files, whole));
    CHECK(files == std::vector<std::string>{scene});
    CHECK_FALSE(whole);

    write_file(scene, std::string(kScene) + "sphere {\n");
    renderer.request();
    s = wait_until(state, [](const auto& x) { return x.generation == 2 && x.phase == "error"; });
    CHECK(s.diagnostics.find("s.wsd:6:1: error:") != std::string::npos);
    CHECK(s.image_generation == 1);  // the last good image stays
    CHECK(state.image_png() == first);
    CHECK(renderer.take_watch_list(files, whole));
    CHECK(whole);

    std::string blue = kScene;
    blue.replace(blue.find("<1, 0, 0>"), 9, "<0, 0, 1>");
    write_file(scene, blue);
    renderer.request();
    s = wait_until(state, [](const auto& x) { return x.generation == 3 && x.phase == "done"; });
    CHECK(s.diagnostics.empty());
    CHECK(s.image_generation == 3);
    CHECK(state.image_png() != first);
    renderer.stop();
    loop.join();
}

TEST_CASE("a preview of a scene whose texture is missing watches the texture", "[preview]") {
    TempDir dir;
    const std::string scene = dir / "s.wsd";
    std::string text = kScene;
    text.replace(text.find("color <1, 0, 0>"), 15, "texture image \"tex/t.png\"");
    write_file(scene, text);
    wsd::app::PreviewState state;
    wsd::app::PreviewRenderer renderer(state, scene, 1);
    std::thread loop([&] { renderer.run(); });
    renderer.request();
    const wsd::app::PreviewSnapshot s =
        wait_until(state, [](const auto& x) { return x.generation == 1 && x.phase == "error"; });
    CHECK(s.diagnostics.find("tex/t.png") != std::string::npos);
    std::vector<std::string> files;
    bool whole = false;
    CHECK(renderer.take_watch_list(files, whole));
    CHECK(files == std::vector<std::string>{scene, dir / "tex/t.png"});
    CHECK(whole);
    renderer.stop();
    loop.join();
}

TEST_CASE("a preview of a scene whose mesh file is missing or broken watches the mesh file", "[preview]") {
    TempDir dir;
    const std::string scene = dir / "s.wsd";
    write_file(scene, std::string(kScene) + "mesh { file \"models/m.obj\"  material { color <0, 1, 0> } }\n");
    wsd::app::PreviewState state;
    wsd::app::PreviewRenderer renderer(state, scene, 1);
    std::thread loop([&] { renderer.run(); });
    const std::vector<std::string> expected{scene, dir / "models/m.obj"};
    std::vector<std::string> files;
    bool whole = false;
    // Missing: the load fails while lowering, before anything names the file but the mesh itself.
    renderer.request();
    wsd::app::PreviewSnapshot s =
        wait_until(state, [](const auto& x) { return x.generation == 1 && x.phase == "error"; });
    CHECK(s.diagnostics.find("cannot read mesh file") != std::string::npos);
    CHECK(renderer.take_watch_list(files, whole));
    CHECK(files == expected);
    CHECK(whole);
    // Broken: the same.
    fs::create_directories(dir / "models");
    write_file(dir / "models/m.obj", "v 0 0 0\nf 1 2 3\n");
    renderer.request();
    s = wait_until(state, [](const auto& x) { return x.generation == 2 && x.phase == "error"; });
    CHECK(s.diagnostics.find("out of range") != std::string::npos);
    CHECK_FALSE(renderer.take_watch_list(files, whole));  // unchanged: the mesh file is still watched
    // Fixed: the image comes back, the mesh still watched.
    write_file(dir / "models/m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    renderer.request();
    s = wait_until(state, [](const auto& x) { return x.generation == 3 && x.phase == "done"; });
    CHECK(s.diagnostics.empty());
    CHECK(renderer.take_watch_list(files, whole));
    CHECK(files == expected);
    CHECK_FALSE(whole);
    renderer.stop();
    loop.join();
}

TEST_CASE("preview: an empty host and a scene that is not a regular file are refused at once", "[preview]") {
    TempDir dir;
    write_file(dir / "s.wsd", kScene);
    RunResult r = run_wsd(dir, "preview s.wsd --port 0 --host ''", "timeout 20");
    CHECK(r.status == 2);
    CHECK(r.err.find("--host") != std::string::npos);
    r = run_wsd(dir, "preview /dev/zero --port 0", "timeout 20");
    CHECK(r.status == 3);
    CHECK(r.err.find("not a regular file") != std::string::npos);
}

TEST_CASE("preview: a bad --define is a usage error at once", "[preview]") {
    TempDir dir;
    write_file(dir / "s.wsd", kScene);
    RunResult r = run_wsd(dir, "preview s.wsd --port 0 -D w", "timeout 20");
    CHECK(r.status == 2);
    CHECK(r.err.find("NAME=EXPR") != std::string::npos);
    r = run_wsd(dir, "preview s.wsd --port 0 --define 'w=1 +'", "timeout 20");
    CHECK(r.status == 2);
    CHECK(r.err.find("--define w") != std::string::npos);
}
