// `wsd diff A B [-o HEATMAP]`: compares two images on display values (sRGB-encoded, clamped) and
// prints RMSE, PSNR, the largest absolute error and SSIM. A file that cannot be opened is an I/O
// error (3); one that opens but does not decode, or two sizes that differ, are input errors (1).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/image_files.h"
#include "app/image_metrics.h"
#include "app/io_util.h"
#include "render/image_io.h"

namespace wsd::app {

namespace {

int read_display(const std::string& path, DisplayImage& image) {
    std::string error;
    if (!can_open_for_reading(path, error)) return fail(exit_code::io, error);
    render::Film film;
    bool eight_bit = false;  // by the file's content, not its name
    if (!read_image_file(path, film, error, &eight_bit))
        return fail(exit_code::input_error, "cannot read image '" + path + "': " + error);
    const auto nonfinite =
        std::count_if(film.rgb.begin(), film.rgb.end(), [](float v) { return !std::isfinite(v); });
    if (nonfinite > 0)
        std::cerr << "wsd: note: '" << path << "' holds " << nonfinite
                  << (nonfinite == 1 ? " value that is" : " values that are")
                  << " not finite: NaN and -inf are compared as black, +inf as white\n";
    image = to_display(film, eight_bit);
    return exit_code::ok;
}

std::string number(double v) {
    if (std::isinf(v)) return "inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

}  // namespace

int run_diff(const DiffArgs& args) {
    std::string error;
    if (!args.heatmap.empty()) {
        if (!known_image_format(args.heatmap))
            return fail(exit_code::usage, unknown_format_message(args.heatmap));
        if (!output_directory_exists(args.heatmap, error)) return fail(exit_code::io, error);
        // `wsd diff a.png b.png -o a.png` would replace an image compared with the heat map.
        for (const std::string& input : {args.a, args.b})
            if (same_path(input, args.heatmap))
                return fail(exit_code::usage,
                            "-o '" + args.heatmap + "' names the compared image '" + input + "'");
    }
    DisplayImage a, b;
    if (const int s = read_display(args.a, a); s != exit_code::ok) return s;
    if (const int s = read_display(args.b, b); s != exit_code::ok) return s;
    if (a.width != b.width || a.height != b.height)
        return fail(exit_code::input_error, "the images have different sizes: '" + args.a + "' is " +
                                                std::to_string(a.width) + "x" + std::to_string(a.height) +
                                                ", '" + args.b + "' is " + std::to_string(b.width) + "x" +
                                                std::to_string(b.height));
    const ImageMetrics m = compare(a, b);
    std::cout << "RMSE: " << number(m.rmse) << '\n'
              << "PSNR: " << number(m.psnr) << (std::isinf(m.psnr) ? "" : " dB") << '\n'
              << "max abs error: " << number(m.max_abs_error) << '\n'
              << "SSIM: " << number(m.ssim) << '\n'
              << std::flush;
    if (!args.heatmap.empty()) {
        double scale = 0;
        const DisplayImage heat = error_heatmap(a, b, scale);
        render::Film film;
        film.width = heat.width;
        film.height = heat.height;
        film.rgb.resize(heat.rgb.size());
        for (size_t i = 0; i < heat.rgb.size(); ++i)
            film.rgb[i] = static_cast<float>(render::srgb_decode(heat.rgb[i]));
        if (!write_image_file(args.heatmap, film, error)) return fail(exit_code::io, error);
        std::cerr << "heat map: " << args.heatmap << " (white = error " << number(scale) << ")\n";
    }
    return exit_code::ok;
}

}  // namespace wsd::app
