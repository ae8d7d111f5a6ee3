// render(): the image (or a region of it) cut into 16×16 tiles rendered by parallel_for. Each
// worker thread has its own tracer and RayStats (summed under a lock once per tile). Pixels: 1
// centre ray, or a jittered grid averaged (box filter), or adaptive supersampling in two phases:
// centre rays over the region plus a 1-pixel border, then the full grid where a neighbour's
// display value differs. Auxiliary images, when asked for, are traced per sample at the colour's
// sample positions and averaged the same way (render/aov.h).
#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <utility>

#include "render/aov.h"
#include "render/image_io.h"
#include "render/integrator.h"
#include "render/math.h"
#include "render/parallel.h"
#include "render/progressive.h"
#include "render/sampling.h"
#include "render/scene.h"

namespace wsd::render {

namespace {

// The sample index of the adaptive prepass's centre ray (distinct from the grid's indices).
constexpr uint32_t kCentreSample = 0xffffffffu;

using Clock = std::chrono::steady_clock;

size_t area(const Region& r) {
    return size_t(r.x1 - r.x0) * size_t(r.y1 - r.y0);
}

// The adaptive prepass: each pixel's centre sample over `rect` (the region plus a 1-pixel
// border, clipped to the image), and its display value (clamped, sRGB-encoded) for comparisons.
struct Prepass {
    Region rect;
    std::vector<Color> centre;
    std::vector<Vec3> display;
    std::vector<AovSample> centre_aov;  // when auxiliary images are rendered
    size_t index(int x, int y) const {
        return size_t(y - rect.y0) * size_t(rect.x1 - rect.x0) + size_t(x - rect.x0);
    }
};

// Renders tiles into a film (and the prepass) for one worker thread; with kAov, the auxiliary
// images too (a separate instantiation, so that the colour-only one runs exactly its own code).
// Once `cancel` holds true a tile stops at the next pixel (or 4×4 block), its film left part done.
template <bool kAov>
class TileRenderer {
public:
    // `aov` and `aov_film` are both null, or both set to render the auxiliary images too.
    TileRenderer(const Scene& scene, Tracer& tracer, RayStats& stats, Film& film, const Region& region,
                 Prepass& prepass, AovTracer* aov, AovFilm* aov_film, const std::atomic<bool>* cancel)
        : tracer_(tracer),
          aov_(aov),
          aov_film_(aov_film),
          stats_(stats),
          film_(film),
          region_(region),
          prepass_(prepass),
          seed_(scene.settings().seed),
          samples_(scene.settings().supersamples),
          grid_(supersample_grid(scene.settings().supersamples)),
          threshold_(scene.settings().aa_threshold),
          cancel_(cancel) {}

    void render(const Region& t) {
        if (samples_ == 1) {
            // One ray a pixel: the pixels' centre rays, a 4×4 block at a time (one packet).
            for_blocks(t, 0, [&](int x, int y, const Color& c) {
                store(x, y, guarded(c));
                if constexpr (kAov) store_aov(x, y, aov_->sample(x + 0.5, y + 0.5));
            });
            return;
        }
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (cancelled()) return;
                store(x, y, full_pixel(x, y));
            }
    }

    // Phase 1 of adaptive supersampling.
    void render_centres(const Region& t) {
        for_blocks(t, kCentreSample, [&](int x, int y, const Color& colour) {
            const size_t i = prepass_.index(x, y);
            prepass_.centre[i] = guarded(colour);
            const Color c = glm::clamp(prepass_.centre[i], 0.0, 1.0);
            prepass_.display[i] = {srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z)};
            if constexpr (kAov) prepass_.centre_aov[i] = aov_->sample(x + 0.5, y + 0.5);
        });
    }

