// One pixel's running estimate in progressive rendering: the sums of its samples and of their
// squares, from which its mean (the pixel's value) and the variance of that mean follow. The
// error is measured in display space, as `wsd diff` measures it: each channel clamped to [0, 1]
// and sRGB-encoded. The variance of the linear mean is carried to display space through the
// display curve by a symmetric secant, (f(m + σ) − f(m − σ)) / 2 with σ the standard error of
// the mean, which is f'(m)·σ for small σ and stays bounded where the curve clamps.
//
// The samples are summed in two halves, even and odd sample indices, and each half gives its
// own estimate of the samples' variance. Deciding when a pixel stops from the same samples that
// then report its error would be biased: pixels whose samples happened to vary little stop early
// and report too little. So the even half decides (Half::Decide) and the odd half, independent
// of that decision, reports (Half::Report).
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
    enum Half { Decide = 0, Report = 1 };
    Vec3 sum[2] = {Vec3(0), Vec3(0)}, sum2[2] = {Vec3(0), Vec3(0)};
    uint32_t n = 0;

    void add(const Color& c) {
        const int h = int(n & 1u);
        sum[h] += c;
        sum2[h] += c * c;
        ++n;
    }
    Color mean() const { return n > 0 ? (sum[0] + sum[1]) / double(n) : Color(0); }

    // The estimated squared display-space error of the pixel's mean, averaged over its three
    // channels, with the samples' variance taken from one half; +∞ while that half has fewer
    // than two samples.
    double display_variance(Half half) const {
        const uint32_t k = half == Decide ? (n + 1) / 2 : n / 2;  // samples in the half
        if (k < 2) return std::numeric_limits<double>::infinity();
        const Color m_all = mean();
        double total = 0;
        for (int c = 0; c < 3; ++c) {
            const double m = sum[half][c] / k;
            const double s2 = std::max(0.0, (sum2[half][c] - sum[half][c] * m) / double(k - 1));
            const double sigma = std::sqrt(s2 / n);  // of the mean of all n samples
            const double e = 0.5 * (display_value(m_all[c] + sigma) - display_value(m_all[c] - sigma));
            total += e * e;
        }
        return total / 3.0;
    }
};

}  // namespace wsd::render
