// incomplete_image_data (image_check.h): each format's pixel data walked as stb_image reads it,
// counting bytes only. A header this check does not understand is left to the decoder.
#include "render/image_check.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string_view>

namespace wsd::render {

namespace {

const std::string kTruncated = "the file ends before its last pixel (truncated?)";

uint32_t u16le(const unsigned char* p) {
    return uint32_t{p[0]} | uint32_t{p[1]} << 8;
}
uint32_t u32le(const unsigned char* p) {
    return u16le(p) | u16le(p + 2) << 16;
}

// Radiance HDR: header lines up to an empty one, then "-Y height +X width", then scanlines, flat
// or run-length encoded per component (stbi__hdr_load).
std::string check_hdr(const unsigned char* data, size_t size) {
    size_t pos = 0;
    auto line = [&](std::string_view& out) {
        const size_t start = pos;
        while (pos < size && data[pos] != '\n') ++pos;
        if (pos == size) return false;
        out = std::string_view(reinterpret_cast<const char*>(data) + start, pos - start);
        ++pos;
        return true;
    };
    std::string_view text;
    if (!line(text)) return "";  // the decoder reports a header without an end
    do {
        if (!line(text)) return "";
    } while (!text.empty());
    if (!line(text)) return "";
    long long height = 0, width = 0;
    {
        const std::string s(text);
        if (std::sscanf(s.c_str(), "-Y %lld +X %lld", &height, &width) != 2) return "";
    }
    if (width <= 0 || height <= 0 || width > (1 << 24) || height > (1 << 24)) return "";
    const auto flat_bytes =
        static_cast<unsigned long long>(width) * static_cast<unsigned long long>(height) * 4;
    if (width < 8 || width >= 32768) return size - pos >= flat_bytes ? "" : kTruncated;
    for (long long row = 0; row < height; ++row) {
        if (size - pos < 4) return kTruncated;
        const unsigned char* p = data + pos;
        if (p[0] != 2 || p[1] != 2 || (p[2] & 0x80) != 0) {
            // Not run-length encoded: the decoder reads the whole image flat from here.
            return size - pos >= flat_bytes ? "" : kTruncated;
        }
        if ((static_cast<long long>(p[2]) << 8 | p[3]) != width) return "";  // the decoder says so
        pos += 4;
        for (int component = 0; component < 4; ++component) {
            for (long long x = 0; x < width;) {
                if (pos >= size) return kTruncated;
                unsigned count = data[pos++];
                if (count > 128) {
                    count -= 128;
                    if (pos >= size) return kTruncated;
                    ++pos;
                } else {
                    // A literal run of no values makes no progress: stb_image would loop forever.
                    if (count == 0) return "a run of length 0 in its pixel data (the file is corrupt)";
                    if (size - pos < count) return kTruncated;
                    pos += count;
                }
                if (static_cast<long long>(count) > width - x) return "";  // the decoder says so
                x += count;
            }
        }
    }
    return "";
}

// BMP without compression or with bit fields: rows of ((width · bits + 31) / 32) · 4 bytes from
// the data offset; the last row's padding may be missing (stbi__bmp_load skips it).
std::string check_bmp(const unsigned char* data, size_t size) {
    if (size < 30) return "";
    const uint32_t offset = u32le(data + 10), header = u32le(data + 14);
    long long width = 0, height = 0;
    uint32_t bits = 0, compression = 0;
    if (header == 12) {
        width = u16le(data + 18);
        height = u16le(data + 20);
        bits = u16le(data + 24);
    } else if (header >= 40 && size >= 34) {
        width = static_cast<int32_t>(u32le(data + 18));
        height = static_cast<int32_t>(u32le(data + 22));
        bits = u16le(data + 28);
        compression = u32le(data + 30);
    } else {
        return "";
    }
    if (height < 0) height = -height;
    if (width <= 0 || height <= 0 || width > (1 << 24) || height > (1 << 24)) return "";
    if (compression != 0 && compression != 3) return "";
    if (bits != 1 && bits != 4 && bits != 8 && bits != 16 && bits != 24 && bits != 32) return "";
    if (offset < 14 + header) return "";
    const unsigned long long row = (static_cast<unsigned long long>(width) * bits + 31) / 32 * 4;
    const unsigned long long last = (static_cast<unsigned long long>(width) * bits + 7) / 8;
    const unsigned long long needed = offset + row * static_cast<unsigned long long>(height - 1) + last;
    return size >= needed ? "" : kTruncated;
}

// TGA, as stbi__tga_test accepts it: the palette, then pixels raw or in run-length packets.
std::string check_tga(const unsigned char* data, size_t size) {
    if (size < 18) return "";
    const unsigned id_length = data[0], colormap = data[1], type = data[2];
    const uint32_t palette_start = u16le(data + 3), palette_length = u16le(data + 5);
    const unsigned palette_bits = data[7];
    const uint32_t width = u16le(data + 12), height = u16le(data + 14);
    const unsigned bits = data[16];
    if (colormap > 1 || width == 0 || height == 0) return "";
    const unsigned base = type >= 8 ? type - 8 : type;
    if (type != base && type < 9) return "";
    if (colormap == 1) {
        if (base != 1 || (bits != 8 && bits != 16)) return "";
        if (palette_bits != 8 && palette_bits != 15 && palette_bits != 16 && palette_bits != 24 &&
            palette_bits != 32)
            return "";
    } else {
        if (base != 2 && base != 3) return "";
        if (bits != 8 && bits != 15 && bits != 16 && bits != 24 && bits != 32) return "";
    }
    unsigned long long pos = 18ull + id_length;
    if (colormap == 1)
        pos += palette_start + static_cast<unsigned long long>(palette_length) * ((palette_bits + 7) / 8);
    const unsigned long long pixel = (bits + 7) / 8;
    const unsigned long long pixels = static_cast<unsigned long long>(width) * height;
    if (type == base) return pos + pixels * pixel <= size ? "" : kTruncated;
    for (unsigned long long done = 0; done < pixels;) {
        if (pos >= size) return kTruncated;
        const unsigned command = data[pos++];
        const unsigned long long count = 1 + (command & 127);
        pos += (command & 128) ? pixel : count * pixel;
        if (pos > size) return kTruncated;
        done += count;
    }
    return "";
}

bool starts_with(const unsigned char* data, size_t size, std::string_view prefix) {
    return size >= prefix.size() && std::memcmp(data, prefix.data(), prefix.size()) == 0;
}

}  // namespace

std::string incomplete_image_data(const unsigned char* data, size_t size) {
    if (starts_with(data, size, "#?RADIANCE\n") || starts_with(data, size, "#?RGBE\n"))
        return check_hdr(data, size);
    if (starts_with(data, size, "BM")) return check_bmp(data, size);
    // The formats stb_image recognises by their first bytes come before TGA, which it tries last.
    for (std::string_view magic :
         {std::string_view("\x89PNG"), std::string_view("\xFF\xD8"), std::string_view("GIF8"),
          std::string_view("8BPS"), std::string_view("\x53\x80\xF6\x34"), std::string_view("P5"),
          std::string_view("P6"), std::string_view("#?")})
        if (starts_with(data, size, magic)) return "";
    return check_tga(data, size);
}

}  // namespace wsd::render
