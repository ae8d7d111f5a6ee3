// Image files for textures: decoding through stb_image (8-bit sRGB → linear through the exact
// curve, 16-bit PNG through the same curve, HDR already linear), PFM (linear) through the image
// reader of image_io.h, the per-scene cache that loads each path once, and the bilinear lookup,
// wrapped or clamped (robustness.md: safe texture lookup, R49).
#include <stb_image.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

#include "render/file_util.h"
#include "render/image_check.h"
#include "render/image_io.h"
#include "render/texture.h"

namespace wsd::render {

namespace {

double srgb_curve(double c) {
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

const std::array<float, 256>& srgb8_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (size_t i = 0; i < 256; ++i)
            t[i] = static_cast<float>(srgb_curve(static_cast<double>(i) / 255.0));
        return t;
    }();
    return table;
}

std::string stb_reason() {
    const char* r = stbi_failure_reason();
    return r ? r : "unknown decoding error";
}

// Values a texture may hold: finite and >= 0. A PFM can store anything, NaN included; such a
// value is the file's error, at its pixel (x from the left, y from the top).
std::string bad_texel(const std::vector<float>& rgb, int width, const std::string& label) {
    static const char* const kChannel[3] = {"red", "green", "blue"};
    for (size_t i = 0; i < rgb.size(); ++i) {
        const float c = rgb[i];
        if (c >= 0.0f && std::isfinite(c)) continue;
        const size_t pixel = i / 3, w = static_cast<size_t>(width);
        const std::string value = std::isnan(c)   ? "NaN"
                                  : std::isinf(c) ? (c > 0 ? "+inf" : "-inf")
                                                  : "negative";
        return "image " + label + " holds a " + value + " " + kChannel[i % 3] + " value at pixel (" +
               std::to_string(pixel % w) + ", " + std::to_string(pixel / w) +
               "); texture values must be finite and at least 0";
    }
    return {};
}

std::shared_ptr<Image> decode_pfm(const std::string& path, const std::string& label, std::string& error) {
    Film film;
    if (!read_image(path, film, error)) return nullptr;
    if (static_cast<long long>(film.width) * film.height > kMaxImagePixels) {
        error = "image " + label + " is too large (" + std::to_string(film.width) + "x" +
                std::to_string(film.height) + "; at most " + std::to_string(kMaxImagePixels) + " pixels)";
        return nullptr;
    }
    auto image = std::make_shared<Image>();
    image->width = film.width;
    image->height = film.height;
    image->rgb = std::move(film.rgb);
    if (std::string why = bad_texel(image->rgb, image->width, label); !why.empty()) {
        error = std::move(why);
        return nullptr;
    }
    return image;
}

// Decodes an image file's bytes; `label` is the quoted path for messages.
std::shared_ptr<Image> decode(const FileBytes& bytes, const std::string& label, std::string& error) {
    if (bytes.size > size_t{INT_MAX}) {
        error = "cannot read image " + label + ": file too large";
        return nullptr;
    }
    const auto* file = reinterpret_cast<const unsigned char*>(bytes.data.get());
    if (const std::string why = incomplete_image_data(file, bytes.size); !why.empty()) {
        error = "cannot decode image " + label + ": " + why;
        return nullptr;
    }
    const int len = static_cast<int>(bytes.size);
    int w = 0, h = 0, n = 0;
    if (!stbi_info_from_memory(file, len, &w, &h, &n)) {
        error = "cannot decode image " + label + ": " + stb_reason();
        return nullptr;
    }
    // A truncated file can pass stb's header check with no size at all (a GIF cut after its
    // signature reads as 0x0): that is a broken file, not a large one.
    if (w <= 0 || h <= 0) {
        error = "cannot decode image " + label + ": the file is corrupt or in an unsupported format (" +
                "its header gives the size " + std::to_string(w) + "x" + std::to_string(h) + ")";
        return nullptr;
    }
    if (static_cast<long long>(w) * h > kMaxImagePixels) {
        error = "image " + label + " is too large (" + std::to_string(w) + "x" + std::to_string(h) +
                "; at most " + std::to_string(kMaxImagePixels) + " pixels)";
        return nullptr;
    }
    auto image = std::make_shared<Image>();
    const auto fail = [&] {
        error = "cannot decode image " + label + ": " + stb_reason();
        return nullptr;
    };
    if (stbi_is_hdr_from_memory(file, len)) {
        float* data = stbi_loadf_from_memory(file, len, &w, &h, &n, 3);
        if (!data) return fail();
        const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h) * 3;
        image->rgb.assign(data, data + count);
        stbi_image_free(data);
        // RGBE holds neither NaN nor negative values; checked all the same.
        if (std::string why = bad_texel(image->rgb, w, label); !why.empty()) {
            error = std::move(why);
            return nullptr;
        }
    } else if (stbi_is_16_bit_from_memory(file, len)) {
        stbi_us* data = stbi_load_16_from_memory(file, len, &w, &h, &n, 3);
        if (!data) return fail();
        const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h) * 3;
        image->rgb.resize(count);
        for (size_t i = 0; i < count; ++i)
            image->rgb[i] = static_cast<float>(srgb_curve(static_cast<double>(data[i]) / 65535.0));
        stbi_image_free(data);
    } else {
        stbi_uc* data = stbi_load_from_memory(file, len, &w, &h, &n, 3);
        if (!data) return fail();
        const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h) * 3;
        const auto& table = srgb8_table();
        image->rgb.resize(count);
        for (size_t i = 0; i < count; ++i) image->rgb[i] = table[data[i]];
        stbi_image_free(data);
    }
    image->width = w;
    image->height = h;
    return image;
}

