// Progressive passes over 16×16 tiles with parallel_for. Before each pass a serial scan plans
// every pixel's new sample count (planned_samples); a pass with nothing planned ends the render.
// Each thread traces its pixels' new samples as packets and adds them to the pixel's sums in
// sample order, so a pixel's value depends on its samples alone. The first pass also covers an
// apron of one pixel around the region (inside the image), whose first samples only serve the
// neighbourhood guard of planned_samples; the apron is neither refined nor written.
#include "render/progressive.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

#include "render/aov.h"
#include "render/geometry.h"
#include "render/integrator.h"
#include "render/sampling.h"
#include "render/scene.h"
#include "render/sequence.h"

namespace wsd::render {

namespace {

using Clock = std::chrono::steady_clock;

// The state every pass shares: the pixels' estimates and plans, and the counters summed once a
// tile under a lock (read by progress while a pass runs).
struct Passes {
    const Scene& scene;
    const RenderOptions& options;
    Region region;  // the rendered region and its apron: one pixel around it, inside the image
    Region inner;   // the rendered region
    std::vector<PixelEstimate> pixels;  // over `region`
    std::vector<float> calm;            // per pixel: the largest first-pass spread around it
    std::vector<AovSum> aov;            // with options.aovs
    std::vector<uint32_t> planned;      // this pass's sample count per pixel
    std::mutex mutex;
    RayStats stats;
    uint64_t samples_done = 0;  // in the running pass

    size_t index(int x, int y) const {
        return size_t(y - region.y0) * size_t(region.x1 - region.x0) + size_t(x - region.x0);
    }
    bool in_inner(int x, int y) const {
        return x >= inner.x0 && x < inner.x1 && y >= inner.y0 && y < inner.y1;
    }

    // The rendered region's estimated display-space RMSE.
    double inner_rmse() const { return estimated_rmse(pixels, region, inner); }
};

// One render thread's tracer and counters.
struct Worker {
    RayStats stats;
    std::unique_ptr<Tracer> tracer;
    std::unique_ptr<AovTracer> aov;
};

// The sequence key of one half of a pixel's samples (0: even sample indices, 1: odd): the two
// halves are independent randomisations, each stratified in itself.
uint64_t half_sequence(uint64_t pixel, uint32_t half) {
    return mix64(pixel ^ mix64((uint64_t(half) + 1) * kSequenceSalt));
}

// Traces the planned new samples of the pixels of tile `t`, as packets that may span pixels;
// each pixel's samples are added to its sums in sample order.
void refine_tile(Passes& p, Worker& w, const Region& t) {
    const uint32_t seed = p.scene.settings().seed;
    constexpr int kMax = Geometry::kMaxPacket;
    double px[kMax], py[kMax];
    uint64_t key[kMax], seq[kMax];
    uint32_t index[kMax];
    size_t owner[kMax];
    Color out[kMax];
    uint64_t traced = 0;
    int n = 0;
    auto flush = [&] {
        if (n == 0) return;
        w.tracer->sequence_samples(px, py, key, seq, index, n, out);
        for (int k = 0; k < n; ++k) {
            PixelEstimate& e = p.pixels[owner[k]];
            if (finite3(out[k])) {
                e.add(out[k]);
            } else {
                ++w.stats.nonfinite_samples;
                e.add(Color(0));
            }
            if (w.aov) p.aov[owner[k]].add(w.aov->sample(px[k], py[k]));
        }
        traced += uint64_t(n);
        n = 0;
    };
    for (int y = t.y0; y < t.y1; ++y) {
        for (int x = t.x0; x < t.x1; ++x) {
            const size_t i = p.index(x, y);
            const uint32_t target = p.planned[i];
            if (p.pixels[i].n >= target) continue;
            const uint64_t pk = pixel_key(seed, x, y);
            const uint64_t half_key[2] = {half_sequence(pk, 0), half_sequence(pk, 1)};
            for (uint32_t s = p.pixels[i].n; s < target; ++s) {
                key[n] = sample_key(pk, s);
                seq[n] = half_key[s & 1u];
                index[n] = s >> 1;
                owner[n] = i;
                const Uniform2 j = sobol2(index[n], seq[n] ^ kCameraSalt);
                px[n] = x + j.u;
                py[n] = y + j.v;
                if (++n == kMax) flush();
            }
        }
    }
    flush();
    std::lock_guard lock(p.mutex);
    p.stats += w.stats;
    w.stats = RayStats{};
    p.samples_done += traced;
}

// Plans the next pass at `target`; the number of samples it adds. The apron's pixels take their
// first pass only.
uint64_t plan_pass(Passes& p, double target, const Progressive& options) {
    uint64_t added = 0;
    for (int y = p.region.y0; y < p.region.y1; ++y) {
        for (int x = p.region.x0; x < p.region.x1; ++x) {
            const size_t i = p.index(x, y);
            const PixelEstimate& e = p.pixels[i];
            if (e.n > 0 && !p.in_inner(x, y)) {
                p.planned[i] = e.n;
                continue;
            }
            p.planned[i] = planned_samples(e, target, options, p.calm.empty() ? kNotCalm : double(p.calm[i]));
            added += p.planned[i] - e.n;
        }
    }
    return added;
}

// After the first pass: each pixel's largest first-pass spread over itself and its eight
// neighbours (those in the image; the apron holds the ones outside the region).
void measure_calm(Passes& p) {
    const int w = p.region.x1 - p.region.x0, h = p.region.y1 - p.region.y0;
    std::vector<float> spread(p.pixels.size());
    for (size_t i = 0; i < p.pixels.size(); ++i) spread[i] = float(p.pixels[i].display_spread());
    p.calm.assign(p.pixels.size(), 0.0f);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            float m = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int u = x + dx, v = y + dy;
                    if (u >= 0 && u < w && v >= 0 && v < h)
                        m = std::max(m, spread[size_t(v) * size_t(w) + size_t(u)]);
                }
            p.calm[size_t(y) * size_t(w) + size_t(x)] = m;
        }
    }
}

