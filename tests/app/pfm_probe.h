// Reading back the .pfm files that `wsd render` writes, for tests that compare images or look at
// single pixels: little-endian RGB floats, bottom row first in the file, addressed here top row
// first like the image. Header-only, beside app_test_util.h.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace wsd::test {

struct PfmImage {
    int width = 0, height = 0;
    std::vector<float> rgb;  // top row first, 3 floats per pixel

    const float* at(int x, int y) const { return rgb.data() + (size_t(y) * size_t(width) + size_t(x)) * 3; }
};

// An empty image (width 0) when the bytes are not a little-endian RGB PFM.
inline PfmImage parse_pfm(const std::string& bytes) {
    PfmImage img;
    std::istringstream in(bytes);
    std::string magic;
    double scale = 0;
    int w = 0, h = 0;
    in >> magic >> w >> h >> scale;
    if (magic != "PF" || w <= 0 || h <= 0 || scale >= 0) return img;
    const size_t n = size_t(w) * size_t(h) * 3;
    const size_t header = size_t(in.tellg()) + 1;
    if (bytes.size() < header + n * 4) return img;
    img.width = w;
    img.height = h;
    img.rgb.resize(n);
    for (int y = 0; y < h; ++y)
        std::memcpy(img.rgb.data() + size_t(h - 1 - y) * size_t(w) * 3,
                    bytes.data() + header + size_t(y) * size_t(w) * 12, size_t(w) * 12);
    return img;
}

// How many pixels differ by more than `tolerance` in some channel.
inline int pixels_differing(const PfmImage& a, const PfmImage& b, float tolerance) {
    int n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 3; ++c)
                if (!(std::abs(a.at(x, y)[c] - b.at(x, y)[c]) <= tolerance)) {
                    ++n;
                    break;
                }
    return n;
}

}  // namespace wsd::test
