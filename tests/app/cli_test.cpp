// The `wsd` command through the real binary: exit statuses for every case of wsd-cli.md, the
// `check` ok line, `ast`, help and version, and that a failed command writes nothing.
#include <algorithm>
#include <catch2/catch.hpp>
#include <regex>
#include <sstream>

#include "app_test_util.h"

using namespace wsd::test;

TEST_CASE("wsd --version, --help and COMMAND --help succeed", "[cli]") {
    TempDir dir;
    RunResult r = run_wsd(dir, "--version");
    CHECK(r.status == 0);
    CHECK(r.out.find("wsd ") != std::string::npos);
    r = run_wsd(dir, "--help");
    CHECK(r.status == 0);
    for (const char* command : {"check", "ast", "render", "diff", "bench", "merge"})
        CHECK(r.out.find(command) != std::string::npos);
    r = run_wsd(dir, "render --help");
    CHECK(r.status == 0);
    CHECK(r.out.find("--supersamples") != std::string::npos);
    CHECK(r.out.find("--tile") != std::string::npos);
}

TEST_CASE("usage errors exit with 2", "[cli]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    CHECK(run_wsd(dir, "").status == 2);                        // no command
    CHECK(run_wsd(dir, "frobnicate").status == 2);              // unknown command
    CHECK(run_wsd(dir, "render s.wsd --bogus").status == 2);    // unknown option
    CHECK(run_wsd(dir, "render").status == 2);                  // missing argument
    CHECK(run_wsd(dir, "render s.wsd --width").status == 2);    // missing value
    CHECK(run_wsd(dir, "render s.wsd --width 0").status == 2);  // bad value
    CHECK(run_wsd(dir, "render s.wsd --width abc").status == 2);
    CHECK(run_wsd(dir, "render s.wsd --supersamples 0").status == 2);
    CHECK(run_wsd(dir, "render s.wsd --seed -1").status == 2);
    CHECK(run_wsd(dir, "render s.wsd --tile 5/4").status == 2);
    CHECK(run_wsd(dir, "render s.wsd --tile 0/4").status == 2);
    CHECK(run_wsd(dir, "render s.wsd --tile 1-4").status == 2);
    CHECK(run_wsd(dir, "render s.wsd --region 4,4,2,8").status == 2);
    CHECK(run_wsd(dir, "render s.wsd --region 0,0,17,16 -o r.pfm").status == 2);  // outside 16×16
    const RunResult ext = run_wsd(dir, "render s.wsd -o out.xyz");
    CHECK(ext.status == 2);
    CHECK(ext.err.find("out.xyz") != std::string::npos);
    CHECK(run_wsd(dir, "merge a.pfm").status == 2);  // -o is required
    CHECK(run_wsd(dir, "diff a.png").status == 2);
    // An empty value is a mistake, not the option left out.
    for (const char* option : {"-o", "--tile", "--region", "--stats-json", "--frames"}) {
        INFO(option);
        const RunResult empty = run_wsd(dir, std::string("render s.wsd --quiet ") + option + " ''");
        CHECK(empty.status == 2);
        CHECK(empty.err.find("an empty value") != std::string::npos);
    }
    CHECK(run_wsd(dir, "merge a.pfm -o ''").status == 2);
    CHECK(run_wsd(dir, "bench s.wsd -o ''").status == 2);
    // Nothing was written by any of them.
    const auto files = list_files(dir);
    CHECK(files == std::vector<std::string>{"s.wsd"});
}

