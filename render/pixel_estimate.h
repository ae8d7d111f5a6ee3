// One pixel's running estimate in progressive rendering: the sums of its samples and of their
// squares, from which its mean (the pixel's value) and the variance of that mean follow. The
// error is measured in display space, as `wsd diff` measures it: each channel clamped to [0, 1]
// and sRGB-encoded. The variance of the linear mean is carried to display space through the
// display curve by a symmetric secant, (f(m + σ) − f(m − σ)) / 2 with σ the standard error of
// the mean, which is f'(m)·σ for small σ and stays bounded where the curve clamps.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "render/image_io.h"
#include "render/math.h"

namespace wsd::render {

// A linear value as `wsd diff` displays it (clamped, sRGB-encoded).
inline double display_value(double linear) {
    return srgb_encode(std::clamp(linear, 0.0, 1.0));
}

struct PixelEstimate {
    Vec3 sum{0}, sum2{0};
    uint32_t n = 0;

    void add(const Color& c) {
        sum += c;
        sum2 += c * c;
        ++n;
    }
    Color mean() const { return n > 0 ? sum / double(n) : Color(0); }

    // The estimated squared display-space error of the pixel's mean, averaged over its three
    // channels; +∞ with fewer than two samples (no variance to estimate from).
    double display_variance() const {
        if (n < 2) return std::numeric_limits<double>::infinity();
        double total = 0;
        for (int c = 0; c < 3; ++c) {
            const double m = sum[c] / n;
            const double s2 = std::max(0.0, (sum2[c] - sum[c] * m) / double(n - 1));  // sample variance
            const double sigma = std::sqrt(s2 / n);                                   // of the mean
            const double e = 0.5 * (display_value(m + sigma) - display_value(m - sigma));
            total += e * e;
        }
        return total / 3.0;
    }
};

}  // namespace wsd::render
