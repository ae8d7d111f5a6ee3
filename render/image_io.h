// Reading and writing images (the stb implementation macros live in render/stb_impl.cpp).
// 8-bit formats are clamped, sRGB-encoded and rounded; HDR and PFM are linear floats.
#pragma once

#include <string>
#include <string_view>

#include "render/renderer.h"

namespace wsd::render {

enum class ImageFormat { Png, Jpeg, Bmp, Tga, Hdr, Pfm, Unknown };

ImageFormat format_from_extension(const std::string& path);  // case-insensitive

double srgb_encode(double linear);  // [0,1] → [0,1]
double srgb_decode(double encoded);

// Writes to a temporary file in the same directory, then renames it over `path`; on failure
// nothing is left behind and `error` says why. Returns false on failure.
bool write_image(const std::string& path, const Film& film, std::string& error);

// The bytes of a PFM file of `film`: "PF", little-endian floats, bottom row first.
std::string encode_pfm(const Film& film);
// The same for `channels` (3: "PF" colour, 1: "Pf" grey) interleaved floats a pixel, top row first.
std::string encode_pfm(int width, int height, int channels, const float* data);

// Parses the PFM image ("PF" colour or "Pf" grey, either byte order) at the start of `bytes`.
// Returns the offset just past its pixel data (where anything appended to it starts), or 0 with
// `error` saying what is malformed.
size_t decode_pfm(std::string_view bytes, Film& film, std::string& error);

// Reads any supported format into linear RGB (8-bit formats are sRGB-decoded). False + error.
// `eight_bit`, when given, is set to whether the file held 8-bit values (PNG, JPEG, BMP or TGA
// at 8 bits a channel; not a 16-bit PNG, HDR or PFM), whatever its name.
bool read_image(const std::string& path, Film& film, std::string& error, bool* eight_bit = nullptr);

}  // namespace wsd::render