    // Phase 2: the full grid where the centre value differs from one of its 4 neighbours' by more
    // than the threshold in some channel; the centre value elsewhere.
    void render_adaptive(const Region& t) {
        const Region& p = prepass_.rect;
        const size_t row = size_t(p.x1 - p.x0);
        auto differs = [&](size_t a, size_t b) {
            const Vec3 d = glm::abs(prepass_.display[a] - prepass_.display[b]);
            return d.x > threshold_ || d.y > threshold_ || d.z > threshold_;
        };
        for (int y = t.y0; y < t.y1; ++y) {
            for (int x = t.x0; x < t.x1; ++x) {
                if (cancelled()) return;
                const size_t i = prepass_.index(x, y);
                const bool refine = (x > p.x0 && differs(i, i - 1)) || (x + 1 < p.x1 && differs(i, i + 1)) ||
                                    (y > p.y0 && differs(i, i - row)) ||
                                    (y + 1 < p.y1 && differs(i, i + row));
                if (refine) {
                    ++stats_.adaptive_pixels;
                    store(x, y, full_pixel(x, y));
                } else {
                    store(x, y, prepass_.centre[i]);
                    if constexpr (kAov) store_aov(x, y, prepass_.centre_aov[i]);
                }
            }
        }
    }

private:
    bool cancelled() const { return cancel_ && cancel_->load(std::memory_order_relaxed); }

    Color guarded(const Color& c) {
        if (finite3(c)) return c;
        ++stats_.nonfinite_samples;
        return Color(0);
    }

    // The centre samples (sample index `sample`) of the pixels of `t`, traced a 4×4 block of
    // pixels at a time as one packet; done(x, y, colour) for each, row by row within a block.
    template <class Done>
    void for_blocks(const Region& t, uint32_t sample, Done done) {
        constexpr int kSide = 4;
        static_assert(kSide * kSide <= Geometry::kMaxPacket);
        for (int y = t.y0; y < t.y1; y += kSide) {
            for (int x = t.x0; x < t.x1; x += kSide) {
                if (cancelled()) return;
                double px[kSide * kSide], py[kSide * kSide];
                uint64_t key[kSide * kSide];
                int xs[kSide * kSide], ys[kSide * kSide], n = 0;
                for (int dy = 0; dy < kSide && y + dy < t.y1; ++dy) {
                    for (int dx = 0; dx < kSide && x + dx < t.x1; ++dx) {
                        xs[n] = x + dx, ys[n] = y + dy;
                        px[n] = xs[n] + 0.5, py[n] = ys[n] + 0.5;
                        key[n] = sample_key(pixel_key(seed_, xs[n], ys[n]), sample);
                        ++n;
                    }
                }
                Color out[kSide * kSide];
                tracer_.camera_samples(px, py, key, n, out);
                for (int k = 0; k < n; ++k) done(xs[k], ys[k], out[k]);
            }
        }
    }

    // The box-filtered average of the pixel's camera samples (1 = its centre), traced as
    // packets of up to Geometry::kMaxPacket and summed in grid order; the auxiliary images'
    // pixel is averaged over the same samples and stored here.
    Color full_pixel(int x, int y) {
        const uint64_t pk = pixel_key(seed_, x, y);
        if (samples_ == 1) {
            if constexpr (kAov) store_aov(x, y, aov_->sample(x + 0.5, y + 0.5));
            return guarded(tracer_.camera_sample(x + 0.5, y + 0.5, sample_key(pk, 0)));
        }
        Color sum(0);
        AovSum aov_sum;
        constexpr int kMax = Geometry::kMaxPacket;
        double px[kMax], py[kMax];
        uint64_t key[kMax];
        Color out[kMax];
        int n = 0;
        auto flush = [&] {
            tracer_.camera_samples(px, py, key, n, out);
            for (int k = 0; k < n; ++k) sum += guarded(out[k]);
            if constexpr (kAov)
                for (int k = 0; k < n; ++k) aov_sum.add(aov_->sample(px[k], py[k]));
            n = 0;
        };
        for (int r = 0; r < grid_.rows; ++r) {
            for (int c = 0; c < grid_.cols; ++c) {
                key[n] = sample_key(pk, uint32_t(r * grid_.cols + c));
                const Uniform2 j = camera_jitter(key[n]);
                px[n] = x + (c + j.u) / grid_.cols;
                py[n] = y + (r + j.v) / grid_.rows;
                if (++n == kMax) flush();
            }
        }
        if (n > 0) flush();
        if constexpr (kAov) store_aov(x, y, aov_sum.mean());
        return sum / double(samples_);
    }

