// One pixel's running estimate in progressive rendering: the sums of its samples and of their
// squares, from which its mean (the pixel's value) and the variance of that mean follow. The
// error is measured in display space, as `wsd diff` measures it: each channel clamped to [0, 1]
// and sRGB-encoded. The variance of the linear mean is carried to display space through the
// display curve by a symmetric secant, (f(m + σ) − f(m − σ)) / 2 with σ the standard error of
// the mean, which is f'(m)·σ for small σ and stays bounded where the curve clamps.
//
// The samples are summed in two halves, even and odd sample indices, and the halves are
// independent randomisations, each stratified in itself (render/sequence.h): a stratified
// mean's error is not the samples' variance over n, which overestimates it, and it is not known
// from one half alone. Two estimates follow from the halves:
// - Decide: the even half's sample variance over n, through the display curve as above. For
//   stratified samples it is an upper bound in expectation (stratification only removes variance),
//   so deciding on it is conservative; and it does not use the odd half.
// - Report: the difference of the two half means. With independent halves of n_e and n_o samples
//   whose means have variances σ²/n_e and σ²/n_o, E[(m_e − m_o)²] = σ²·n/(n_e·n_o), so
//   (m_e − m_o)²·n_e·n_o/n² is unbiased for σ²/n, the variance of the mean of all n. It is taken
//   per channel in display space (the difference of the displayed half means), averaged over the
//   channels. Deciding from the same samples that then report the error would be biased (pixels
//   whose samples happened to agree stop early and report too little); the odd half does not
//   decide, so its difference from the even half stays an honest measure.
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
    Vec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
    uint32_t n = 0;

    void add(const Color& c) {
        const int h = int(n & 1u);
        sum[h] += c;
        sum2[h] += c * c;
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
        ++n;
    }

    // The largest difference between two of the pixel's samples as displayed, over the channels
    // (0 without samples).
    double display_spread() const {
        double spread = 0;
        for (int c = 0; c < 3 && n > 0; ++c)
            spread = std::max(spread, display_value(hi[c]) - display_value(lo[c]));
        return spread;
    }
    Color mean() const { return n > 0 ? (sum[0] + sum[1]) / double(n) : Color(0); }

    // The estimated squared display-space error of the pixel's mean, averaged over its three
    // channels (see the top of this file); +∞ while it cannot be estimated yet (Decide: fewer
    // than two even samples; Report: a half without samples).
    double display_variance(Half half) const {
        return half == Decide ? decide_variance() : report_variance();
    }

private:
    double decide_variance() const {
        const uint32_t k = (n + 1) / 2;  // samples in the even half
        if (k < 2) return std::numeric_limits<double>::infinity();
        const Color m_all = mean();
        double total = 0;
        for (int c = 0; c < 3; ++c) {
            const double m = sum[0][c] / k;
            const double s2 = std::max(0.0, (sum2[0][c] - sum[0][c] * m) / double(k - 1));
            const double sigma = std::sqrt(s2 / n);  // of the mean of all n samples
            const double e = 0.5 * (display_value(m_all[c] + sigma) - display_value(m_all[c] - sigma));
            total += e * e;
        }
        return total / 3.0;
    }

    double report_variance() const {
        const uint32_t ne = (n + 1) / 2, no = n / 2;
        if (no < 1) return std::numeric_limits<double>::infinity();
        const double w = double(ne) * double(no) / (double(n) * double(n));
        double total = 0;
        for (int c = 0; c < 3; ++c) {
            const double d = display_value(sum[0][c] / ne) - display_value(sum[1][c] / no);
            total += d * d * w;
        }
        return total / 3.0;
    }
};

}  // namespace wsd::render
