// Image files: extension detection, round trips through every writable format, the
// temporary-file-and-rename discipline (nothing left behind on failure) and PFM parsing.
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "render/image_io.h"

namespace fs = std::filesystem;
using namespace wsd::render;

namespace {

// A fresh empty directory for one test.
struct TempDir {
    fs::path path;
    TempDir() {
        static int counter = 0;
        path = fs::temp_directory_path() /
               ("wsd_image_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string file(const std::string& name) const { return (path / name).string(); }
    size_t entries() const {
        size_t n = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(path)) ++n;
        return n;
    }
};

Film gradient(int w, int h, float lo, float hi) {
    Film f;
    f.width = w;
    f.height = h;
    f.rgb.resize(size_t(w) * size_t(h) * 3);
    for (size_t i = 0; i < f.rgb.size(); ++i) f.rgb[i] = lo + (hi - lo) * float(i % 97) / 96.0f;
    return f;
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::string float_bytes(float v, bool little) {
    unsigned char b[4];
    std::memcpy(b, &v, 4);  // the test machine is little-endian
    if (!little) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
    return std::string(reinterpret_cast<char*>(b), 4);
}

}  // namespace

TEST_CASE("format_from_extension is case-insensitive", "[image_io]") {
    CHECK(format_from_extension("a/b.png") == ImageFormat::Png);
    CHECK(format_from_extension("x.PNG") == ImageFormat::Png);
    CHECK(format_from_extension("x.jpg") == ImageFormat::Jpeg);
    CHECK(format_from_extension("x.JpEg") == ImageFormat::Jpeg);
    CHECK(format_from_extension("x.bmp") == ImageFormat::Bmp);
    CHECK(format_from_extension("x.tga") == ImageFormat::Tga);
    CHECK(format_from_extension("x.hdr") == ImageFormat::Hdr);
    CHECK(format_from_extension("x.pfm") == ImageFormat::Pfm);
    CHECK(format_from_extension("x.exr") == ImageFormat::Unknown);
    CHECK(format_from_extension("png") == ImageFormat::Unknown);
    CHECK(format_from_extension("dir.png/x") == ImageFormat::Unknown);
}

TEST_CASE("sRGB encode and decode are inverse and use the exact curve", "[image_io]") {
    CHECK(srgb_encode(0) == 0);
    CHECK(srgb_encode(1) == Approx(1).margin(1e-12));
    CHECK(srgb_encode(0.002) == Approx(0.002 * 12.92));
    CHECK(srgb_encode(0.5) == Approx(1.055 * std::pow(0.5, 1 / 2.4) - 0.055));
    for (double x = 0; x <= 1; x += 1.0 / 64) CHECK(srgb_decode(srgb_encode(x)) == Approx(x).margin(1e-12));
}

TEST_CASE("8-bit formats round trip within one step of the encoding", "[image_io]") {
    TempDir dir;
    const Film film = gradient(13, 7, -0.2f, 1.3f);  // includes values clamped at both ends
    for (const char* name : {"a.png", "a.bmp", "a.tga"}) {
        std::string error;
        REQUIRE(write_image(dir.file(name), film, error));
        Film back;
        REQUIRE(read_image(dir.file(name), back, error));
        REQUIRE(back.width == 13);
        REQUIRE(back.height == 7);
        for (size_t i = 0; i < film.rgb.size(); ++i) {
            const double want = srgb_encode(std::clamp(double(film.rgb[i]), 0.0, 1.0));
            INFO(name << " value " << i);
            CHECK(std::abs(srgb_encode(back.rgb[i]) - want) <= 0.5 / 255 + 1e-6);
        }
    }
    CHECK(dir.entries() == 3);  // no temporary files left
    std::string error;
    REQUIRE(write_image(dir.file("a.jpg"), film, error));
    Film back;
    REQUIRE(read_image(dir.file("a.jpg"), back, error));
    CHECK(back.width == 13);
}

TEST_CASE("PFM round trips exactly, HDR closely", "[image_io]") {
    TempDir dir;
    Film film = gradient(9, 5, 0.0f, 40.0f);
    film.rgb[0] = -3.5f;  // PFM keeps anything finite
    std::string error;
    REQUIRE(write_image(dir.file("a.pfm"), film, error));
    Film back;
    REQUIRE(read_image(dir.file("a.pfm"), back, error));
    CHECK(back.width == 9);
    CHECK(back.height == 5);
    CHECK(std::equal(back.rgb.begin(), back.rgb.end(), film.rgb.begin(), film.rgb.end()));

    film.rgb[0] = 0;
    REQUIRE(write_image(dir.file("a.hdr"), film, error));
    REQUIRE(read_image(dir.file("a.hdr"), back, error));
    REQUIRE(back.rgb.size() == film.rgb.size());
    for (size_t i = 0; i < film.rgb.size(); ++i) {
        // RGBE keeps 8 mantissa bits relative to the pixel's largest channel.
        const size_t p = i / 3 * 3;
        const float biggest = std::max({film.rgb[p], film.rgb[p + 1], film.rgb[p + 2]});
        CHECK(std::abs(back.rgb[i] - film.rgb[i]) <= biggest / 128 + 1e-6);
    }
}

TEST_CASE("HDR writing clamps channels above the RGBE maximum instead of wrapping them to black",
          "[image_io]") {
    TempDir dir;
    Film film = gradient(3, 1, 0.0f, 1.0f);
    film.rgb[0] = 3e38f;  // above 255 · 2^119, the largest RGBE value
    film.rgb[1] = 1.0f;
    film.rgb[2] = 1.0f;
    film.rgb[3] = std::numeric_limits<float>::max();
    film.rgb[4] = film.rgb[5] = 0.0f;
    std::string error;
    REQUIRE(write_image(dir.file("big.hdr"), film, error));
    Film back;
    REQUIRE(read_image(dir.file("big.hdr"), back, error));
    REQUIRE(back.rgb.size() == film.rgb.size());
    const float largest = 255.0f * 0x1p119f;
    CHECK(back.rgb[0] == largest);
    CHECK(back.rgb[3] == largest);
    CHECK(back.rgb[4] == 0.0f);
    // The third pixel is untouched.
    CHECK(std::abs(back.rgb[6] - film.rgb[6]) <= 1.0f / 128);
}

TEST_CASE("PFM reading: both byte orders, bottom-to-top rows, malformed files", "[image_io]") {
    TempDir dir;
    for (bool little : {true, false}) {
        // 1×2 image: the bottom row (stored first) is red-ish, the top row blue-ish.
        std::string bytes = little ? "PF\n1 2\n-1.0\n" : "PF\n1 2\n1.0\n";
        for (float v : {1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 2.5f}) bytes += float_bytes(v, little);
        write_bytes(dir.file("x.pfm"), bytes);
        Film f;
        std::string error;
        REQUIRE(read_image(dir.file("x.pfm"), f, error));
        REQUIRE(f.width == 1);
        REQUIRE(f.height == 2);
        CHECK(f.rgb == std::vector<float>{0, 0, 2.5f, 1, 0, 0});
    }
    // Greyscale "Pf" is expanded to RGB.
    write_bytes(dir.file("g.pfm"), "Pf 2 1 -1\n" + float_bytes(0.25f, true) + float_bytes(4.0f, true));
    Film g;
    std::string error;
    REQUIRE(read_image(dir.file("g.pfm"), g, error));
    CHECK(g.rgb == std::vector<float>{0.25f, 0.25f, 0.25f, 4, 4, 4});

    for (const std::string& bad : {std::string("PF\n2 2\n-1.0\n") + "abcd",              // short data
                                   std::string("PF\n0 2\n-1.0\n"),                       // zero width
                                   std::string("PF\n-2 2\n-1.0\n"),                      // negative width
                                   std::string("PF\n2 2\n0\n") + std::string(48, '\0'),  // zero scale
                                   std::string("PF\n99999999 99999999\n-1\n"),           // absurd size
                                   std::string("PF\nx 2\n-1\n"), std::string("PF")}) {
        write_bytes(dir.file("bad.pfm"), bad);
        Film f;
        std::string err;
        CHECK_FALSE(read_image(dir.file("bad.pfm"), f, err));
        CHECK(err.find("bad.pfm") != std::string::npos);
    }
}

TEST_CASE("failed writes report why and leave nothing behind", "[image_io]") {
    TempDir dir;
    const Film film = gradient(4, 4, 0, 1);
    std::string error;
    CHECK_FALSE(write_image(dir.file("missing/x.png"), film, error));
    CHECK(error == "cannot write '" + dir.file("missing/x.png") + "': No such file or directory");
    CHECK_FALSE(write_image(dir.file("x.exr"), film, error));
    CHECK(error.find("unknown image format") != std::string::npos);
    CHECK_FALSE(write_image(dir.file("x.png"), Film{}, error));
    CHECK(dir.entries() == 0);

    // A target that is a directory: the rename fails and the temporary file is removed.
    fs::create_directories(dir.path / "taken.png");
    CHECK_FALSE(write_image(dir.file("taken.png"), film, error));
    CHECK(dir.entries() == 1);

    // Replacing an existing file works (rename over it).
    REQUIRE(write_image(dir.file("ok.png"), film, error));
    REQUIRE(write_image(dir.file("ok.png"), gradient(2, 2, 0, 1), error));
    Film back;
    REQUIRE(read_image(dir.file("ok.png"), back, error));
    CHECK(back.width == 2);
    CHECK(dir.entries() == 2);

    CHECK_FALSE(read_image(dir.file("nothing.png"), back, error));
    CHECK(error.find("No such file or directory") != std::string::npos);
    write_bytes(dir.file("junk.png"), "not an image at all");
    CHECK_FALSE(read_image(dir.file("junk.png"), back, error));
    CHECK(error.find("junk.png") != std::string::npos);
}

TEST_CASE("decode_pfm says where the pixel data ends, and encode_pfm is what write_image writes",
          "[image_io]") {
    TempDir dir;
    const Film film = gradient(3, 2, -1.0f, 7.0f);
    std::string error;
    REQUIRE(write_image(dir.file("a.pfm"), film, error));
    std::ifstream in(dir.file("a.pfm"), std::ios::binary);
    const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string bytes = wsd::render::encode_pfm(film);
    CHECK(bytes == written);

    Film back;
    CHECK(wsd::render::decode_pfm(bytes + "\nanything after", back, error) == bytes.size());
    CHECK(back.rgb == film.rgb);
    CHECK(wsd::render::decode_pfm(bytes.substr(0, bytes.size() - 1), back, error) == 0);
    CHECK(error.find("truncated") != std::string::npos);
}

TEST_CASE("truncated HDR, BMP and TGA files are errors, not black pixels or a hang", "[image_io]") {
    // stb_image loops forever on a Radiance file cut inside its run-length data, and fills
    // the missing rows of a BMP or TGA with zeros: read_image checks the data first.
    TempDir dir;
    const Film film = gradient(40, 9, 0.0f, 2.0f);  // 40 wide: HDR rows are run-length encoded
    for (const char* name : {"a.hdr", "a.bmp", "a.tga"}) {
        INFO(name);
        std::string error;
        REQUIRE(write_image(dir.file(name), film, error));
        std::ifstream in(dir.file(name), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        Film back;
        REQUIRE(read_image(dir.file(name), back, error));  // whole: read as before
        for (size_t cut : {bytes.size() - 1, bytes.size() * 3 / 4, bytes.size() / 2}) {
            INFO("cut to " << cut << " of " << bytes.size() << " bytes");
            write_bytes(dir.file("cut"), bytes.substr(0, cut));
            error.clear();
            CHECK_FALSE(read_image(dir.file("cut"), back, error));
            CHECK(error.find("the file ends before its last pixel") != std::string::npos);
        }
    }
    // A literal run of length 0 in an HDR scanline (a corrupt but full-length file).
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n";
    hdr += std::string("\x02\x02\x00\x08", 4) + std::string(64, '\0');
    write_bytes(dir.file("zero.hdr"), hdr);
    Film back;
    std::string error;
    CHECK_FALSE(read_image(dir.file("zero.hdr"), back, error));
    CHECK(error.find("a run of length 0") != std::string::npos);
}