// Texel index along an axis: wrap into [0, n) or clamp to it. i is in [-1, n] here.
inline size_t address(long long i, long long n, bool wrap) {
    if (wrap) {
        i %= n;
        if (i < 0) i += n;
    } else {
        i = std::clamp(i, 0LL, n - 1);
    }
    return static_cast<size_t>(i);
}

}  // namespace

float srgb8_to_linear(uint8_t v) {
    return srgb8_table()[v];
}

std::shared_ptr<const Image> load_image(const std::string& path, std::string& error) {
    const std::string label = "'" + path + "'";
    // Checked before opening too: opening a FIFO blocks until something writes to it.
    struct stat before {};
    if (::stat(path.c_str(), &before) == 0 && !S_ISREG(before.st_mode)) {
        error = "cannot read image " + label + ": not a regular file";
        return nullptr;
    }
    try {
        FileBytes bytes;
        std::string reason;
        if (!read_whole_file(path, bytes, reason)) {
            error = "cannot open image " + label + ": " + reason;
            return nullptr;
        }
        // PFM, the linear format wsd writes, which stb_image does not read: "PF" or "Pf" first.
        const std::string_view view = bytes.view();
        if (view.size() >= 2 && view[0] == 'P' && (view[1] == 'F' || view[1] == 'f'))
            return decode_pfm(path, label, error);
        return decode(bytes, label, error);
    } catch (const std::bad_alloc&) {
        error = "cannot load image " + label + ": out of memory";
        return nullptr;
    }
}

std::shared_ptr<const Image> ImageCache::get(const std::string& path, std::string& error) {
    if (auto it = images_.find(path); it != images_.end()) return it->second;
    auto image = load_image(path, error);
    // Failures are not cached: the caller reports them, and a retry should try the file again.
    if (image) images_.emplace(path, image);
    return image;
}

Color sample_image(const Image& image, Vec2 uv, bool wrap_v) {
    const long long w = image.width, h = image.height;
    if (w <= 0 || h <= 0 || image.rgb.size() < static_cast<size_t>(w * h * 3)) return Color(0.0);
    double u = std::isfinite(uv.x) ? uv.x : 0.0;
    double v = std::isfinite(uv.y) ? uv.y : 0.0;
    // Reduce to [0, 1] first so that huge coordinates never reach the integer conversion; the
    // integer addressing below handles the u = 1 that u − floor(u) gives for tiny negative u.
    u -= std::floor(u);
    v = wrap_v ? v - std::floor(v) : std::clamp(v, 0.0, 1.0);
    const double x = u * static_cast<double>(w) - 0.5;
    const double y = v * static_cast<double>(h) - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const auto xi = static_cast<long long>(x0), yi = static_cast<long long>(y0);
    const size_t c0 = address(xi, w, true), c1 = address(xi + 1, w, true);
    const size_t r0 = address(yi, h, wrap_v), r1 = address(yi + 1, h, wrap_v);
    const size_t stride = static_cast<size_t>(w);
    const auto texel = [&](size_t r, size_t c) {
        const float* p = &image.rgb[(r * stride + c) * 3];
        return Color(p[0], p[1], p[2]);
    };
    const Color top = (1.0 - fx) * texel(r0, c0) + fx * texel(r0, c1);
    const Color bottom = (1.0 - fx) * texel(r1, c0) + fx * texel(r1, c1);
    return (1.0 - fy) * top + fy * bottom;
}

}  // namespace wsd::render
