// Progressive rendering (render/progressive.h): the estimator on synthetic pixels of known
// variance, the planning rule, determinism across threads and regions with a target, a deadline
// that has passed before the first pass ends, and the estimate against the error measured from
// a long reference.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <random>

#include "render/pixel_estimate.h"
#include "render/progressive.h"
#include "tests/render/scene_builders.h"

using namespace wsd::test;
using wsd::render::display_value;
using wsd::render::estimated_rmse;
using wsd::render::Film;
using wsd::render::LightSampling;
using wsd::render::PixelEstimate;
using wsd::render::planned_samples;
using wsd::render::Progressive;
using wsd::render::Region;
using wsd::render::RenderOptions;
using wsd::render::SceneSpec;

namespace {

// A matte sphere on a floor under a jittered area light, with a point light: soft shadows and
// anti-aliased edges, at a size that is not a multiple of the tile size.
SceneSpec soft_scene(int width, int height) {
    auto spec = basic_scene(width, height, {0, 1.5, -5});
    spec.settings.background = {0.1, 0.2, 0.3};
    spec.shapes.push_back(plane({0, 1, 0}, -1, add_material(spec, matte({0.9, 0.9, 0.9}))));
    auto shiny = matte({0.8, 0.3, 0.2});
    shiny.reflection = 0.3;
    shiny.specular = 0.5;
    spec.shapes.push_back(sphere({-0.6, 0, 0.3}, 1, add_material(spec, shiny)));
    spec.shapes.push_back(sphere({1.2, -0.4, -0.5}, 0.6, add_material(spec, matte({0.2, 0.5, 0.9}))));
    spec.lights.push_back(area_light({0, 4, -1}, {3, 0, 0}, {0, 0, 3}, 4, 4, LightSampling::Jittered));
    spec.lights.push_back(point_light({-3, 3, -3}, 0.3));
    return spec;
}

RenderOptions progressive(double target, int threads = 2) {
    RenderOptions o;
    o.threads = threads;
    Progressive p;
    p.target_error = target;
    o.progressive = p;
    return o;
}

bool same_pixels(const Film& a, const Film& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// The display-space RMSE between two films, as `wsd diff` measures it (without 8-bit rounding).
double display_rmse(const Film& a, const Film& b) {
    double sum = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double d = display_value(a.rgb[i]) - display_value(b.rgb[i]);
        sum += d * d;
    }
    return std::sqrt(sum / double(a.rgb.size()));
}

}  // namespace

TEST_CASE("a pixel's display variance follows its samples' variance through the display curve",
          "[progressive]") {
    const auto decide = PixelEstimate::Decide, report = PixelEstimate::Report;
    PixelEstimate e;
    CHECK(std::isinf(e.display_variance(decide)));
    CHECK(std::isinf(e.display_variance(report)));
    e.add(Color(0.5));
    CHECK(std::isinf(e.display_variance(report)));  // no odd sample yet
    for (int i = 0; i < 2; ++i) e.add(Color(0.5));
    CHECK(e.display_variance(decide) == 0);  // samples 0 and 2
    CHECK(e.display_variance(report) == 0);  // the halves agree
    // Samples 0.2 ± 0.01 in the pattern − − + +: each half alternates, with sample variance
    // 0.01² · 32/31; the mean of all 64 has standard error 0.01 · √(32/31/64), in display space
    // times the sRGB curve's slope at 0.2. The halves' means agree: no reported error.
    PixelEstimate f;
    const int n = 64;
    for (int i = 0; i < n; ++i) f.add(Color((i / 2) % 2 ? 0.21 : 0.19));
    const double sigma = 0.01 * std::sqrt(32.0 / 31.0 / n);
    const double slope = (display_value(0.2 + 1e-6) - display_value(0.2 - 1e-6)) / 2e-6;
    CHECK(std::sqrt(f.display_variance(decide)) == Approx(slope * sigma).epsilon(1e-3));
    CHECK(f.display_variance(report) == 0);
    // The report is the halves' difference: even samples 0.19, odd 0.21, 32 each, give
    // (d/2)² with d the difference of their displayed values.
    PixelEstimate h;
    for (int i = 0; i < n; ++i) h.add(Color(i % 2 ? 0.21 : 0.19));
    CHECK(h.display_variance(decide) == 0);
    const double d = display_value(0.21) - display_value(0.19);
    CHECK(std::sqrt(h.display_variance(report)) == Approx(d / 2).epsilon(1e-9));
    CHECK(h.display_spread() == Approx(d).epsilon(1e-12));  // the largest difference as displayed
    CHECK(PixelEstimate{}.display_spread() == 0);
    // Unequal halves (5 even, 4 odd) weigh the difference by 5·4/9².
    PixelEstimate u;
    for (int i = 0; i < 9; ++i) u.add(Color(i % 2 ? 0.21 : 0.19));
    CHECK(u.display_variance(report) == Approx(d * d * 20.0 / 81.0).epsilon(1e-9));
    // Variation within a half alone does not show in the report: even samples 0.2 and 0.4, odd
    // ones 0.3, the same mean.
    PixelEstimate g;
    for (int i = 0; i < 8; ++i) g.add(Color(i % 2 ? 0.3 : (i % 4 ? 0.4 : 0.2)));
    CHECK(g.display_variance(decide) > 0);
    CHECK(g.display_variance(report) == Approx(0).margin(1e-12));
    // Above 1 everything displays as white: no display error.
    PixelEstimate white;
    for (int i = 0; i < 8; ++i) white.add(Color((i / 2) % 2 ? 3.0 : 5.0));
    CHECK(white.display_variance(decide) == 0);
    CHECK(white.display_variance(report) == 0);
}

