// read_whole_file and quoted: the one whole-file reader and the one message quoting that every
// module uses.
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "render/file_util.h"
#include "render/text_util.h"

namespace fs = std::filesystem;
using wsd::render::FileBytes;
using wsd::render::read_whole_file;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        char name[] = "/tmp/wsd-file-util-XXXXXX";
        path = mkdtemp(name);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

}  // namespace

TEST_CASE("read_whole_file reads regular files and pipes whole, and says why it cannot", "[file_util]") {
    TempDir dir;
    const std::string text = std::string("line 1\n\0binary\xff", 15) + std::string(200000, 'x');
    std::ofstream(dir.path / "a.txt", std::ios::binary) << text;
    std::ofstream(dir.path / "empty.txt", std::ios::binary).flush();
    FileBytes bytes;
    std::string reason;
    REQUIRE(read_whole_file((dir.path / "a.txt").string(), bytes, reason));
    CHECK(bytes.view() == text);
    REQUIRE(read_whole_file((dir.path / "empty.txt").string(), bytes, reason));
    CHECK(bytes.view().empty());

    CHECK_FALSE(read_whole_file((dir.path / "missing.txt").string(), bytes, reason));
    CHECK(reason == "No such file or directory");
    CHECK_FALSE(read_whole_file(dir.path.string(), bytes, reason));
    CHECK(reason == "it is a directory");
    CHECK_FALSE(read_whole_file("/dev/zero", bytes, reason));  // would never end
    CHECK(reason == "it is not a regular file");

    // A pipe has no size: it is read until its writer closes it.
    const std::string fifo = (dir.path / "pipe").string();
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    std::thread writer([&] { std::ofstream(fifo, std::ios::binary) << text; });
    const bool ok = read_whole_file(fifo, bytes, reason);
    writer.join();
    REQUIRE(ok);
    CHECK(bytes.view() == text);
}

TEST_CASE("read_whole_file reads a file whose size says nothing until its end", "[file_util]") {
    // The files of /proc have the size 0 and bytes all the same.
    FileBytes bytes;
    std::string reason;
    REQUIRE(read_whole_file("/proc/self/status", bytes, reason));
    CHECK(bytes.view().find("Name:") == 0);
    CHECK(bytes.view().find("VmHWM:") != std::string_view::npos);
    REQUIRE(read_whole_file("/proc/self/maps", bytes, reason));  // longer than the first buffer
    CHECK(bytes.view().size() > 1000);
    CHECK(bytes.view().back() == '\n');
}

TEST_CASE("quoted puts single quotes around any text, and quoted_cut cuts long text", "[file_util]") {
    using wsd::render::quoted;
    CHECK(quoted("a b") == "'a b'");
    CHECK(quoted(std::string("path/x.wsd")) == "'path/x.wsd'");
    CHECK(quoted(std::string_view("é")) == "'é'");
    CHECK(wsd::render::quoted_cut("abcdef", 3) == "'abc...'");
    CHECK(wsd::render::quoted_cut("ab\xc3\xa9", 3) == "'ab...'");  // never inside a UTF-8 character
    CHECK(wsd::render::quoted_cut("abc", 3) == "'abc'");
}
