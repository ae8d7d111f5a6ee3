// The image metrics of `wsd diff` and `wsd bench`. SSIM follows Wang, Bovik, Sheikh and Simoncelli
// (2004) with their constants K1 = 0.01, K2 = 0.03 and dynamic range 1; the Gaussian window is
// separable, so each local mean costs two 1-D passes.
#include "app/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/image_io.h"

namespace wsd::app {

DisplayImage to_display(const render::Film& film, bool quantize_8bit) {
    DisplayImage out;
    out.width = film.width;
    out.height = film.height;
    out.rgb.resize(film.rgb.size());
    for (size_t i = 0; i < film.rgb.size(); ++i) {
        double v = film.rgb[i];
        if (!std::isfinite(v)) v = v > 0 ? 1.0 : 0.0;  // +inf is bright; NaN and -inf count as black
        double d = render::srgb_encode(std::clamp(v, 0.0, 1.0));
        d = std::clamp(d, 0.0, 1.0);
        if (quantize_8bit) d = std::round(d * 255.0) / 255.0;
        out.rgb[i] = d;
    }
    return out;
}

double psnr_from_mse(double mse) {
    if (mse <= 0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(1.0 / mse);
}

namespace {

constexpr int window_radius = 5;  // 11×11
constexpr double window_sigma = 1.5;

std::vector<double> luminance(const DisplayImage& img) {
    std::vector<double> y(static_cast<size_t>(img.width) * img.height);
    for (size_t i = 0; i < y.size(); ++i)
        y[i] = 0.2126 * img.rgb[3 * i] + 0.7152 * img.rgb[3 * i + 1] + 0.0722 * img.rgb[3 * i + 2];
    return y;
}

// Normalised Gaussian blur, separable; near the border only the taps inside the image count.
std::vector<double> blur(const std::vector<double>& src, int w, int h) {
    double taps[2 * window_radius + 1];
    for (int k = -window_radius; k <= window_radius; ++k)
        taps[k + window_radius] = std::exp(-(k * k) / (2.0 * window_sigma * window_sigma));
    std::vector<double> tmp(src.size()), out(src.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0, weight = 0;
            for (int k = -window_radius; k <= window_radius; ++k) {
                const int xx = x + k;
                if (xx < 0 || xx >= w) continue;
                sum += taps[k + window_radius] * src[static_cast<size_t>(y) * w + xx];
                weight += taps[k + window_radius];
            }
            tmp[static_cast<size_t>(y) * w + x] = sum / weight;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0, weight = 0;
            for (int k = -window_radius; k <= window_radius; ++k) {
                const int yy = y + k;
                if (yy < 0 || yy >= h) continue;
                sum += taps[k + window_radius] * tmp[static_cast<size_t>(yy) * w + x];
                weight += taps[k + window_radius];
            }
            out[static_cast<size_t>(y) * w + x] = sum / weight;
        }
    return out;
}

}  // namespace

double ssim(const DisplayImage& a, const DisplayImage& b) {
    const int w = a.width, h = a.height;
    if (w <= 0 || h <= 0) return 1.0;
    const std::vector<double> ya = luminance(a), yb = luminance(b);
    std::vector<double> aa(ya.size()), bb(ya.size()), ab(ya.size());
    for (size_t i = 0; i < ya.size(); ++i) {
        aa[i] = ya[i] * ya[i];
        bb[i] = yb[i] * yb[i];
        ab[i] = ya[i] * yb[i];
    }
    const std::vector<double> mu_a = blur(ya, w, h), mu_b = blur(yb, w, h);
    const std::vector<double> e_aa = blur(aa, w, h), e_bb = blur(bb, w, h), e_ab = blur(ab, w, h);
    const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    double total = 0;
    for (size_t i = 0; i < ya.size(); ++i) {
        // Written symmetrically so that identical images give exactly 1.
        const double var_a = e_aa[i] - mu_a[i] * mu_a[i];
        const double var_b = e_bb[i] - mu_b[i] * mu_b[i];
        const double cov = e_ab[i] - mu_a[i] * mu_b[i];
        const double num = (2 * mu_a[i] * mu_b[i] + c1) * (2 * cov + c2);
        const double den = (mu_a[i] * mu_a[i] + mu_b[i] * mu_b[i] + c1) * (var_a + var_b + c2);
        total += num / den;
    }
    return total / static_cast<double>(ya.size());
}

ImageMetrics compare(const DisplayImage& a, const DisplayImage& b) {
    ImageMetrics m;
    double sum = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double d = a.rgb[i] - b.rgb[i];
        sum += d * d;
        m.max_abs_error = std::max(m.max_abs_error, std::abs(d));
    }
    m.mse = a.rgb.empty() ? 0.0 : sum / static_cast<double>(a.rgb.size());
    m.rmse = std::sqrt(m.mse);
    m.psnr = psnr_from_mse(m.mse);
    m.ssim = ssim(a, b);
    return m;
}

DisplayImage error_heatmap(const DisplayImage& a, const DisplayImage& b, double& scale) {
    DisplayImage out;
    out.width = a.width;
    out.height = a.height;
    const size_t n = static_cast<size_t>(a.width) * a.height;
    std::vector<double> err(n);
    scale = 0;
    for (size_t i = 0; i < n; ++i) {
        double e = 0;
        for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(a.rgb[3 * i + c] - b.rgb[3 * i + c]));
        err[i] = e;
        scale = std::max(scale, e);
    }
    out.rgb.resize(3 * n);
    for (size_t i = 0; i < n; ++i) {
        const double t = scale > 0 ? err[i] / scale : 0.0;
        // Three ramps of equal length: red rises, then green, then blue.
        out.rgb[3 * i] = std::clamp(3 * t, 0.0, 1.0);
        out.rgb[3 * i + 1] = std::clamp(3 * t - 1, 0.0, 1.0);
        out.rgb[3 * i + 2] = std::clamp(3 * t - 2, 0.0, 1.0);
    }
    return out;
}

}  // namespace wsd::app
