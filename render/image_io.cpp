// Image files: PNG, JPEG, BMP, TGA (8-bit sRGB), Radiance HDR and PFM (linear float). Writes go
// to a temporary file in the target's directory that is renamed over the target, so a failed or
// interrupted write never leaves a partial image. The stb implementations live in stb_impl.cpp.
#include "render/image_io.h"

#include <stb_image.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

#include "render/file_util.h"
#include "render/image_check.h"
#include "render/limits.h"
#include "render/text_util.h"

namespace wsd::render {

namespace {

uint8_t to_byte(float v) {
    const double x = v > 0 ? std::min(double(v), 1.0) : 0.0;  // NaN → 0
    return uint8_t(std::lround(srgb_encode(x) * 255.0));
}

// A FILE* sink for stb's *_to_func writers that remembers the first error.
struct Sink {
    std::FILE* file = nullptr;
    int error = 0;
};

void sink_write(void* context, void* data, int size) {
    auto* sink = static_cast<Sink*>(context);
    if (sink->error || size <= 0) return;
    if (std::fwrite(data, 1, size_t(size), sink->file) != size_t(size)) sink->error = errno ? errno : EIO;
}

// The largest value RGBE stores: mantissa 255 at the largest exponent, 255 · 2^119 ≈ 1.7e38. A
// channel above it would need exponent 128, which the exponent byte wraps to 0 (black).
constexpr float kRgbeMax = 255.0f * 0x1p119f;

// The film for RGBE: every channel clamped to what RGBE stores, so the brightest pixels stay
// the brightest the format can say.
std::vector<float> rgbe_clamped(const Film& film) {
    std::vector<float> rgb(film.rgb);
    for (float& v : rgb) v = std::min(v, kRgbeMax);
    return rgb;
}

bool encode(ImageFormat format, const Film& film, Sink& sink) {
    const int w = film.width, h = film.height;
    if (format == ImageFormat::Hdr)
        return stbi_write_hdr_to_func(sink_write, &sink, w, h, 3, rgbe_clamped(film).data()) != 0;
    if (format == ImageFormat::Pfm) {
        std::string bytes = encode_pfm(film);
        sink_write(&sink, bytes.data(), int(bytes.size()));
        return true;
    }
    std::vector<unsigned char> bytes(film.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = to_byte(film.rgb[i]);
    switch (format) {
        case ImageFormat::Png:
            return stbi_write_png_to_func(sink_write, &sink, w, h, 3, bytes.data(), w * 3) != 0;
        case ImageFormat::Jpeg:
            return stbi_write_jpg_to_func(sink_write, &sink, w, h, 3, bytes.data(), 95) != 0;
        case ImageFormat::Bmp:
            return stbi_write_bmp_to_func(sink_write, &sink, w, h, 3, bytes.data()) != 0;
        case ImageFormat::Tga:
            return stbi_write_tga_to_func(sink_write, &sink, w, h, 3, bytes.data()) != 0;
        default:
            return false;
    }
}

}  // namespace

ImageFormat format_from_extension(const std::string& path) {
    const std::string ext = extension_lower(path);
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::Jpeg;
    if (ext == ".bmp") return ImageFormat::Bmp;
    if (ext == ".tga") return ImageFormat::Tga;
    if (ext == ".hdr") return ImageFormat::Hdr;
    if (ext == ".pfm") return ImageFormat::Pfm;
    return ImageFormat::Unknown;
}

double srgb_encode(double linear) {
    if (linear <= 0.0031308) return 12.92 * linear;
    return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double encoded) {
    if (encoded <= 0.04045) return encoded / 12.92;
    return std::pow((encoded + 0.055) / 1.055, 2.4);
}

std::string encode_pfm(const Film& film) {
    return encode_pfm(film.width, film.height, 3, film.rgb.data());
}

std::string encode_pfm(int width, int height, int channels, const float* data) {
    const size_t w = size_t(width), h = size_t(height), row = w * size_t(channels);
    std::string out =
        (channels == 1 ? "Pf\n" : "PF\n") + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n";
    const size_t header = out.size();
    out.resize(header + row * h * 4);
    for (size_t y = 0; y < h; ++y) {  // PFM stores the bottom row first
        const float* src = data + (h - 1 - y) * row;
        for (size_t i = 0; i < row; ++i) {
            uint32_t bits = std::bit_cast<uint32_t>(src[i]);
            if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
            std::memcpy(out.data() + header + (y * row + i) * 4, &bits, 4);
        }
    }
    return out;
}

// PFM: "PF" (RGB) or "Pf" (grey), width, height, scale (negative: little-endian), each separated by
// whitespace, one whitespace byte, then rows of 32-bit floats from the bottom row up.
size_t decode_pfm(std::string_view bytes, Film& film, std::string& error) {
    const char* const begin = bytes.data();
    const char* p = begin;
    const char* end = p + bytes.size();
    auto bad = [&](const char* why) {
        error = std::string("malformed PFM file (") + why + ")";
        return size_t(0);
    };
    auto skip_space = [&] {
        while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    };
    if (end - p < 2 || p[0] != 'P' || (p[1] != 'F' && p[1] != 'f')) return bad("bad signature");
    const int channels = p[1] == 'F' ? 3 : 1;
    p += 2;
    long w = 0, h = 0;
    double scale = 0;
    skip_space();
    auto r1 = std::from_chars(p, end, w);
    if (r1.ec != std::errc()) return bad("bad width");
    p = r1.ptr;
    skip_space();
    auto r2 = std::from_chars(p, end, h);
    if (r2.ec != std::errc()) return bad("bad height");
    p = r2.ptr;
    skip_space();
    auto r3 = std::from_chars(p, end, scale);
    if (r3.ec != std::errc() || !std::isfinite(scale) || scale == 0) return bad("bad scale");
    p = r3.ptr;
    if (p >= end || !std::isspace(static_cast<unsigned char>(*p)))
        return bad("no whitespace after the header");
    ++p;
    if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide || w * h > kMaxPixels)
        return bad("bad image size");
    const size_t values = size_t(w) * size_t(h) * size_t(channels);
    if (size_t(end - p) < values * 4) return bad("truncated: the pixel data is shorter than the header says");
    const bool little = scale < 0;
    const bool swap = little != (std::endian::native == std::endian::little);
    film.width = int(w);
    film.height = int(h);
    film.rgb.assign(size_t(w) * size_t(h) * 3, 0.0f);
    for (long y = 0; y < h; ++y) {
        const long out_row = h - 1 - y;  // stored bottom row first
        for (long x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c) {
                const size_t src =
                    (size_t(y) * size_t(w) + size_t(x)) * size_t(channels) + size_t(c % channels);
                uint32_t bits;
                std::memcpy(&bits, p + src * 4, 4);
                if (swap) bits = __builtin_bswap32(bits);
                film.rgb[(size_t(out_row) * size_t(w) + size_t(x)) * 3 + size_t(c)] =
                    std::bit_cast<float>(bits);
            }
        }
    }
    return size_t(p - begin) + values * 4;
}

