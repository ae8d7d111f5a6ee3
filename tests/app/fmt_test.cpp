// `wsd fmt` and `wsd check --format json` through the real binary: printing, --check and -i
// (exit statuses, files left untouched, mtime kept, the rewrite by rename, stopped by a signal),
// files with syntax errors reported as `check` reports them, directory arguments, and the JSON
// diagnostics.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <nlohmann/json.hpp>
#include <thread>

#include "app_test_util.h"

using namespace wsd::test;

namespace {

// Waits, up to 30 s, until process `pid` runs `cmdline` (its arguments, each ended by '\0') and
// catches signal `sig` (its handler is installed: the SigCgt mask of /proc/PID/status), so that
// a signal sent then is the program's to handle. Before exec the child still has the test
// runner's handlers, hence the command line. A fixed delay raced a slow start (a sanitized build
// on a busy machine). False on timeout.
bool wait_until_catches(pid_t pid, const std::string& cmdline, int sig) {
    const std::string proc = "/proc/" + std::to_string(pid);
    for (int i = 0; i < 3000; ++i) {
        std::ifstream args(proc + "/cmdline");
        const std::string running((std::istreambuf_iterator<char>(args)), std::istreambuf_iterator<char>());
        std::ifstream in(proc + "/status");
        std::string line;
        while (running == cmdline && std::getline(in, line))
            if (line.rfind("SigCgt:", 0) == 0 && (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1) & 1))
                return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

const std::string messy = "sphere{radius 1 center<0,1,0>}\nlet a=1+2\n";
const std::string canonical = "sphere { radius 1  center <0, 1, 0> }\nlet a = 1 + 2\n";

// Sets the modification time of `path` an hour back, so a rewrite would show.
fs::file_time_type age(const std::string& path) {
    const fs::file_time_type old = fs::last_write_time(path) - std::chrono::hours(1);
    fs::last_write_time(path, old);
    return old;
}

ino_t inode(const std::string& path) {
    struct stat st {};
    ::stat(path.c_str(), &st);
    return st.st_ino;
}

}  // namespace

TEST_CASE("fmt prints the canonical form of each file", "[cli][fmt]") {
    TempDir dir;
    write_file(dir / "a.wsd", messy);
    write_file(dir / "b.wsdi", "let m=material{color<1,0,0>}");
    const RunResult r = run_wsd(dir, "fmt a.wsd b.wsdi");
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(r.out == canonical + "let m = material { color <1, 0, 0> }\n");
    CHECK(read_file(dir / "a.wsd") == messy);  // printing changes no file
    const RunResult piped = run_wsd(dir, "fmt - < a.wsd");
    CHECK(piped.status == 0);
}

TEST_CASE("fmt --check changes nothing and names each file that is not canonical", "[cli][fmt]") {
    TempDir dir;
    write_file(dir / "messy.wsd", messy);
    write_file(dir / "clean.wsd", canonical);
    const auto messy_time = age(dir / "messy.wsd");
    const auto clean_time = age(dir / "clean.wsd");
    RunResult r = run_wsd(dir, "fmt --check clean.wsd messy.wsd");
    CHECK(r.status == 1);
    CHECK(r.out == "messy.wsd\n");
    CHECK(read_file(dir / "messy.wsd") == messy);
    CHECK(fs::last_write_time(dir / "messy.wsd") == messy_time);
    CHECK(fs::last_write_time(dir / "clean.wsd") == clean_time);
    r = run_wsd(dir, "fmt --check clean.wsd");
    CHECK(r.status == 0);
    CHECK(r.out.empty());
}

TEST_CASE("fmt -i rewrites by rename, keeps permissions, leaves canonical files untouched", "[cli][fmt]") {
    TempDir dir;
    write_file(dir / "messy.wsd", messy);
    write_file(dir / "clean.wsd", canonical);
    fs::permissions(dir / "messy.wsd", fs::perms(0640));
    const auto clean_time = age(dir / "clean.wsd");
    const ino_t messy_inode = inode(dir / "messy.wsd"), clean_inode = inode(dir / "clean.wsd");
    RunResult r = run_wsd(dir, "fmt -i messy.wsd clean.wsd");
    CHECK(r.status == 0);
    CHECK(r.out.empty());
    CHECK(read_file(dir / "messy.wsd") == canonical);
    CHECK(inode(dir / "messy.wsd") != messy_inode);  // a new file renamed over the old one
    CHECK((fs::status(dir / "messy.wsd").permissions() & fs::perms::all) == fs::perms(0640));
    CHECK(inode(dir / "clean.wsd") == clean_inode);
    CHECK(fs::last_write_time(dir / "clean.wsd") == clean_time);
    std::vector<std::string> files = list_files(dir);
    std::sort(files.begin(), files.end());
    CHECK(files == std::vector<std::string>{"clean.wsd", "messy.wsd"});  // no temporary left
    r = run_wsd(dir, "fmt --check messy.wsd clean.wsd");
    CHECK(r.status == 0);
    CHECK(run_wsd(dir, "fmt -i --check messy.wsd").status == 2);
    CHECK(run_wsd(dir, "fmt -i -").status == 2);
}

TEST_CASE("fmt -i through a symbolic link rewrites the file it leads to and keeps the link", "[cli][fmt]") {
    TempDir dir;
    fs::create_directories(dir / "lib");
    write_file(dir / "lib/target.wsd", messy);
    fs::create_symlink("lib/target.wsd", dir / "link.wsd");
    fs::create_symlink("target.wsd", dir / "lib/near.wsd");
    RunResult r = run_wsd(dir, "fmt -i link.wsd");
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(fs::is_symlink(dir / "link.wsd"));
    CHECK(fs::read_symlink(dir / "link.wsd") == "lib/target.wsd");
    CHECK(read_file(dir / "lib/target.wsd") == canonical);
    write_file(dir / "lib/target.wsd", messy);
    r = run_wsd(dir, "fmt -i lib/near.wsd");  // a link relative to its own directory
    CHECK(r.status == 0);
    CHECK(fs::is_symlink(dir / "lib/near.wsd"));
    CHECK(read_file(dir / "lib/target.wsd") == canonical);
    std::vector<std::string> files = list_files(dir);
    std::sort(files.begin(), files.end());
    CHECK(files == std::vector<std::string>{"lib", "link.wsd"});
}

TEST_CASE("fmt -i stopped by SIGINT or SIGTERM exits 130 or 143 and leaves no temporary file",
          "[cli][fmt][signal]") {
    TempDir dir;
    std::string big;
    // About two seconds of formatting on an idle two-core machine: the signal, 100 ms after wsd
    // installs its handler, comes well before the end.
    for (int i = 0; i < 800000; ++i)
        big += "let a" + std::to_string(i) + "=<1,2,3>*(" + std::to_string(i) + "-1)\n";
    write_file(dir / "big.wsd", big);
    fs::permissions(dir / "big.wsd", fs::perms(0600));
    for (const auto& [signal_number, expected] : {std::pair{SIGINT, 130}, std::pair{SIGTERM, 143}}) {
        INFO(expected);
        const pid_t pid = ::fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {
            const int null = ::open("/dev/null", O_WRONLY);
            if (::chdir(dir.path().c_str()) != 0 || null < 0) ::_exit(127);
            ::dup2(null, 1);
            ::dup2(null, 2);
            ::execl(WSD_BINARY, WSD_BINARY, "fmt", "-i", "big.wsd", static_cast<char*>(nullptr));
            ::_exit(127);
        }
        // Once wsd handles the signal, and a little later, well into the formatting.
        const bool catches = wait_until_catches(
            pid, std::string(WSD_BINARY) + '\0' + "fmt" + '\0' + "-i" + '\0' + "big.wsd" + '\0',
            signal_number);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        ::kill(pid, signal_number);
        int raw = 0;
        ::waitpid(pid, &raw, 0);
        REQUIRE(catches);
        REQUIRE(WIFEXITED(raw));  // it stopped itself rather than being killed by the signal
        CHECK(WEXITSTATUS(raw) == expected);
        CHECK(list_files(dir) == std::vector<std::string>{"big.wsd"});
        CHECK(read_file(dir / "big.wsd") == big);
    }
}

TEST_CASE("fmt refuses a file with syntax errors as check reports it and writes nothing", "[cli][fmt]") {
    TempDir dir;
    const std::string broken = "sphere { radius 1\nlet = 2\n";
    write_file(dir / "broken.wsd", broken);
    write_file(dir / "messy.wsd", messy);
    const auto broken_time = age(dir / "broken.wsd");
    const RunResult check = run_wsd(dir, "check broken.wsd");
    REQUIRE(check.status == 1);
    for (const char* mode : {"", "-i ", "--check "}) {
        INFO(mode);
        const RunResult r = run_wsd(dir, std::string("fmt ") + mode + "broken.wsd");
        CHECK(r.status == 1);
        CHECK(r.err == check.err);
        CHECK(r.out.empty());
        CHECK(read_file(dir / "broken.wsd") == broken);
        CHECK(fs::last_write_time(dir / "broken.wsd") == broken_time);
    }
    // The other files of the run are still formatted.
    const RunResult r = run_wsd(dir, "fmt -i broken.wsd messy.wsd");
    CHECK(r.status == 1);
    CHECK(read_file(dir / "messy.wsd") == canonical);
    CHECK(run_wsd(dir, "fmt missing.wsd").status == 3);
}

TEST_CASE("fmt and check take directories: their .wsd and .wsdi files, recursively", "[cli][fmt]") {
    TempDir dir;
    fs::create_directories(dir / "scenes/lib");
    write_file(dir / "scenes/b.wsd", messy);
    write_file(dir / "scenes/a.wsd", canonical);
    write_file(dir / "scenes/lib/m.wsdi", "let m=material{color<1,0,0>}");
    write_file(dir / "scenes/notes.txt", "not a scene {");
    RunResult r = run_wsd(dir, "fmt --check scenes");
    CHECK(r.status == 1);
    CHECK(r.out == "scenes/b.wsd\nscenes/lib/m.wsdi\n");
    r = run_wsd(dir, "fmt -i scenes");
    CHECK(r.status == 0);
    CHECK(run_wsd(dir, "fmt --check scenes").status == 0);
    CHECK(read_file(dir / "scenes/notes.txt") == "not a scene {");
    r = run_wsd(dir, "check --format json scenes");
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j.size() == 3);
    CHECK(j[0]["file"] == "scenes/a.wsd");
    CHECK(j[2]["file"] == "scenes/lib/m.wsdi");
}

