// read_whole_file: one sized read for a regular file, reads until the end for a pipe.
#include "render/file_util.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>

namespace wsd::render {

namespace {

// A pipe (`wsd check <(generate)`) has no size: read until its writer closes it.
bool read_pipe(const std::string& path, FileBytes& out, std::string& reason) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) {
        reason = std::strerror(errno);
        return false;
    }
    std::string text;
    char buffer[65536];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) text.append(buffer, n);
    if (std::ferror(file.get())) {
        reason = std::strerror(errno ? errno : EIO);
        return false;
    }
    out.data.reset(new char[text.size() + 1]);
    std::memcpy(out.data.get(), text.data(), text.size());
    out.size = text.size();
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
    if (S_ISFIFO(st.st_mode)) return read_pipe(path, out, reason);
    if (!S_ISREG(st.st_mode)) {
        reason = "it is not a regular file";
        return false;
    }
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    // The file may have changed since stat: the size is read again from the open file.
    if (!file || fstat(fileno(file.get()), &st) != 0 || !S_ISREG(st.st_mode)) {
        reason = file ? "it is not a regular file" : std::strerror(errno);
        return false;
    }
    const size_t size = static_cast<size_t>(st.st_size);
    out.data.reset(new (std::nothrow) char[size == 0 ? 1 : size]);
    if (!out.data) {
        reason = "out of memory";
        return false;
    }
    errno = 0;
    const size_t got = size == 0 ? 0 : std::fread(out.data.get(), 1, size, file.get());
    if (got != size || std::ferror(file.get())) {
        reason = std::strerror(errno ? errno : EIO);
        return false;
    }
    out.size = size;
    return true;
}

}  // namespace wsd::render