TEST_CASE("the estimated RMSE of a synthetic image of known variance matches its actual error",
          "[progressive]") {
    // 4000 pixels with true value m (a ramp over [0.05, 0.8]) and n Gaussian samples of standard
    // deviation s: the actual display error of each mean against display(m), over the image,
    // against the estimate from the samples alone.
    std::mt19937_64 rng(7);
    for (const int n : {8, 32}) {
        for (const double s : {0.02, 0.1}) {
            std::vector<PixelEstimate> pixels(4000);
            double sum = 0;
            for (size_t i = 0; i < pixels.size(); ++i) {
                const double m = 0.05 + 0.75 * double(i) / double(pixels.size());
                std::normal_distribution<double> sample(m, s);
                for (int k = 0; k < n; ++k) pixels[i].add(Color(sample(rng), sample(rng), sample(rng)));
                const Color mean = pixels[i].mean();
                for (int c = 0; c < 3; ++c) {
                    const double d = display_value(mean[c]) - display_value(m);
                    sum += d * d;
                }
            }
            const double actual = std::sqrt(sum / (3.0 * double(pixels.size())));
            INFO("n " << n << " s " << s << " actual " << actual << " estimate " << estimated_rmse(pixels));
            CHECK(estimated_rmse(pixels) == Approx(actual).epsilon(0.1));
        }
    }
}

TEST_CASE("the estimated RMSE of a region counts that region's pixels only", "[progressive]") {
    // A 3 × 2 grid at (10, 20) whose pixel i (row by row) has samples 0 and 0.01·(i + 1): each
    // reports an error of its own.
    const Region grid{10, 20, 13, 22};
    std::vector<PixelEstimate> pixels(6);
    std::vector<double> report(6);
    for (size_t i = 0; i < 6; ++i) {
        pixels[i].add(Color(0));
        pixels[i].add(Color(0.01 * double(i + 1)));
        report[i] = pixels[i].display_variance(PixelEstimate::Report);
        REQUIRE(report[i] > 0);
    }
    // The part x in [11, 13), y = 21: pixels 4 and 5 of the grid.
    CHECK(estimated_rmse(pixels, grid, Region{11, 21, 13, 22}) ==
          Approx(std::sqrt((report[4] + report[5]) / 2)));
    CHECK(estimated_rmse(pixels, grid, grid) == Approx(estimated_rmse(pixels)));
    CHECK(estimated_rmse(pixels, grid, Region{11, 21, 11, 22}) == 0);  // no pixels
}

TEST_CASE("planned_samples: first pass, minimum, target, growth and maximum", "[progressive]") {
    Progressive o;
    o.min_samples = 8;
    PixelEstimate e;
    CHECK(planned_samples(e, 0.01, o) == 4);
    for (int i = 0; i < 4; ++i) e.add(Color(0.3));
    CHECK(planned_samples(e, 0.01, o) == 8);  // no variance, but below the minimum
    // A calm neighbourhood (first-pass spread at most the target) lets it stop at its first pass.
    CHECK(planned_samples(e, 0.01, o, 0.01) == 4);
    CHECK(planned_samples(e, 0.01, o, 0.02) == 8);
    for (int i = 0; i < 4; ++i) e.add(Color(0.3));
    CHECK(planned_samples(e, 0.01, o) == 8);  // converged
    PixelEstimate noisy;
    for (int i = 0; i < 8; ++i) noisy.add(Color((i / 2) % 2 ? 0.0 : 0.5));
    const uint32_t next = planned_samples(noisy, 0.01, o);
    CHECK(next == 16);  // far from the target: at most twice as many
    const double err = std::sqrt(noisy.display_variance(PixelEstimate::Decide));
    CHECK(planned_samples(noisy, err * 0.99, o) == 10);  // close to it: at least 1.25 times
    CHECK(planned_samples(noisy, err, o) == 8);
    o.max_samples = 12;
    CHECK(planned_samples(noisy, 0.01, o) == 12);
    for (int i = 0; i < 4; ++i) noisy.add(Color(0.5));
    CHECK(planned_samples(noisy, 0.01, o) == 12);
}

