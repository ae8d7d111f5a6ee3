// Reading a whole file into memory, the one way every module does it (scenes and their includes,
// meshes, images, tiles).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace wsd::render {

// A file's bytes. Not zero-filled before the read: for a 100 MB mesh that would cost a tenth of
// the load time.
struct FileBytes {
    std::unique_ptr<char[]> data;
    size_t size = 0;
    std::string_view view() const { return {data.get(), size}; }
};

// Reads the file `path` whole, until its end: a regular file (also one whose size says 0, as the
// files of /proc do), or a pipe until its writer closes it. A directory or device is refused
// before it is opened (it would fail late, or never end). False + `reason`: "it is a directory",
// "it is not a regular file", "out of memory", or the system's message.
bool read_whole_file(const std::string& path, FileBytes& out, std::string& reason);

// The extension of `path` with its dot, in ASCII lower case (".png" for "a/B.PNG"; "" for none).
std::string extension_lower(const std::string& path);

}  // namespace wsd::render
