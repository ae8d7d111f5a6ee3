// File helpers for the commands: command-line inputs (with "-" for stdin), atomic outputs, the
// FNV-1a hash used by tile metadata, and the process's peak memory for the statistics.
#include "app/io_util.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "app/exit_codes.h"
#include "render/file_util.h"

namespace wsd::app {

namespace fs = std::filesystem;

bool read_input_file(const std::string& path, std::string& text, std::string& error) {
    if (path == "-") {
        std::ostringstream buffer;
        buffer << std::cin.rdbuf();
        if (std::cin.bad()) {
            error = "cannot read standard input";
            return false;
        }
        text = buffer.str();
        return true;
    }
    render::FileBytes bytes;
    if (!render::read_whole_file(path, bytes, error)) {
        error = "cannot read '" + path + "': " + error;
        return false;
    }
    text.assign(bytes.view());
    return true;
}

bool can_open_for_reading(const std::string& path, std::string& error) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        error = "cannot read '" + path + "': it is a directory";
        return false;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot read '" + path + "': " + std::strerror(errno);
        return false;
    }
    // A device or a pipe (/dev/zero) is refused here, as `check` refuses it, not later as an
    // image that does not decode.
    if (!fs::is_regular_file(path, ec)) {
        error = "cannot read '" + path + "': it is not a regular file";
        return false;
    }
    return true;
}

namespace {

// An existing output that is neither a regular file nor a directory (a device such as /dev/null,
// a FIFO, a socket), or any existing path under /dev or /proc (/dev/stdout, /dev/fd/3, whatever
// the descriptor leads to). It is written in place, as any tool writes to it: a new file renamed
// over it would replace the device, the pipe or the link, and /dev is no place for a new file.
bool is_special_output(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || S_ISDIR(st.st_mode)) return false;
    if (!S_ISREG(st.st_mode)) return true;
    const std::string absolute = fs::absolute(path).lexically_normal().string();
    return absolute.rfind("/dev/", 0) == 0 || absolute.rfind("/proc/", 0) == 0;
}

// Writes all of `data` to `fd`, in pieces so that a signal stops a large write soon. False with
// errno set, or with `interrupted` set when `how.cancel` stopped it.
bool write_all(int fd, std::string_view data, const AtomicWrite& how, bool& interrupted) {
    constexpr size_t piece = size_t{1} << 20;
    size_t written = 0;
    while (written < data.size()) {
        if (how.cancel && how.cancel->load()) {
            interrupted = true;
            return false;
        }
        const ssize_t n = ::write(fd, data.data() + written, std::min(piece, data.size() - written));
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        written += static_cast<size_t>(n);
    }
    return true;
}

// The descriptor that /dev/stdout, /dev/stderr, /dev/fd/N or /proc/self/fd/N names, or -1.
int named_descriptor(const std::string& path) {
    if (path == "/dev/stdout") return 1;
    if (path == "/dev/stderr") return 2;
    for (const std::string_view prefix : {"/dev/fd/", "/proc/self/fd/"}) {
        if (path.rfind(prefix, 0) != 0) continue;
        const std::string digits = path.substr(prefix.size());
        if (digits.empty() || digits.size() > 9 ||
            !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
            return -1;
        return std::stoi(digits);
    }
    return -1;
}

// write_file_atomic for an is_special_output path: opened (never created) and written. A path
// naming one of our descriptors is written to that descriptor, after what it holds already
// (`wsd render --stats --stats-json /dev/stdout > out` keeps the table and appends the JSON).
bool write_special_output(const std::string& path, std::string_view data, std::string& error,
                          const AtomicWrite& how) {
    if (const int own = named_descriptor(path); own >= 0) {
        std::cout.flush();
        std::cerr.flush();
        std::fflush(nullptr);
        bool interrupted = false;
        if (!write_all(own, data, how, interrupted)) {
            error = interrupted ? "interrupted" : "cannot write '" + path + "': " + std::strerror(errno);
            return false;
        }
        return true;
    }
    const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) {
        error = "cannot write '" + path + "': " + std::strerror(errno);
        return false;
    }
    bool interrupted = false;
    if (!write_all(fd, data, how, interrupted)) {
        error = interrupted ? "interrupted" : "cannot write '" + path + "': " + std::strerror(errno);
        ::close(fd);
        return false;
    }
    if (::close(fd) != 0) {
        error = "cannot write '" + path + "': " + std::strerror(errno);
        return false;
    }
    return true;
}

}  // namespace