bool write_image(const std::string& path, const Film& film, std::string& error) {
    const ImageFormat format = format_from_extension(path);
    if (format == ImageFormat::Unknown) {
        error = "cannot write " + quoted(path) +
                ": unknown image format (use .png, .jpg, .jpeg, .bmp, .tga, .hdr or .pfm)";
        return false;
    }
    if (film.width < 1 || film.height < 1 ||
        film.rgb.size() != size_t(film.width) * size_t(film.height) * 3) {
        error = "cannot write " + quoted(path) + ": the image is empty";
        return false;
    }
    const std::filesystem::path target(path);
    std::string temp_name = ".";  // appended piecewise: GCC 12 warns (-Wrestrict) on a + chain
    temp_name.append(target.filename().string()).append(".tmp-").append(std::to_string(::getpid()));
    const std::filesystem::path temp = target.parent_path() / temp_name;
    const std::string temp_str = temp.string();

    Sink sink;
    sink.file = std::fopen(temp_str.c_str(), "wb");
    if (!sink.file) {
        error = "cannot write " + quoted(path) + ": " + std::strerror(errno);
        return false;
    }
    errno = 0;
    const bool encoded = encode(format, film, sink);
    if (std::fflush(sink.file) != 0 && !sink.error) sink.error = errno ? errno : EIO;
    if (std::fclose(sink.file) != 0 && !sink.error) sink.error = errno ? errno : EIO;
    if (!encoded || sink.error) {
        std::remove(temp_str.c_str());
        error = "cannot write " + quoted(path) + ": " +
                (sink.error ? std::strerror(sink.error) : "the image could not be encoded in this format");
        return false;
    }
    if (std::rename(temp_str.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(temp_str.c_str());
        error = "cannot write " + quoted(path) + ": " + std::strerror(e);
        return false;
    }
    return true;
}

bool read_image(const std::string& path, Film& film, std::string& error, bool* eight_bit) {
    if (eight_bit) *eight_bit = false;
    FileBytes file;
    if (!read_whole_file(path, file, error)) {
        error = "cannot read " + quoted(path) + ": " + error;
        return false;
    }
    if (file.size > size_t(INT_MAX)) {
        error = "cannot read " + quoted(path) + ": file too large";
        return false;
    }
    const auto* data = reinterpret_cast<const unsigned char*>(file.data.get());
    if (file.size >= 2 && data[0] == 'P' && (data[1] == 'F' || data[1] == 'f')) {
        if (decode_pfm(file.view(), film, error) > 0) return true;
        error = "cannot read " + quoted(path) + ": " + error;
        return false;
    }
    if (const std::string why = incomplete_image_data(data, file.size); !why.empty()) {
        error = "cannot read " + quoted(path) + ": " + why;
        return false;
    }
    const int len = int(file.size);
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(data, len, &w, &h, &comp)) {
        error = "cannot read " + quoted(path) + ": not a supported image (" + stbi_failure_reason() + ")";
        return false;
    }
    if (long(w) * long(h) > kMaxPixels) {
        error = "cannot read " + quoted(path) + ": image too large";
        return false;
    }
    const size_t n = size_t(w) * size_t(h) * 3;
    if (stbi_is_hdr_from_memory(data, len)) {
        float* px = stbi_loadf_from_memory(data, len, &w, &h, &comp, 3);
        if (!px) {
            error = "cannot read " + quoted(path) + ": " + stbi_failure_reason();
            return false;
        }
        film.width = w;
        film.height = h;
        film.rgb.assign(px, px + n);
        stbi_image_free(px);
        return true;
    }
    if (stbi_is_16_bit_from_memory(data, len)) {
        uint16_t* px = stbi_load_16_from_memory(data, len, &w, &h, &comp, 3);
        if (!px) {
            error = "cannot read " + quoted(path) + ": " + stbi_failure_reason();
            return false;
        }
        film.width = w;
        film.height = h;
        film.rgb.resize(n);
        for (size_t i = 0; i < n; ++i) film.rgb[i] = float(srgb_decode(px[i] / 65535.0));
        stbi_image_free(px);
        return true;
    }
    unsigned char* px = stbi_load_from_memory(data, len, &w, &h, &comp, 3);
    if (!px) {
        error = "cannot read " + quoted(path) + ": " + stbi_failure_reason();
        return false;
    }
    float table[256];
    for (int i = 0; i < 256; ++i) table[i] = float(srgb_decode(i / 255.0));
    film.width = w;
    film.height = h;
    film.rgb.resize(n);
    for (size_t i = 0; i < n; ++i) film.rgb[i] = table[px[i]];
    stbi_image_free(px);
    if (eight_bit) *eight_bit = true;
    return true;
}

}  // namespace wsd::render
