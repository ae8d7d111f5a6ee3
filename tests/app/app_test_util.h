// Helpers for the app tests: a temporary directory per test, running the real `wsd` binary in it
// (stdout and stderr captured), and small file utilities. Header-only; every test file of
// tests/app includes it.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace wsd::test {

namespace fs = std::filesystem;

class TempDir {
public:
    TempDir() {
        std::string pattern = (fs::temp_directory_path() / "wsd-app-test-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
        path_ = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const fs::path& path() const { return path_; }
    std::string operator/(const std::string& name) const { return (path_ / name).string(); }

private:
    fs::path path_;
};

struct RunResult {
    int status = -1;
    std::string out, err;
};

inline std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

inline std::string shell_quote(const std::string& s) {
    std::string out = "'";
    for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// Runs `wsd ARGS` (ARGS already shell-quoted where needed) with `dir` as the working directory;
// `prefix` goes before the command (environment settings, `timeout ...`).
inline RunResult run_wsd(const TempDir& dir, const std::string& args, const std::string& prefix = "") {
    const std::string out = dir / ".stdout", err = dir / ".stderr";
    const std::string command = "cd " + shell_quote(dir.path().string()) + " && " + prefix + " " +
                                shell_quote(WSD_BINARY) + " " + args + " >" + shell_quote(out) + " 2>" +
                                shell_quote(err) + " </dev/null";
    const int raw = std::system(command.c_str());
    RunResult r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    r.out = read_file(out);
    r.err = read_file(err);
    fs::remove(out);
    fs::remove(err);
    return r;
}

// Files in `dir` other than the captured outputs (to check that nothing partial is left behind).
inline std::vector<std::string> list_files(const TempDir& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir.path()))
        names.push_back(entry.path().filename().string());
    return names;
}

// An uncompressed 24-bit TGA (bottom-up rows), written by hand so that the 8-bit values are
// exactly what the test says. `rgb` is top row first, 3 bytes per pixel.
inline void write_tga(const std::string& path, int w, int h, const std::vector<uint8_t>& rgb) {
    std::string bytes(18, '\0');
    bytes[2] = 2;  // uncompressed true-colour
    bytes[12] = static_cast<char>(w & 0xff);
    bytes[13] = static_cast<char>(w >> 8);
    bytes[14] = static_cast<char>(h & 0xff);
    bytes[15] = static_cast<char>(h >> 8);
    bytes[16] = 24;
    for (int y = h - 1; y >= 0; --y)
        for (int x = 0; x < w; ++x) {
            const size_t i = (static_cast<size_t>(y) * w + x) * 3;
            bytes += static_cast<char>(rgb[i + 2]);
            bytes += static_cast<char>(rgb[i + 1]);
            bytes += static_cast<char>(rgb[i]);
        }
    write_file(path, bytes);
}

// A value after "KEY: " on its own line of `text`, or "" if absent.
inline std::string field(const std::string& text, const std::string& key) {
    const std::string tag = key + ": ";
    size_t at = text.find(tag);
    if (at == std::string::npos) return "";
    at += tag.size();
    const size_t end = text.find_first_of(" \n", at);
    return text.substr(at, end - at);
}

// A tiny scene (16×16) with supersampling jitter, an area light, reflection and a checker floor:
// everything that draws random numbers, so tiles and bench have something to get wrong.
inline std::string tiny_scene(int seed = 3, int size = 16) {
    return "settings { width " + std::to_string(size) + "  height " + std::to_string(size) +
           "  supersamples 4  seed " + std::to_string(seed) +
           " }\n"
           "camera { position <0, 1, -4>  look_at <0, 0.5, 0>  fov 50 }\n"
           "light area { position <2, 5, -2>  u <1, 0, 0>  v <0, 0, 1>  samples 2 }\n"
           "plane { normal <0, 1, 0>  distance 0  material { texture checker { scale 0.25 } } }\n"
           "sphere { center <0, 0.7, 0>  radius 0.7  material { color <0.9, 0.2, 0.2>  specular 0.5  "
           "reflection 0.3 } }\n";
}

}  // namespace wsd::test
