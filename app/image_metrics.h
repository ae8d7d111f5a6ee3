// Image comparison on display values: RMSE, PSNR, maximum absolute error and SSIM (Wang et al.
// 2004: 11×11 Gaussian window, σ = 1.5, on luminance), plus a per-pixel error heat map. Used by
// `wsd diff` and `wsd bench`; pure functions, no I/O.
#pragma once

#include <vector>

#include "render/renderer.h"

namespace wsd::app {

// An image of display values in [0, 1] (sRGB-encoded and clamped), RGB, row-major.
struct DisplayImage {
    int width = 0, height = 0;
    std::vector<double> rgb;
};

// Clamps and sRGB-encodes a linear film. With `quantize_8bit`, values are rounded to multiples of
// 1/255 (what an 8-bit file held), so decoding and re-encoding an 8-bit image is exact.
DisplayImage to_display(const render::Film& film, bool quantize_8bit = false);

struct ImageMetrics {
    double mse = 0;
    double rmse = 0;
    double psnr = 0;           // 10·log10(1/MSE); +infinity when MSE is 0
    double max_abs_error = 0;  // over all pixels and channels
    double ssim = 1;
};

double psnr_from_mse(double mse);

// Luminance (Rec. 709 weights) SSIM; borders use the part of the window inside the image,
// renormalised, so images smaller than the window still get a value. Sizes must match.
double ssim(const DisplayImage& a, const DisplayImage& b);

// Every metric at once; `a` and `b` must have the same size (checked by the caller).
ImageMetrics compare(const DisplayImage& a, const DisplayImage& b);

// Heat map of the per-pixel error (largest channel difference), black → red → yellow → white,
// scaled so that the largest error is white. Returns display values; `scale` receives that error.
DisplayImage error_heatmap(const DisplayImage& a, const DisplayImage& b, double& scale);

}  // namespace wsd::app
