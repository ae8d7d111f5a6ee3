// The stratified sequences of progressive rendering (render/sequence.h): prefixes of 2^k points
// are (0,k,2)-nets for any key, keys give different randomisations, and the two-half estimator
// of render/pixel_estimate.h is honest for stratified halves on an integrand of known mean.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <vector>

#include "render/pixel_estimate.h"
#include "render/progressive.h"
#include "render/sequence.h"

using wsd::render::Color;
using wsd::render::display_value;
using wsd::render::estimated_rmse;
using wsd::render::PixelEstimate;
using wsd::render::sobol2;
using wsd::render::Uniform2;

TEST_CASE("every prefix of 2^k points of a scrambled sequence is a (0,k,2)-net", "[sequence]") {
    for (const uint64_t key : {uint64_t(0), uint64_t(1), uint64_t(0x123456789abcdefULL), ~uint64_t(0)}) {
        std::vector<Uniform2> pts;
        for (uint32_t i = 0; i < 256; ++i) pts.push_back(sobol2(i, key));
        for (const Uniform2& p : pts) {
            CHECK(p.u >= 0);
            CHECK(p.u < 1);
            CHECK(p.v >= 0);
            CHECK(p.v < 1);
        }
        for (int k = 0; k <= 8; ++k) {
            const size_t count = size_t(1) << k;
            // Every shape 2^-a × 2^-(k−a) of elementary rectangle holds one point each.
            for (int a = 0; a <= k; ++a) {
                std::set<std::pair<int, int>> cells;
                for (size_t i = 0; i < count; ++i)
                    cells.insert({int(std::floor(pts[i].u * double(1 << a))),
                                  int(std::floor(pts[i].v * double(1 << (k - a))))});
                INFO("key " << key << " k " << k << " a " << a);
                CHECK(cells.size() == count);
            }
        }
    }
}

TEST_CASE("a sequence's points are fixed by index and key, and keys randomise them", "[sequence]") {
    const Uniform2 a = sobol2(5, 42), b = sobol2(5, 42), c = sobol2(5, 43);
    CHECK(a.u == b.u);
    CHECK(a.v == b.v);
    CHECK((a.u != c.u || a.v != c.v));
    // Over many keys, point 0 is uniform: its mean is near 1/2 in both coordinates.
    double su = 0, sv = 0;
    const int n = 20000;
    for (int k = 0; k < n; ++k) {
        const Uniform2 p = sobol2(0, uint64_t(k) * 0x9e3779b97f4a7c15ULL);
        su += p.u;
        sv += p.v;
    }
    CHECK(su / n == Approx(0.5).margin(0.01));
    CHECK(sv / n == Approx(0.5).margin(0.01));
}

TEST_CASE("the two-half estimate is honest for stratified halves, and the deciding one conservative",
          "[sequence]") {
    // 3000 pixels, each an edge at a random angle and offset: a sample is 0.2 on one side of it and
    // 0.7 on the other. The pixel's true value is the exact area fraction (found with many
    // samples of a third, independent sequence). Even samples come from one scrambled sequence,
    // odd ones from another, as progressive rendering draws them.
    for (const uint32_t n : {8u, 15u, 32u}) {
        std::vector<PixelEstimate> pixels(3000);
        double actual = 0, decide = 0;
        for (size_t i = 0; i < pixels.size(); ++i) {
            const uint64_t key = wsd::render::mix64(i + 1000 * n);
            const double angle = double(wsd::render::mix64(key) >> 11) * 0x1p-53 * 6.283185307179586;
            const double offset = double(wsd::render::mix64(key + 1) >> 11) * 0x1p-53 - 0.5;
            auto value = [&](Uniform2 p) {
                const double s = (p.u - 0.5) * std::cos(angle) + (p.v - 0.5) * std::sin(angle);
                return s < offset ? 0.2 : 0.7;
            };
            double truth = 0;
            for (uint32_t k = 0; k < 4096; ++k) truth += value(sobol2(k, key + 3));
            truth /= 4096;
            for (uint32_t s = 0; s < n; ++s) pixels[i].add(Color(value(sobol2(s >> 1, key + 1 + (s & 1u)))));
            const double d = display_value(pixels[i].mean().x) - display_value(truth);
            actual += d * d;
            decide += pixels[i].display_variance(PixelEstimate::Decide);
        }
        actual = std::sqrt(actual / double(pixels.size()));
        decide = std::sqrt(decide / double(pixels.size()));
        const double estimate = estimated_rmse(pixels);
        INFO("n " << n << " actual " << actual << " estimate " << estimate << " decide " << decide);
        CHECK(estimate == Approx(actual).epsilon(0.15));
        CHECK(decide > actual);
    }
}
