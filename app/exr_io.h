// OpenEXR files through the OpenEXR library: any set of named 32-bit float channels, written
// ZIP-compressed, and read back whatever their stored type (as float).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "render/renderer.h"

namespace wsd::app {

// One channel to write: pixel (x, y) is data[(y·width + x)·stride] (stride 3 for one component
// of an interleaved RGB film).
struct ExrChannel {
    std::string name;
    const float* data = nullptr;
    size_t stride = 1;
};

// The bytes of a scanline EXR file of `channels`, ZIP-compressed; false + error on failure.
bool encode_exr(int width, int height, const std::vector<ExrChannel>& channels, std::string& bytes,
                std::string& error);

// Every channel of an EXR file's data window, row-major from its top row, as floats.
struct ExrImage {
    int width = 0, height = 0;
    std::map<std::string, std::vector<float>> channels;
};

// True when `bytes` starts with the EXR magic number.
bool looks_like_exr(std::string_view bytes);

// Parses an EXR file: the channels named in `wanted` that it has (every channel when `wanted` is
// empty) from its first part; channels stored at a coarser sampling are left out. False + error
// for a file the library cannot read, or one larger than 2^28 pixels.
bool decode_exr(const std::string& bytes, ExrImage& image, std::string& error,
                const std::vector<std::string>& wanted = {});

// Reads the colour of an EXR file: its R, G, B channels (a missing one is 0), or Y as grey when
// it has none of them; false + error when it has neither or cannot be read.
bool decode_exr_colour(const std::string& bytes, render::Film& film, std::string& error);

}  // namespace wsd::app