TEST_CASE("an output that is a directory is named as one, with a file in it to use", "[cli]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    fs::create_directory(dir.path() / "out");
    fs::create_directory(dir.path() / "shot.png");
    for (const char* output : {"out", "out/", "new/"}) {
        INFO(output);
        const RunResult r = run_wsd(dir, std::string("render s.wsd --quiet -o ") + output);
        CHECK(r.status == 2);
        const std::string file = std::string(output).substr(0, 3) + "/image.png";
        CHECK(r.err.find("it is a directory; name an image file in it, such as '" + file + "'") !=
              std::string::npos);
    }
    const RunResult dash = run_wsd(dir, "render s.wsd --quiet -o -");
    CHECK(dash.status == 2);
    CHECK(dash.err.find("images are written to files, not to stdout") != std::string::npos);
    const RunResult merged = run_wsd(dir, "merge a.pfm -o out");
    CHECK(merged.status == 2);
    CHECK(merged.err.find("'out': it is a directory") != std::string::npos);
    // A directory whose name looks like an image: refused when it is written, and left as it was.
    const RunResult png = run_wsd(dir, "render s.wsd --quiet -o shot.png");
    CHECK(png.status != 0);
    CHECK(png.err.find("shot.png") != std::string::npos);
    CHECK(fs::is_directory(dir.path() / "shot.png"));
    CHECK(fs::is_empty(dir.path() / "shot.png"));
    CHECK(!fs::exists(dir.path() / "new"));
}

TEST_CASE("an unknown option is named even when a required argument is missing too", "[cli]") {
    TempDir dir;
    write_file(dir / "-x.wsd", tiny_scene());
    for (const char* args : {"check --bogus", "render --bogus", "fmt --bogus", "check --version", "-V"}) {
        INFO(args);
        const RunResult r = run_wsd(dir, args);
        CHECK(r.status == 2);
        CHECK(r.err.find("was not expected: -") != std::string::npos);
        CHECK(r.err.find("is required") == std::string::npos);
    }
    // A file whose name starts with '-': the message says how to name it.
    RunResult r = run_wsd(dir, "check -x.wsd");
    CHECK(r.status == 2);
    CHECK(r.err.find("was not expected: -x.wsd (to name the file '-x.wsd', write `-- -x.wsd` or "
                     "`./-x.wsd`)") != std::string::npos);
    CHECK(run_wsd(dir, "check -- -x.wsd").status == 0);
    // An option without its value says so in words, not in CLI11's type names.
    r = run_wsd(dir, "render ./-x.wsd --width");
    CHECK(r.status == 2);
    CHECK(r.err.find("wsd: error: --width needs a value\n") != std::string::npos);
    r = run_wsd(dir, "check ./-x.wsd -D");
    CHECK(r.status == 2);
    CHECK(r.err.find("wsd: error: --define needs a value\n") != std::string::npos);
}

TEST_CASE("check and fmt warn about a directory that holds no scene file", "[cli][check][fmt]") {
    TempDir dir;
    fs::create_directories(dir / "empty/sub");
    write_file(dir / "empty/notes.txt", "not a scene");
    for (const char* args : {"check empty", "check --format json empty", "fmt empty", "fmt --check empty"}) {
        INFO(args);
        const RunResult r = run_wsd(dir, args);
        CHECK(r.status == 0);
        CHECK(r.err == "wsd: warning: no .wsd or .wsdi file under 'empty'\n");
    }
    CHECK(run_wsd(dir, "check --format json empty").out == "[]\n");
    const RunResult quiet = run_wsd(dir, "check --no-warnings empty");
    CHECK(quiet.status == 0);
    CHECK(quiet.err.empty());
}

TEST_CASE("check prints the ok line with the counts", "[cli][check]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    write_file(dir / "frag.wsdi",
               "let red = material { color <1, 0, 0> }\nsphere { center <0,0,0> radius 1 material red }\n");
    const RunResult r = run_wsd(dir, "check s.wsd frag.wsdi");
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    const std::regex line(
        "s\\.wsd: ok \xE2\x80\x94 2 objects, 0 triangles, 1 light, 2 materials\n"
        "frag\\.wsdi: ok \xE2\x80\x94 1 object, 0 triangles, 0 lights, 1 material\n");
    CHECK(std::regex_match(r.out, line));
}

