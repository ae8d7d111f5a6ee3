// write_file_atomic called directly: the permission bits it gives the file, and a cancel flag
// that stops it with nothing left behind.
#include "app/io_util.h"

#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>

#include "app_test_util.h"

using namespace wsd::test;

namespace {

unsigned mode_of(const std::string& path) {
    struct stat st {};
    ::stat(path.c_str(), &st);
    return st.st_mode & 07777;
}

// Sets the umask for the life of the object.
struct Umask {
    mode_t previous;
    explicit Umask(mode_t mask) : previous(::umask(mask)) {}
    ~Umask() { ::umask(previous); }
};

}  // namespace

TEST_CASE("write_file_atomic gives the file exactly the bits asked for, else 0644 less the umask",
          "[io_util]") {
    TempDir dir;
    const Umask mask(0077);
    std::string error;
    wsd::app::AtomicWrite how;
    how.mode = 0640;  // the umask would take the group's read
    REQUIRE(wsd::app::write_file_atomic(dir / "exact.txt", "a", error, how));
    CHECK(mode_of(dir / "exact.txt") == 0640);
    how.mode = 0600;
    REQUIRE(wsd::app::write_file_atomic(dir / "exact.txt", "b", error, how));
    CHECK(mode_of(dir / "exact.txt") == 0600);
    REQUIRE(wsd::app::write_file_atomic(dir / "new.txt", "c", error));
    CHECK(mode_of(dir / "new.txt") == 0600);
    std::vector<std::string> files = list_files(dir);
    std::sort(files.begin(), files.end());
    CHECK(files == std::vector<std::string>{"exact.txt", "new.txt"});
}

TEST_CASE("write_file_atomic stops when its cancel flag is set, leaving the file and no temporary",
          "[io_util]") {
    TempDir dir;
    write_file(dir / "a.txt", "old");
    const std::atomic<bool> cancel{true};
    wsd::app::AtomicWrite how;
    how.cancel = &cancel;
    std::string error;
    CHECK_FALSE(wsd::app::write_file_atomic(dir / "a.txt", std::string(3 << 20, 'x'), error, how));
    CHECK(error == "interrupted");
    CHECK(read_file(dir / "a.txt") == "old");
    CHECK(list_files(dir) == std::vector<std::string>{"a.txt"});
}