TEST_CASE("with a target the image is the same for any thread count and any region", "[progressive]") {
    const auto spec = soft_scene(37, 29);
    const auto one = render_spec(spec, progressive(0.03, 1));
    const auto three = render_spec(spec, progressive(0.03, 3));
    CHECK(one.progressive.used);
    CHECK(one.progressive.passes > 2);
    CHECK(one.progressive.samples_max > one.progressive.samples_min);
    CHECK(one.progressive.target_reached);
    CHECK(one.progressive.estimated_rmse <= 0.03 * 1.5);  // reported by the samples that did not decide
    CHECK(same_pixels(one.film, three.film));
    CHECK(one.progressive.samples == three.progressive.samples);
    for (const Region r : {Region{3, 5, 29, 22}, Region{17, 0, 18, 29}, Region{20, 16, 37, 29}}) {
        RenderOptions o = progressive(0.03);
        o.region = r;
        const auto part = render_spec(spec, o);
        bool same = true;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) {
                same = same && pixel(part.film, x - r.x0, y - r.y0) == pixel(one.film, x, y);
                same = same && part.progressive.samples[size_t((y - r.y0) * (r.x1 - r.x0) + (x - r.x0))] ==
                                   one.progressive.samples[size_t(y * 37 + x)];
            }
        CHECK(same);
    }
    // A tighter target takes more samples and lowers the estimate.
    const auto tighter = render_spec(spec, progressive(0.015));
    CHECK(tighter.progressive.samples_total > one.progressive.samples_total);
    CHECK(tighter.progressive.estimated_rmse < one.progressive.estimated_rmse);
}

TEST_CASE("a target that pixels stop short of at the sample cap is not reached", "[progressive]") {
    const auto spec = soft_scene(12, 9);
    RenderOptions o = progressive(0.0001);
    o.progressive->max_samples = 32;  // the cap, far below what 0.0001 needs
    const auto r = render_spec(spec, o);
    CHECK(r.progressive.samples_max == 32);
    CHECK_FALSE(r.progressive.deadline_reached);
    CHECK_FALSE(r.progressive.target_reached);
    // With a cap that lets every pixel meet a loose target, it is reached.
    const auto loose = render_spec(spec, progressive(0.05));
    CHECK(loose.progressive.target_reached);
    CHECK(loose.progressive.estimated_rmse <= 0.05);
}

TEST_CASE("a deadline passed during the first pass gives that pass, every pixel sampled", "[progressive]") {
    const auto spec = soft_scene(37, 29);
    RenderOptions o = progressive(0);
    o.progressive->deadline = std::chrono::steady_clock::now();  // over before the first pass ends
    const auto r = render_spec(spec, o);
    CHECK(r.progressive.passes == 1);
    CHECK(r.progressive.deadline_reached);
    CHECK(r.progressive.first_pass_over);
    CHECK(r.progressive.samples_min == 4);
    CHECK(r.progressive.samples_max == 4);
    CHECK(r.progressive.estimated_rmse > 0);
    // The first pass is the same samples the untimed render starts with: its image is the mean of
    // samples 0 to 3, deterministic.
    const auto again = render_spec(spec, o);
    CHECK(same_pixels(r.film, again.film));
}

TEST_CASE("the estimate is honest: the error measured against a long reference is within 1.5 times it",
          "[progressive]") {
    auto glassy = soft_scene(32, 24);
    glassy.shapes.push_back(sphere({0.4, -0.5, -1.5}, 0.5, add_material(glassy, glass(1.5, {1, 0.9, 0.8}))));
    auto small_light = soft_scene(32, 24);
    small_light.lights[0].u = {0.6, 0, 0};
    small_light.lights[0].v = {0, 0, 0.6};
    for (const SceneSpec* base : {&glassy, &small_light}) {
        SceneSpec ref_spec = *base;
        ref_spec.settings.seed = 99;                 // independent samples
        RenderOptions ref_options = progressive(0);  // 512 samples in every pixel
        ref_options.progressive->first_samples = 512;
        ref_options.progressive->max_samples = 512;
        const auto reference = render_spec(ref_spec, ref_options);
        for (const double target : {0.04, 0.02}) {
            const auto r = render_spec(*base, progressive(target));
            const double measured = display_rmse(r.film, reference.film);
            const double estimate = r.progressive.estimated_rmse;
            INFO("target " << target << " estimate " << estimate << " measured " << measured << " reference "
                           << reference.progressive.estimated_rmse);
            CHECK(reference.progressive.estimated_rmse < estimate / 3);
            CHECK(measured <= 1.5 * estimate);
            CHECK(measured >= estimate / 1.5);
        }
    }
}