TEST_CASE("check --format json: fields, notes with the include chain, clean files", "[cli][check]") {
    TempDir dir;
    fs::create_directories(dir / "lib");
    write_file(dir / "lib/broken.wsdi", "let m = 1\nsphere { radius 1\n");
    write_file(dir / "main.wsd", "// a scene\ninclude \"lib/broken.wsdi\"\n");
    write_file(dir / "clean.wsd", tiny_scene());
    const RunResult text = run_wsd(dir, "check main.wsd clean.wsd");
    const RunResult r = run_wsd(dir, "check --format json main.wsd clean.wsd");
    CHECK(r.status == 1);
    CHECK(r.status == text.status);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j.is_array());
    REQUIRE(j.size() == 2);

    const nlohmann::json& bad = j[0];
    CHECK(bad["file"] == "main.wsd");
    CHECK(bad["ok"] == false);
    REQUIRE(bad["diagnostics"].size() == 1);
    const nlohmann::json& d = bad["diagnostics"][0];
    CHECK(d["severity"] == "error");
    CHECK(d["message"].get<std::string>().find("expected '}'") != std::string::npos);
    CHECK(text.err.find(d["message"].get<std::string>()) != std::string::npos);
    CHECK(d["file"] == "lib/broken.wsdi");
    CHECK(d["line"] == 3);  // at the end of the file
    CHECK(d["column"] == 1);
    CHECK(d["end_line"] == 3);
    CHECK(d["end_column"] == 1);
    CHECK(d["help"].is_string());
    REQUIRE(d["notes"].size() == 2);
    CHECK(d["notes"][0]["message"] == "to match this '{'");
    CHECK(d["notes"][0]["file"] == "lib/broken.wsdi");
    CHECK(d["notes"][0]["line"] == 2);
    CHECK(d["notes"][0]["column"] == 8);
    CHECK(d["notes"][1]["message"] == "in file included from here");
    CHECK(d["notes"][1]["file"] == "main.wsd");
    CHECK(d["notes"][1]["line"] == 2);
    CHECK(d["notes"][1]["column"] == 9);
    for (const char* key :
         {"severity", "message", "file", "line", "column", "end_line", "end_column", "help", "notes"})
        CHECK(d.contains(key));

    CHECK(j[1]["file"] == "clean.wsd");
    CHECK(j[1]["ok"] == true);
    CHECK(j[1]["diagnostics"].empty());
    CHECK(run_wsd(dir, "check --format json clean.wsd").status == 0);
    CHECK(run_wsd(dir, "check --format xml clean.wsd").status == 2);
}