void write_film(const Passes& p, RenderResult& result) {
    size_t i = 0;
    for (int y = p.inner.y0; y < p.inner.y1; ++y) {
        for (int x = p.inner.x0; x < p.inner.x1; ++x, ++i) {
            const Color m = p.pixels[p.index(x, y)].mean();
            const float v[3] = {float(m.x), float(m.y), float(m.z)};
            const bool ok = std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
            if (!ok) ++result.stats.nonfinite_samples;  // a finite double too large for a float
            for (size_t k = 0; k < 3; ++k) result.film.rgb[3 * i + k] = ok ? v[k] : 0.0f;
            if (!p.aov.empty()) {
                const AovSample s = p.aov[p.index(x, y)].mean();
                for (int k = 0; k < 3; ++k) {
                    result.aovs.albedo[3 * i + size_t(k)] = float(s.albedo[k]);
                    result.aovs.normal[3 * i + size_t(k)] = float(s.normal[k]);
                }
                result.aovs.depth[i] = float(s.depth);
            }
        }
    }
}

// Whether the rendered region met `target`: every pixel by the estimate that decides (a pixel
// that stopped at max_samples, or at the deadline, above it did not) and the image by the
// estimate that is reported.
bool target_met(const Passes& p, double target, double rmse) {
    if (!(rmse <= target)) return false;
    for (int y = p.inner.y0; y < p.inner.y1; ++y)
        for (int x = p.inner.x0; x < p.inner.x1; ++x)
            if (!(p.pixels[p.index(x, y)].display_variance(PixelEstimate::Decide) <= target * target))
                return false;
    return true;
}

void report(const Passes& p, ProgressiveReport& r) {
    r.used = true;
    r.estimated_rmse = p.inner_rmse();
    std::vector<uint32_t> counts;
    counts.reserve(size_t(p.inner.x1 - p.inner.x0) * size_t(p.inner.y1 - p.inner.y0));
    for (int y = p.inner.y0; y < p.inner.y1; ++y)
        for (int x = p.inner.x0; x < p.inner.x1; ++x) counts.push_back(p.pixels[p.index(x, y)].n);
    r.samples.resize(counts.size());
    r.samples_total = 0;
    for (size_t i = 0; i < counts.size(); ++i) {
        r.samples[i] = float(counts[i]);
        r.samples_total += counts[i];
    }
    if (counts.empty()) return;
    const auto [lo, hi] = std::minmax_element(counts.begin(), counts.end());
    r.samples_min = *lo;
    r.samples_max = *hi;
    std::nth_element(counts.begin(), counts.begin() + std::ptrdiff_t(counts.size() / 2), counts.end());
    r.samples_median = counts[counts.size() / 2];
}

}  // namespace

