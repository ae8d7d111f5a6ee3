// read_whole_file: one read for a regular file of the size it says, reads until the end for a
// pipe or a file whose size says nothing (/proc).
#include "render/file_util.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <string>

namespace wsd::render {

namespace {

// Reads `file` until its end. `expected` is the size it says it has (0 for a pipe, and for a
// /proc file that has bytes all the same): a buffer one byte larger takes a file of that size in
// one read and sees its end; a longer one grows the buffer.
bool read_to_end(std::FILE* file, size_t expected, FileBytes& out, std::string& reason) {
    size_t capacity = expected + 1, used = 0;
    std::unique_ptr<char[]> data(new (std::nothrow) char[capacity]);
    for (;;) {
        if (!data) {
            reason = "out of memory";
            return false;
        }
        errno = 0;
        used += std::fread(data.get() + used, 1, capacity - used, file);
        if (std::ferror(file)) {
            reason = std::strerror(errno ? errno : EIO);
            return false;
        }
        if (used < capacity) break;
        const size_t grown = std::max<size_t>(capacity * 2, 65536);
        std::unique_ptr<char[]> larger(new (std::nothrow) char[grown]);
        if (larger) std::memcpy(larger.get(), data.get(), used);
        data = std::move(larger);
        capacity = grown;
    }
    out.data = std::move(data);
    out.size = used;
    return true;
}

}  // namespace

bool read_whole_file(const std::string& path, FileBytes& out, std::string& reason) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        reason = std::strerror(errno);
        return false;
    }
    if (S_ISDIR(st.st_mode)) {
        reason = "it is a directory";
        return false;
    }
    if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
        reason = "it is not a regular file";
        return false;
    }
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    // The file may have changed since stat: its kind and size are read again from the open file.
    if (!file || fstat(fileno(file.get()), &st) != 0 || !(S_ISREG(st.st_mode) || S_ISFIFO(st.st_mode))) {
        reason = file ? "it is not a regular file" : std::strerror(errno);
        return false;
    }
    return read_to_end(file.get(), S_ISREG(st.st_mode) ? static_cast<size_t>(st.st_size) : 0, out, reason);
}

std::string extension_lower(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = (c >= 'A' && c <= 'Z') ? char(c - 'A' + 'a') : c;
    return ext;
}

}  // namespace wsd::render