    void store(int x, int y, const Color& c) {
        const size_t i = 3 * (size_t(y - region_.y0) * size_t(film_.width) + size_t(x - region_.x0));
        const float v[3] = {float(c.x), float(c.y), float(c.z)};
        const bool ok = std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
        if (!ok) ++stats_.nonfinite_samples;  // a finite double too large for a float
        for (int k = 0; k < 3; ++k) film_.rgb[i + size_t(k)] = ok ? v[k] : 0.0f;
    }

    void store_aov(int x, int y, const AovSample& s) {
        const size_t i = size_t(y - region_.y0) * size_t(film_.width) + size_t(x - region_.x0);
        for (int k = 0; k < 3; ++k) {
            aov_film_->albedo[3 * i + size_t(k)] = float(s.albedo[k]);
            aov_film_->normal[3 * i + size_t(k)] = float(s.normal[k]);
        }
        aov_film_->depth[i] = float(s.depth);
    }

    Tracer& tracer_;
    AovTracer* aov_;
    AovFilm* aov_film_;
    RayStats& stats_;
    Film& film_;
    Region region_;
    Prepass& prepass_;
    uint32_t seed_;
    int samples_;
    SampleGrid grid_;
    double threshold_;
    const std::atomic<bool>* cancel_;
};

// One render thread's state, made on its first tile: its tracer, its tile renderer and the
// counters they increment.
template <bool kAov>
struct Worker {
    RayStats stats;
    std::unique_ptr<Tracer> tracer;
    std::unique_ptr<AovTracer> aov;  // with kAov
    std::unique_ptr<TileRenderer<kAov>> tiles;
};

// The workers' counters and the work done so far (pixels, prepass pixels included), summed
// under a lock once per tile so that progress can report them while the render runs.
class Tally {
public:
    void add(RayStats& local, size_t work) {
        std::lock_guard lock(mutex_);
        total_ += local;
        work_ += work;
        local = RayStats{};
    }
    std::pair<RayStats, size_t> snapshot() {
        std::lock_guard lock(mutex_);
        return {total_, work_};
    }

private:
    std::mutex mutex_;
    RayStats total_;
    size_t work_ = 0;
};

Region clamped_region(const RenderOptions& options, const Settings& settings) {
    Region r = options.region.value_or(Region{0, 0, settings.width, settings.height});
    r.x0 = std::clamp(r.x0, 0, settings.width);
    r.x1 = std::clamp(r.x1, r.x0, settings.width);
    r.y0 = std::clamp(r.y0, 0, settings.height);
    r.y1 = std::clamp(r.y1, r.y0, settings.height);
    return r;
}

// The adaptive prepass's storage over the region plus a 1-pixel border, clipped to the image.
Prepass make_prepass(const Region& region, const Settings& settings, bool aovs) {
    Prepass p;
    p.rect = {std::max(region.x0 - 1, 0), std::max(region.y0 - 1, 0), std::min(region.x1 + 1, settings.width),
              std::min(region.y1 + 1, settings.height)};
    p.centre.resize(area(p.rect));
    p.display.resize(area(p.rect));
    if (aovs) p.centre_aov.resize(area(p.rect));
    return p;
}

// What render_tiles needs of render()'s setup.
struct RenderJob {
    const Scene& scene;
    const RenderOptions& options;
    const Region& region;
    Film& film;
    AovFilm& aovs;  // sized when kAov
    Prepass& prepass;
    bool adaptive;
    Tally& tally;
    const ParallelOptions& parallel;
};