TEST_CASE("check: scene errors exit 1 with diagnostics, unreadable files 3, worst status wins",
          "[cli][check]") {
    TempDir dir;
    write_file(dir / "good.wsd", tiny_scene());
    write_file(dir / "bad.wsd",
               "camera { position <0,0,-1> look_at <0,0,0> }\nsphere { center <0,0,0> radus 1 }\n");
    RunResult r = run_wsd(dir, "check bad.wsd");
    CHECK(r.status == 1);
    CHECK(r.out.empty());
    CHECK(r.err.find("bad.wsd:2:") != std::string::npos);
    CHECK(r.err.find("radus") != std::string::npos);

    r = run_wsd(dir, "check good.wsd bad.wsd");
    CHECK(r.status == 1);
    CHECK(r.out.find("good.wsd: ok") != std::string::npos);

    r = run_wsd(dir, "check missing.wsd");
    CHECK(r.status == 3);
    CHECK(r.err.find("missing.wsd") != std::string::npos);

    r = run_wsd(dir, "check bad.wsd missing.wsd good.wsd");
    CHECK(r.status == 3);
    CHECK(r.out.find("good.wsd: ok") != std::string::npos);

    // A scene that includes a missing file is a scene error (1), not an I/O error.
    write_file(dir / "inc.wsd", "include \"nowhere.wsdi\"\n" + tiny_scene());
    CHECK(run_wsd(dir, "check inc.wsd").status == 1);
}

TEST_CASE("check reads a scene from stdin with -", "[cli][check]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    const std::string out = dir / "o.txt";
    const int raw = std::system(("cd " + shell_quote(dir.path().string()) + " && cat s.wsd | " +
                                 shell_quote(WSD_BINARY) + " check - > o.txt 2>&1")
                                    .c_str());
    CHECK(WEXITSTATUS(raw) == 0);
    CHECK(read_file(out).find(": ok \xE2\x80\x94 2 objects") != std::string::npos);
}

TEST_CASE("ast prints one node per line with positions", "[cli][ast]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    RunResult r = run_wsd(dir, "ast s.wsd");
    CHECK(r.status == 0);
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') > 5);
    CHECK(r.out.find("@1:1") != std::string::npos);
    const RunResult again = run_wsd(dir, "ast s.wsd");
    CHECK(again.out == r.out);
    write_file(dir / "broken.wsd", "sphere { center <0,0,0> radius }\n}\n");
    r = run_wsd(dir, "ast broken.wsd");
    CHECK(r.status == 1);
    CHECK(r.err.find("broken.wsd:") != std::string::npos);
    CHECK(run_wsd(dir, "ast nothing.wsd").status == 3);
}

TEST_CASE("output that cannot be written to stdout exits 3 and says so", "[cli]") {
    if (!fs::exists("/dev/full")) return;  // writes to it fail with ENOSPC
    TempDir dir;
    write_file(dir / "ok.wsdi", "let a = 1\n");
    write_file(dir / "s.wsd", tiny_scene());
    for (const char* args : {"fmt ok.wsdi", "check ok.wsdi", "check --format json ok.wsdi", "ast ok.wsdi",
                             "check --effects s.wsd", "--help"}) {
        INFO(args);
        const std::string command = "cd " + shell_quote(dir.path().string()) + " && " +
                                    shell_quote(WSD_BINARY) + " " + args + " >/dev/full 2>" +
                                    shell_quote(dir / "err");
        const int raw = std::system(command.c_str());
        REQUIRE(WIFEXITED(raw));
        CHECK(WEXITSTATUS(raw) == 3);
        CHECK(read_file(dir / "err").find("wsd: error: cannot write standard output") != std::string::npos);
    }
}

TEST_CASE("an internal error exits 4 and asks for a bug report", "[cli]") {
    TempDir dir;
    const RunResult r = run_wsd(dir, "--version", "WSD_TEST_INTERNAL_ERROR=1");
    CHECK(r.status == 4);
    CHECK(r.err.find("bug") != std::string::npos);
}

TEST_CASE("check --effects names the effects and the objects that call for each", "[cli][check]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    const RunResult r = run_wsd(dir, "check --effects s.wsd");
    CHECK(r.status == 0);
    std::istringstream lines(r.out);
    std::string line;
    bool reflection = false, texture = false, soft = false;
    while (std::getline(lines, line)) {
        if (line.find("reflection") != std::string::npos)
            reflection = line.find("sphere at s.wsd:5:1") != std::string::npos;
        if (line.find("textures") != std::string::npos)
            texture = line.find("plane at s.wsd:4:1") != std::string::npos;
        if (line.find("area") != std::string::npos) soft = true;
    }
    CHECK(reflection);
    CHECK(texture);
    CHECK(soft);
    // Without the flag, only the ok line.
    const std::string plain = run_wsd(dir, "check s.wsd").out;
    CHECK(std::count(plain.begin(), plain.end(), '\n') == 1);
}