bool output_directory_exists(const std::string& path, std::string& error) {
    // A device or pipe is written where it is: its directory (/dev) need not be writable.
    if (is_special_output(path)) return true;
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        // The nearest part of the directory's path that exists says why: a file where a directory
        // should be, or nothing there.
        for (fs::path part = dir; !part.empty(); part = part.parent_path()) {
            const fs::file_status status = fs::status(part, ec);
            if (fs::exists(status) && !fs::is_directory(status)) {
                error = "cannot write '" + path + "': '" + part.string() + "' is not a directory";
                return false;
            }
            if (part == part.parent_path()) break;
        }
        error = "cannot write '" + path + "': directory '" + dir.string() + "' does not exist";
        return false;
    }
    if (::access(dir.c_str(), W_OK) != 0) {
        error = "cannot write '" + path + "': directory '" + dir.string() + "' is not writable";
        return false;
    }
    if (fs::is_directory(path, ec)) {
        error = "cannot write '" + path + "': it is a directory";
        return false;
    }
    return true;
}

bool same_path(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal()) return true;
    return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
}

bool write_file_atomic(const std::string& path, std::string_view data, std::string& error,
                       const AtomicWrite& how) {
    const auto cancelled = [&] { return how.cancel && how.cancel->load(); };
    if (cancelled()) {
        error = "interrupted";
        return false;
    }
    if (!output_directory_exists(path, error)) return false;
    if (is_special_output(path)) return write_special_output(path, data, error, how);
    const fs::path target(path);
    fs::path dir = target.parent_path();
    static int counter = 0;
    // Built with append: GCC 12 warns falsely (-Wrestrict) about `"." + std::string`.
    std::string temp_name = ".";
    temp_name.append(target.filename().string())
        .append(".tmp-")
        .append(std::to_string(::getpid()))
        .append("-")
        .append(std::to_string(counter++));
    const fs::path temp = dir.empty() ? fs::path(temp_name) : dir / temp_name;
    // Created with no more than the bits asked for, then given exactly those.
    const mode_t mode = static_cast<mode_t>(how.mode.value_or(0644) & 07777);
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
    if (fd < 0) {
        error = "cannot write '" + path + "': " + std::strerror(errno);
        return false;
    }
    const auto give_up = [&](const std::string& why) {
        error = why;
        ::close(fd);
        ::unlink(temp.c_str());
        return false;
    };
    if (how.mode && ::fchmod(fd, mode) != 0)
        return give_up("cannot write '" + path + "': " + std::strerror(errno));
    if (bool interrupted = false; !write_all(fd, data, how, interrupted))
        return give_up(interrupted ? "interrupted" : "cannot write '" + path + "': " + std::strerror(errno));
    if (::close(fd) != 0) {
        error = "cannot write '" + path + "': " + std::strerror(errno);
        ::unlink(temp.c_str());
        return false;
    }
    if (cancelled()) {
        error = "interrupted";
        ::unlink(temp.c_str());
        return false;
    }
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        error = "cannot write '" + path + "': " + std::strerror(errno);
        ::unlink(temp.c_str());
        return false;
    }
    return true;
}

void remove_output(const std::string& path) {
    if (is_special_output(path)) return;
    std::error_code ec;
    fs::remove(path, ec);
}

int flush_stdout(int status) {
    errno = 0;
    std::cout.flush();
    int error = std::cout.bad() ? errno : 0;  // 0 when it failed before: its errno is gone
    if (std::fflush(stdout) != 0 && error == 0) error = errno;
    if (!std::cout.fail() && !std::ferror(stdout) && error == 0) return status;
    std::string message = "cannot write standard output";
    if (error != 0) message.append(": ").append(std::strerror(error));
    fail(exit_code::io, message);
    return status == exit_code::ok || status == exit_code::input_error ? exit_code::io : status;
}

int fail(int status, const std::string& message) {
    std::cerr << "wsd: error: " << message << '\n';
    return status;
}

void warn(const std::string& message) {
    std::cerr << "wsd: warning: " << message << '\n';
}

std::string counted(uint64_t count, std::string_view singular, std::string_view plural) {
    std::string out = std::to_string(count) + " ";
    if (count == 1) return out.append(singular);
    return plural.empty() ? out.append(singular).append("s") : out.append(plural);
}

uint64_t fnv1a64(std::string_view data, uint64_t seed) {
    uint64_t h = seed;
    for (const char c : data) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string hex64(uint64_t value) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(value));
    return buf;
}

std::string scene_stem(const std::string& path) {
    if (path == "-") return "stdin";
    std::string stem = fs::path(path).stem().string();
    return stem.empty() ? "scene" : stem;
}

uint64_t peak_memory_bytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) {
            std::istringstream fields(line.substr(6));
            uint64_t kib = 0;
            fields >> kib;
            return kib * 1024;
        }
    }
    return 0;
}

}  // namespace wsd::app
