// Progressive passes over 16×16 tiles with parallel_for. Before each pass a serial scan plans
// every pixel's new sample count (planned_samples); a pass with nothing planned ends the render.
// Each thread traces its pixels' new samples as packets and adds them to the pixel's sums in
// sample order, so a pixel's value depends on its samples alone.
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

namespace wsd::render {

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kTileSize = 16;

std::vector<Region> tiles_of(const Region& r) {
    std::vector<Region> tiles;
    for (int y = r.y0; y < r.y1; y += kTileSize)
        for (int x = r.x0; x < r.x1; x += kTileSize)
            tiles.push_back({x, y, std::min(x + kTileSize, r.x1), std::min(y + kTileSize, r.y1)});
    return tiles;
}

// The state every pass shares: the pixels' estimates and plans, and the counters summed once a
// tile under a lock (read by progress while a pass runs).
struct Passes {
    const Scene& scene;
    const RenderOptions& options;
    Region region;
    std::vector<PixelEstimate> pixels;
    std::vector<AovSum> aov;        // with options.aovs
    std::vector<uint32_t> planned;  // this pass's sample count per pixel
    std::mutex mutex;
    RayStats stats;
    uint64_t samples_done = 0;  // in the running pass

    size_t index(int x, int y) const {
        return size_t(y - region.y0) * size_t(region.x1 - region.x0) + size_t(x - region.x0);
    }
};

// One render thread's tracer and counters.
struct Worker {
    RayStats stats;
    std::unique_ptr<Tracer> tracer;
    std::unique_ptr<AovTracer> aov;
};

// Traces the planned new samples of the pixels of tile `t`.
void refine_tile(Passes& p, Worker& w, const Region& t) {
    const uint32_t seed = p.scene.settings().seed;
    constexpr int kMax = Geometry::kMaxPacket;
    double px[kMax], py[kMax];
    uint64_t key[kMax];
    Color out[kMax];
    uint64_t traced = 0;
    for (int y = t.y0; y < t.y1; ++y) {
        for (int x = t.x0; x < t.x1; ++x) {
            const size_t i = p.index(x, y);
            PixelEstimate& e = p.pixels[i];
            const uint64_t pk = pixel_key(seed, x, y);
            const uint32_t target = p.planned[i];
            for (uint32_t s = e.n; s < target;) {
                int n = 0;
                for (; n < kMax && s < target; ++n, ++s) {
                    key[n] = sample_key(pk, s);
                    const Uniform2 j = camera_jitter(key[n]);
                    px[n] = x + j.u;
                    py[n] = y + j.v;
                }
                w.tracer->camera_samples(px, py, key, n, out);
                for (int k = 0; k < n; ++k) {
                    if (finite3(out[k])) {
                        e.add(out[k]);
                    } else {
                        ++w.stats.nonfinite_samples;
                        e.add(Color(0));
                    }
                    if (w.aov) p.aov[i].add(w.aov->sample(px[k], py[k]));
                }
                traced += uint64_t(n);
            }
        }
    }
    std::lock_guard lock(p.mutex);
    p.stats += w.stats;
    w.stats = RayStats{};
    p.samples_done += traced;
}

// Plans the next pass at `target`; the number of samples it adds.
uint64_t plan_pass(Passes& p, double target, const Progressive& options) {
    uint64_t added = 0;
    for (size_t i = 0; i < p.pixels.size(); ++i) {
        p.planned[i] = planned_samples(p.pixels[i], target, options);
        added += p.planned[i] - p.pixels[i].n;
    }
    return added;
}

void write_film(const Passes& p, RenderResult& result) {
    for (size_t i = 0; i < p.pixels.size(); ++i) {
        const Color m = p.pixels[i].mean();
        const float v[3] = {float(m.x), float(m.y), float(m.z)};
        const bool ok = std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
        if (!ok) ++result.stats.nonfinite_samples;  // a finite double too large for a float
        for (size_t k = 0; k < 3; ++k) result.film.rgb[3 * i + k] = ok ? v[k] : 0.0f;
        if (!p.aov.empty()) {
            const AovSample s = p.aov[i].mean();
            for (int k = 0; k < 3; ++k) {
                result.aovs.albedo[3 * i + size_t(k)] = float(s.albedo[k]);
                result.aovs.normal[3 * i + size_t(k)] = float(s.normal[k]);
            }
            result.aovs.depth[i] = float(s.depth);
        }
    }
}

void report(const Passes& p, ProgressiveReport& r) {
    r.used = true;
    r.estimated_rmse = estimated_rmse(p.pixels);
    std::vector<uint32_t> counts(p.pixels.size());
    r.samples.resize(p.pixels.size());
    r.samples_total = 0;
    for (size_t i = 0; i < p.pixels.size(); ++i) {
        counts[i] = p.pixels[i].n;
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

uint32_t planned_samples(const PixelEstimate& e, double target, const Progressive& options) {
    const uint32_t max = uint32_t(std::max(options.max_samples, 1));
    if (e.n == 0) return std::min(uint32_t(std::max(options.first_samples, 1)), max);
    if (e.n >= max) return e.n;
    const double v = e.display_variance(PixelEstimate::Decide);
    const uint32_t min = std::min(uint32_t(std::max(options.min_samples, 1)), max);
    if (e.n >= min && v <= target * target) return e.n;
    const double n = e.n;
    // The count that would meet the target if the sample variance held (1.1: a little margin).
    const double want = target > 0 ? n * v / (target * target) * 1.1 : 2 * n;
    const double next = std::clamp(std::ceil(want), std::ceil(1.25 * n), 2 * n);
    return std::clamp(uint32_t(std::min(next, double(max))), min, max);
}

double estimated_rmse(const std::vector<PixelEstimate>& pixels) {
    if (pixels.empty()) return 0;
    double sum = 0;
    for (const PixelEstimate& e : pixels) sum += e.display_variance(PixelEstimate::Report);
    return std::sqrt(sum / double(pixels.size()));
}

bool render_progressive(const Scene& scene, const RenderOptions& options, const Region& region,
                        const ParallelOptions& parallel_base, RenderResult& result) {
    const Progressive& prog = *options.progressive;
    const auto start = Clock::now();
    const size_t count = size_t(region.x1 - region.x0) * size_t(region.y1 - region.y0);
    Passes p{scene, options, region, std::vector<PixelEstimate>(count), {}, std::vector<uint32_t>(count),
             {},    {},      0};
    if (options.aovs) p.aov.resize(count);
    const std::vector<Region> tiles = tiles_of(region);
    std::vector<std::unique_ptr<Worker>> workers(size_t(thread_count(options.threads)));
    const TracerOptions tracer_options{options.specialise, options.adaptive_lights};

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
        ++pass;
        if (prog.deadline && Clock::now() >= *prog.deadline) {
            out.deadline_reached = true;
            out.first_pass_over = pass == 1;
            break;
        }
        // With a target every pass aims at it; without one, at the image's current estimate,
        // so that each pass refines the pixels whose error is above it.
        target = prog.target_error > 0 ? prog.target_error : estimated_rmse(p.pixels);
    }
    result.stats += p.stats;
    out.passes = pass;
    if (!complete) return false;
    write_film(p, result);
    report(p, out);
    if (prog.target_error > 0) {
        out.target_reached = !out.deadline_reached || plan_pass(p, prog.target_error, prog) == 0;
    }
    return true;
}

}  // namespace wsd::render