TEST_CASE("an unknown command is named, with a did-you-mean; wsd help [COMMAND] works", "[cli]") {
    TempDir dir;
    write_file(dir / "x.wsd", tiny_scene());
    RunResult r = run_wsd(dir, "rendr x.wsd");
    CHECK(r.status == 2);
    CHECK(r.err.find("unknown command 'rendr'; did you mean 'render'?") != std::string::npos);
    r = run_wsd(dir, "frobnicate");
    CHECK(r.status == 2);
    CHECK(r.err.find("unknown command 'frobnicate'") != std::string::npos);
    r = run_wsd(dir, "");
    CHECK(r.status == 2);
    CHECK(r.err.find("a command is required: check ast render") != std::string::npos);

    r = run_wsd(dir, "help");
    CHECK(r.status == 0);
    for (const char* command : {"check", "ast", "render", "diff", "bench", "merge"})
        CHECK(r.out.find(command) != std::string::npos);
    r = run_wsd(dir, "help render");
    CHECK(r.status == 0);
    CHECK(r.out.find("Usage: wsd render") != std::string::npos);
    CHECK(r.out.find("--supersamples") != std::string::npos);
    r = run_wsd(dir, "help rendr");
    CHECK(r.status == 2);
    CHECK(r.err.find("unknown command 'rendr'; did you mean 'render'?") != std::string::npos);
}

TEST_CASE("an integer option given something else says it is not an integer", "[cli]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    for (const char* option :
         {"--width", "--height", "--supersamples", "--light-samples", "--max-depth", "--seed", "--threads"}) {
        const RunResult r = run_wsd(dir, std::string("render s.wsd ") + option + " abc");
        CHECK(r.status == 2);
        CHECK(r.err.find(std::string(option) + ": 'abc' is not an integer") != std::string::npos);
    }
    for (const char* option : {"--repeat", "--reference-supersamples", "--reference-light-samples",
                               "--reference-depth", "--threads", "--width", "--height"}) {
        const RunResult r = run_wsd(dir, std::string("bench s.wsd ") + option + " 1.5");
        CHECK(r.status == 2);
        CHECK(r.err.find(std::string(option) + ": '1.5' is not an integer") != std::string::npos);
    }
    const RunResult r = run_wsd(dir, "render s.wsd --width 0");
    CHECK(r.status == 2);
    CHECK(r.err.find("--width: 0 is not in the range 1 to 100000") != std::string::npos);
}

TEST_CASE("an option given twice, and a number option given something else, say so in wsd's words", "[cli]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    struct Case {
        const char* args;
        const char* message;
    };
    const Case cases[] = {
        {"--aov albedo --aov depth", "--aov was given 2 times; it takes one value"},
        {"--frames 1-2 --frames 1-3", "--frames was given 2 times; it takes one value"},
        {"--clock 0.1 --clock 0.2 --clock 0.3", "--clock was given 3 times; it takes one value"},
        {"--clock abc", "--clock: 'abc' is not a number"},
        {"--clock ''", "--clock: '' is not a number"},
        {"--clock 0x10", "--clock: '0x10' is not a number"},  // decimal, as scenes write numbers
        {"--target-error 0x1p-7", "--target-error: '0x1p-7' is not a number"},
    };
    for (const Case& c : cases) {
        INFO(c.args);
        const RunResult r = run_wsd(dir, std::string("render s.wsd ") + c.args);
        CHECK(r.status == 2);
        CHECK(r.err.find(c.message) != std::string::npos);
        CHECK(r.err.find("At Most") == std::string::npos);
        CHECK(r.err.find("Could not convert") == std::string::npos);
    }
}