// Renders the region (after the adaptive prepass) with one TileRenderer<kAov> a thread; false
// when cancelled.
template <bool kAov>
bool render_tiles(const RenderJob& job) {
    std::vector<std::unique_ptr<Worker<kAov>>> workers(size_t(thread_count(job.options.threads)));
    const TracerOptions tracer_options{job.options.specialise, job.options.adaptive_lights};
    // Renders every tile of `rect` with tile(renderer, tile); false when cancelled.
    auto run = [&](const Region& rect, void (TileRenderer<kAov>::*tile)(const Region&)) {
        const std::vector<Region> tiles = render_tiles(rect);
        return parallel_for(tiles.size(), job.parallel, [&](size_t i, int id) {
            std::unique_ptr<Worker<kAov>>& w = workers[size_t(id)];
            if (!w) {  // kept only once complete, should make_tracer throw
                auto made = std::make_unique<Worker<kAov>>();
                made->tracer = make_tracer(job.scene, tracer_options, made->stats);
                if constexpr (kAov) made->aov = std::make_unique<AovTracer>(job.scene);
                made->tiles = std::make_unique<TileRenderer<kAov>>(
                    job.scene, *made->tracer, made->stats, job.film, job.region, job.prepass, made->aov.get(),
                    kAov ? &job.aovs : nullptr, job.options.cancel);
                w = std::move(made);
            }
            (w->tiles.get()->*tile)(tiles[i]);
            job.tally.add(w->stats, area(tiles[i]));
        });
    };
    // A tile cut short by cancellation still counts as run: the flag decides.
    auto cancelled = [&] { return job.options.cancel && job.options.cancel->load(); };
    bool complete = true;
    if (job.adaptive) complete = run(job.prepass.rect, &TileRenderer<kAov>::render_centres) && !cancelled();
    if (complete)
        complete = run(job.region,
                       job.adaptive ? &TileRenderer<kAov>::render_adaptive : &TileRenderer<kAov>::render) &&
                   !cancelled();
    return complete;
}

}  // namespace

std::vector<Region> render_tiles(const Region& r) {
    std::vector<Region> tiles;
    for (int y = r.y0; y < r.y1; y += kRenderTile)
        for (int x = r.x0; x < r.x1; x += kRenderTile)
            tiles.push_back({x, y, std::min(x + kRenderTile, r.x1), std::min(y + kRenderTile, r.y1)});
    return tiles;
}

RenderResult render(const Scene& scene, const RenderOptions& options) {
    const auto start = Clock::now();
    RenderResult result;
    result.build_seconds = scene.build_seconds();
    EffectSet effects = scene.effects();
    if (options.adaptive_lights && scene.has_multi_cell_area_light()) effects.add(Effect::AdaptiveLights);
    result.effects = effects.names();

    const Settings& settings = scene.settings();
    const Region region = clamped_region(options, settings);
    Film& film = result.film;
    film = {region.x1 - region.x0, region.y1 - region.y0, std::vector<float>(area(region) * 3, 0.0f)};
    const bool adaptive = !options.progressive && settings.adaptive_supersampling &&
                          settings.supersamples > 1 && area(region) > 0;
    Prepass prepass = adaptive ? make_prepass(region, settings, options.aovs) : Prepass{};
    if (options.aovs)
        result.aovs = {std::vector<float>(area(region) * 3, 0.0f),
                       std::vector<float>(area(region) * 3, 0.0f),
                       std::vector<float>(area(region), 0.0f),
                       {}};
    const double total_work = std::max(1.0, double(area(region)) + double(prepass.centre.size()));

    Tally tally;
    ParallelOptions parallel{options.threads, options.cancel, {}};
    if (options.progress) {
        parallel.poll = [&] {
            const auto [stats, work] = tally.snapshot();
            options.progress(double(work) / total_work, stats);
        };
    }
    bool complete = true;
    if (options.progressive) {
        complete = render_progressive(scene, options, region,
                                      ParallelOptions{options.threads, options.cancel, {}}, result);
    } else {
        const RenderJob job{scene, options, region, film, result.aovs, prepass, adaptive, tally, parallel};
        complete = options.aovs ? render_tiles<true>(job) : render_tiles<false>(job);
        result.stats = tally.snapshot().first;
    }
    result.stats.photons_shot = scene.caustic_build().shot;
    result.stats.photons_stored = scene.caustic_build().stored;
    result.photon_seconds = scene.caustic_build().seconds;
    if (!scene.caustic_build().skipped.empty())
        result.effects.push_back("caustics skipped: " + scene.caustic_build().skipped);
    result.cancelled = !complete;
    if (options.progress && complete) options.progress(1.0, result.stats);
    result.render_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
}

}  // namespace wsd::render