TEST_CASE("check --format json: a span's end is exclusive, help lines and warnings kept", "[cli][check]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene() + "sphere { radius 1  colour <1, 0, 0> }\n");
    const RunResult text = run_wsd(dir, "check s.wsd");
    const RunResult r = run_wsd(dir, "check --format json s.wsd");
    CHECK(r.status == text.status);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j.size() == 1);
    REQUIRE_FALSE(j[0]["diagnostics"].empty());
    const nlohmann::json& d = j[0]["diagnostics"][0];
    CHECK(d["line"] == 6);
    CHECK(d["column"] == 20);
    CHECK(d["end_line"] == 6);
    CHECK(d["end_column"] == 26);  // "colour" is 6 columns
    CHECK(text.err.find(d["message"].get<std::string>()) != std::string::npos);
    CHECK(d["help"] == "a colour belongs in a material: write 'material { color ... }'");
    size_t text_errors = 0;
    for (size_t at = text.err.find(": error: "); at != std::string::npos;
         at = text.err.find(": error: ", at + 1))
        ++text_errors;
    CHECK(j[0]["diagnostics"].size() == text_errors);  // the same diagnostics as the text form
    const RunResult unreadable = run_wsd(dir, "check --format json missing.wsd");
    CHECK(unreadable.status == 3);
    const nlohmann::json u = nlohmann::json::parse(unreadable.out);
    CHECK(u[0]["ok"] == false);
    CHECK(u[0]["diagnostics"][0]["severity"] == "error");
}