uint32_t planned_samples(const PixelEstimate& e, double target, const Progressive& options, double calm) {
    const uint32_t max = uint32_t(std::max(options.max_samples, 1));
    if (e.n == 0) return std::min(uint32_t(std::max(options.first_samples, 1)), max);
    if (e.n >= max) return e.n;
    const double v = e.display_variance(PixelEstimate::Decide);
    const uint32_t min = std::min(uint32_t(std::max(options.min_samples, 1)), max);
    // Before `min_samples`, only a pixel whose samples all agree within the target may stop: the
    // few samples' variance alone would let edges that the first samples missed stop too early.
    if (v <= target * target && (e.n >= min || calm <= target)) return e.n;
    const double n = e.n;
    // The count that would meet the target if the sample variance held (1.1: a little margin).
    const double want = target > 0 ? n * v / (target * target) * 1.1 : 2 * n;
    const double next = std::clamp(std::ceil(want), std::ceil(1.25 * n), 2 * n);
    return std::clamp(uint32_t(std::min(next, double(max))), min, max);
}

double estimated_rmse(const std::vector<PixelEstimate>& pixels, const Region& grid, const Region& part) {
    const size_t width = size_t(grid.x1 - grid.x0);
    double sum = 0;
    for (int y = part.y0; y < part.y1; ++y)
        for (int x = part.x0; x < part.x1; ++x)
            sum += pixels[size_t(y - grid.y0) * width + size_t(x - grid.x0)].display_variance(
                PixelEstimate::Report);
    const double count = double(part.x1 - part.x0) * double(part.y1 - part.y0);
    return count > 0 ? std::sqrt(sum / count) : 0.0;
}

bool render_progressive(const Scene& scene, const RenderOptions& options, const Region& region,
                        const ParallelOptions& parallel_base, RenderResult& result) {
    const Progressive& prog = *options.progressive;
    const auto start = Clock::now();
    const Settings& settings = scene.settings();
    const Region apron{std::max(region.x0 - 1, 0), std::max(region.y0 - 1, 0),
                       std::min(region.x1 + 1, settings.width), std::min(region.y1 + 1, settings.height)};
    const size_t count = size_t(apron.x1 - apron.x0) * size_t(apron.y1 - apron.y0);
    Passes p{scene,
             options,
             apron,
             region,
             std::vector<PixelEstimate>(count),
             {},
             {},
             std::vector<uint32_t>(count),
             {},
             {},
             0};
    if (options.aovs) p.aov.resize(count);
    const std::vector<Region> tiles = render_tiles(apron);
    std::vector<std::unique_ptr<Worker>> workers(size_t(thread_count(options.threads)));
    const TracerOptions tracer_options{options.specialise, options.adaptive_lights, true};

    ProgressiveReport& out = result.progressive;
    int pass = 0;
    uint64_t pass_total = 1;
    ParallelOptions parallel = parallel_base;
    if (options.progress) {
        parallel.poll = [&] {
            RayStats stats;
            double within = 0;
            {
                std::lock_guard lock(p.mutex);
                stats = p.stats;
                within = double(p.samples_done) / double(pass_total);
            }
            double fraction = (pass + within) / (pass + 2);
            if (prog.deadline) {
                const double limit = std::chrono::duration<double>(*prog.deadline - start).count();
                const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
                fraction = limit > 0 ? std::max(fraction, elapsed / limit) : fraction;
            }
            options.progress(std::min(fraction, 0.99), stats);
        };
    }
    double target = 0;
    bool complete = true;
    while (true) {
        pass_total = plan_pass(p, target, prog);
        if (pass_total == 0) break;
        p.samples_done = 0;
        complete = parallel_for(tiles.size(), parallel, [&](size_t i, int id) {
            std::unique_ptr<Worker>& w = workers[size_t(id)];
            if (!w) {  // kept only once complete, should make_tracer throw
                auto made = std::make_unique<Worker>();
                made->tracer = make_tracer(scene, tracer_options, made->stats);
                if (options.aovs) made->aov = std::make_unique<AovTracer>(scene);
                w = std::move(made);
            }
            refine_tile(p, *w, tiles[i]);
        });
        if (!complete) break;
        if (pass == 0) measure_calm(p);
        ++pass;
        if (prog.deadline && Clock::now() >= *prog.deadline) {
            out.deadline_reached = true;
            out.first_pass_over = pass == 1;
            break;
        }
        // With a target every pass aims at it; without one, at the image's current estimate,
        // so that each pass refines the pixels whose error is above it.
        target = prog.target_error > 0 ? prog.target_error : p.inner_rmse();
    }
    result.stats += p.stats;
    out.passes = pass;
    if (!complete) return false;
    write_film(p, result);
    report(p, out);
    if (prog.target_error > 0) out.target_reached = target_met(p, prog.target_error, out.estimated_rmse);
    return true;
}

}  // namespace wsd::render
