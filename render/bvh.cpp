// Binned SAH BVH builder (see bvh.h). Primitive references (bounds + id, 32 bytes) are
// partitioned in place so every pass reads memory in order; children's bounds come from the bins,
// their centroid bounds from the partition pass. Subtrees above kSubtreeMin primitives go to
// another thread when one is idle, into their own node arrays that are spliced in afterwards.
#include "render/bvh.h"

#include <algorithm>

#include "render/parallel.h"
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <atomic>
#include <bit>
#include <functional>
#include <limits>
#include <thread>

namespace wsd::render {

namespace {

// Four floats with min/max: SSE where the target has it (every x86-64), scalar elsewhere.
#if defined(__SSE2__)
struct F4 {
    __m128 v;
    static F4 load(const float* p) { return {_mm_loadu_ps(p)}; }
    static F4 load_xyz(const float* p) {  // lane 3 zeroed
        return {_mm_and_ps(_mm_loadu_ps(p), _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)))};
    }
    static F4 splat(float x) { return {_mm_set1_ps(x)}; }
    void store(float* p) const { _mm_storeu_ps(p, v); }
    friend F4 min(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
    friend F4 max(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
    friend F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
    friend F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
    friend F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
    void truncate_to(int* k) const {
        alignas(16) int32_t out[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(v));
        k[0] = out[0], k[1] = out[1], k[2] = out[2];
    }
};
#else
struct F4 {
    float v[4];
    static F4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
    static F4 load_xyz(const float* p) { return {{p[0], p[1], p[2], 0.0f}}; }
    static F4 splat(float x) { return {{x, x, x, x}}; }
    void store(float* p) const { std::copy(v, v + 4, p); }
    template <class Op>
    static F4 zip(F4 a, F4 b, Op op) {
        return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
    }
    friend F4 min(F4 a, F4 b) {
        return zip(a, b, [](float x, float y) { return x < y ? x : y; });
    }
    friend F4 max(F4 a, F4 b) {
        return zip(a, b, [](float x, float y) { return x > y ? x : y; });
    }
    friend F4 operator+(F4 a, F4 b) {
        return zip(a, b, [](float x, float y) { return x + y; });
    }
    friend F4 operator-(F4 a, F4 b) {
        return zip(a, b, [](float x, float y) { return x - y; });
    }
    friend F4 operator*(F4 a, F4 b) {
        return zip(a, b, [](float x, float y) { return x * y; });
    }
    void truncate_to(int* k) const {
        for (int a = 0; a < 3; ++a) k[a] = static_cast<int>(v[a]);
    }
};
#endif

// A primitive reference: its bounds, with its id in the fourth lane of lo (boxes ignore that
// lane). Centroids are kept doubled (lo + hi) throughout; only their order matters.
struct alignas(16) Ref {
    Ref() {}  // uninitialised: the references are written in parallel, not zeroed first
    Ref(const Bounds3f& b, uint32_t id)
        : lo{b.lo.x, b.lo.y, b.lo.z, std::bit_cast<float>(id)}, hi{b.hi.x, b.hi.y, b.hi.z, 0.0f} {}
    float lo[4];
    float hi[4];  // hi[3] == 0
    // The bounds as vectors. The id's bits read as a float are a denormal, and arithmetic on
    // denormals takes a slow microcode path (it made the whole build twice as slow): lo4 hides it.
    F4 lo4() const { return F4::load_xyz(lo); }
    F4 hi4() const { return F4::load(hi); }
    float c2(int a) const { return lo[a] + hi[a]; }
    uint32_t id() const { return std::bit_cast<uint32_t>(lo[3]); }
};

struct Box {
    static constexpr float kInf = std::numeric_limits<float>::infinity();
    F4 lo = F4::splat(kInf), hi = F4::splat(-kInf);
    void extend(F4 l, F4 h) {
        lo = min(lo, l);
        hi = max(hi, h);
    }
    void extend(const Box& b) { extend(b.lo, b.hi); }
    void extend_point(F4 p) { extend(p, p); }
    void get(float* l, float* h) const {
        lo.store(l);
        hi.store(h);
    }
    float extent(int a) const {
        float l[4], h[4];
        get(l, h);
        return h[a] - l[a];
    }
    float half_area() const {
#if defined(__SSE2__)
        // The same operations in the same order as below, without storing the box.
        if (_mm_comigt_ss(lo.v, hi.v)) return 0;
        const __m128 d = _mm_sub_ps(hi.v, lo.v);                                        // x y z
        const __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));  // xy yz zx
        return _mm_cvtss_f32(p) + _mm_cvtss_f32(_mm_shuffle_ps(p, p, 1)) + _mm_cvtss_f32(_mm_movehl_ps(p, p));
#else
        float l[4], h[4];
        get(l, h);
        if (l[0] > h[0]) return 0;
        float x = h[0] - l[0], y = h[1] - l[1], z = h[2] - l[2];
        return x * y + y * z + z * x;
#endif
    }
};

struct Range {
    uint32_t begin = 0, end = 0;
    Box box, cbox;  // bounds of the primitives and of their (doubled) centroids
};

constexpr uint32_t kSubtreeMin = 1u << 14;
constexpr int kSahDepthCap = 40;  // past it, object-median splits keep the depth < 64
constexpr int kMaxBins = 64;
// Nodes above depth kTopDepth (at most 255 of them) are binned with kTopBins to an axis. Their
// centroid bounds span the whole scene, and with 16 bins an object small against it (a mesh in
// a room) fell into a few bins: on a 10⁶-triangle mesh in a room of 12 triangles this cut the
// boxes a camera ray tests by a quarter (86.7 to 65.4; 58.5 to 46.5 at 10⁴ triangles), as 64
// bins at every node did, for the binning of a few hundred nodes.
constexpr int kTopDepth = 8;
constexpr int kTopBins = 64;
// Ranges of at least kChunkedBinMin references are binned in kBinChunks fixed chunks whose bins
// are merged in chunk order, on two threads when one is idle: the same chunks and the same merge
// whatever the thread count, so the split (and every bound, down to the sign of a zero) is too.
constexpr uint32_t kChunkedBinMin = 1u << 16;
constexpr uint32_t kBinChunks = 32;
constexpr uint32_t kTwoSetMin = 64;  // bin_range's second set of bins pays from this many references

struct Shared {
    HugePageVector<Ref>& refs;
    BvhOptions opt;
    std::atomic<int> idle;
    // Called once every subtree is built, before the root's own subtree from another thread is
    // spliced in (the references are then no longer needed: see build_bvh).
    std::function<void()> built;
};

struct Task {
    HugePageVector<BvhNode> nodes;
    int depth = 0;
};

void set_bounds(BvhNode& n, const Box& b) {
    float l[4], h[4];
    b.get(l, h);
    for (int a = 0; a < 3; ++a) {
        n.b[a] = l[a];
        n.b[a + 3] = h[a];
    }
}

struct Split {
    int axis = -1;
    int bin = 0;  // left side takes bins [0, bin]
    float cost = 0;
    Box left, right;
};

struct Binning {
    int nb = 1;
    F4 cmin = F4::splat(0), scale = F4::splat(0);
    float cmin_s[4] = {}, scale_s[4] = {};
    int index(float c, int a) const {
        int k = static_cast<int>((c - cmin_s[a]) * scale_s[a]);
        return k < 0 ? 0 : (k >= nb ? nb - 1 : k);
    }
    // The bins of a (doubled) centroid on all three axes: clamping before truncating gives
    // the same bins as index() (truncation toward zero maps (-1, 0) to 0 either way).
    void indices(F4 c2, int* k) const {
        F4 f = min(max((c2 - cmin) * scale, F4::splat(0)), F4::splat(static_cast<float>(nb - 1)));
        f.truncate_to(k);
    }
};

struct Bin {
    Box box;
    uint32_t count;
};

// Left uninitialised on purpose (a union with an empty constructor: Box's own initialisers
// would write all 3 × kMaxBins bins for every node, most of a small node's binning time);
// bin_range resets only the bins it uses.
struct BinSet {
    BinSet() {}
    union {
        Bin bins[3][kMaxBins];
    };
    Bin* operator[](int a) { return bins[a]; }
    const Bin* operator[](int a) const { return bins[a]; }
};

void merge_bins(BinSet& into, const BinSet& from, int nb) {
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k < nb; ++k) {
            into[a][k].box.extend(from[a][k].box);
            into[a][k].count += from[a][k].count;
        }
}

// Bins references [begin, end) into `out` (its first binning.nb bins per axis).
void bin_range(const Shared& s, const Binning& binning, uint32_t begin, uint32_t end, BinSet& out) {
    // Two sets of bins, taking the references in turn: consecutive references often fall into
    // the same bin, and with one set each update would wait for the previous one's stores. Bins
    // are merged exactly (min, max, integer counts), so the split is the same as with one set.
    const int nb = binning.nb;
    auto add = [&binning](BinSet& set, const Ref& ref) {
        F4 lo = ref.lo4(), hi = ref.hi4();
        int k[3];
        binning.indices(lo + hi, k);
        for (int a = 0; a < 3; ++a) {
            Bin& b = set[a][k[a]];
            b.box.extend(lo, hi);
            ++b.count;
        }
    };
    const auto reset = [nb](BinSet& set) {
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < nb; ++k) set[a][k] = Bin{Box{}, 0};
    };
    reset(out);
    if (end - begin < kTwoSetMin) {
        // Few references: one set, the first, third, ... references before the second, fourth,
        // ... ones. That gives the same bins as two sets merged: min and max keep, of equal
        // values (+0 and -0), the later operand, which is the later reference in this order,
        // and the second set's when merged.
        for (uint32_t i = begin; i < end; i += 2) add(out, s.refs[i]);
        for (uint32_t i = begin + 1; i < end; i += 2) add(out, s.refs[i]);
        return;
    }
    BinSet other;
    reset(other);
    uint32_t i = begin;
    for (; i + 1 < end; i += 2) {
        add(out, s.refs[i]);
        add(other, s.refs[i + 1]);
    }
    if (i < end) add(out, s.refs[i]);
    merge_bins(out, other, nb);
}

ParallelOptions with_threads(int threads) {
    ParallelOptions o;
    o.threads = threads;
    return o;
}

// Claims an idle thread, if there is one.
bool claim_thread(Shared& s) {
    if (s.idle.fetch_sub(1) > 0) return true;
    s.idle.fetch_add(1);
    return false;
}

// Best SAH split over all three axes (axis -1 when the centroids do not spread) for a node at
// `depth`.
Split find_split(Shared& s, const Range& r, Binning& binning, int depth) {
    const uint32_t n = r.end - r.begin;
    const int wanted = depth < kTopDepth ? std::max(s.opt.bins, kTopBins) : s.opt.bins;
    const int nb = std::min({wanted, kMaxBins, static_cast<int>(n < 4 ? 4 : n)});
    binning.nb = nb;
    bool spread = false;
    float cl[4], ch[4];
    r.cbox.get(cl, ch);
    for (int a = 0; a < 3; ++a) {
        float ext = ch[a] - cl[a];
        binning.cmin_s[a] = cl[a];
        binning.scale_s[a] = ext > 0 ? static_cast<float>(nb) / ext : 0.0f;
        spread = spread || ext > 0;
    }
    binning.cmin = F4::load(binning.cmin_s);
    binning.scale = F4::load(binning.scale_s);
    Split best;
    if (!spread) return best;

    BinSet bins;
    if (n < kChunkedBinMin) {
        bin_range(s, binning, r.begin, r.end, bins);
    } else {
        std::vector<BinSet> chunk(kBinChunks);
        auto run = [&](size_t c) {
            const uint32_t b = r.begin + static_cast<uint32_t>(uint64_t{n} * c / kBinChunks);
            const uint32_t e = r.begin + static_cast<uint32_t>(uint64_t{n} * (c + 1) / kBinChunks);
            bin_range(s, binning, b, e, chunk[c]);
        };
        if (claim_thread(s)) {
            parallel_for(kBinChunks, with_threads(2), [&](size_t c, int) { run(c); });
            s.idle.fetch_add(1);
        } else {
            for (size_t c = 0; c < kBinChunks; ++c) run(c);
        }
        bins = chunk[0];
        for (size_t c = 1; c < kBinChunks; ++c) merge_bins(bins, chunk[c], nb);
    }
    for (int a = 0; a < 3; ++a) {
        if (!(ch[a] - cl[a] > 0)) continue;
        float right_area[kMaxBins];
        uint32_t right_count[kMaxBins];
        Box acc;
        uint32_t nr = 0;
        for (int k = nb - 1; k > 0; --k) {
            acc.extend(bins[a][k].box);
            nr += bins[a][k].count;
            right_area[k] = acc.half_area();
            right_count[k] = nr;
        }
        Box left;
        uint32_t nl = 0;
        for (int k = 0; k < nb - 1; ++k) {
            left.extend(bins[a][k].box);
            nl += bins[a][k].count;
            uint32_t nrk = right_count[k + 1];
            if (nl == 0 || nrk == 0) continue;
            float cost =
                left.half_area() * static_cast<float>(nl) + right_area[k + 1] * static_cast<float>(nrk);
            if (best.axis < 0 || cost < best.cost) {
                best.axis = a;
                best.bin = k;
                best.cost = cost;
                best.left = left;
            }
        }
        if (best.axis == a) {
            Box right;
            for (int k = best.bin + 1; k < nb; ++k) right.extend(bins[a][k].box);
            best.right = right;
        }
    }
    return best;
}

void bounds_of(const Shared& s, Range& r) {
    r.box = Box{};
    r.cbox = Box{};
    for (uint32_t i = r.begin; i < r.end; ++i) {
        F4 lo = s.refs[i].lo4(), hi = s.refs[i].hi4();
        r.box.extend(lo, hi);
        r.cbox.extend_point(lo + hi);
    }
}

// Splits r at its object median along the widest centroid axis.
void median_split(Shared& s, const Range& r, Range& left, Range& right) {
    uint32_t mid = r.begin + (r.end - r.begin) / 2;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (r.cbox.extent(a) > r.cbox.extent(axis)) axis = a;
    if (r.cbox.extent(axis) > 0) {
        std::nth_element(s.refs.begin() + r.begin, s.refs.begin() + mid, s.refs.begin() + r.end,
                         [axis](const Ref& x, const Ref& y) {
                             float cx = x.c2(axis), cy = y.c2(axis);
                             return cx < cy || (cx == cy && x.id() < y.id());
                         });
    }
    left.begin = r.begin, left.end = mid;
    right.begin = mid, right.end = r.end;
    bounds_of(s, left);
    bounds_of(s, right);
}

void build_node(Shared& s, Task& task, uint32_t node, const Range& r, int depth);

void splice(Task& task, uint32_t node, Task& sub) {
    uint32_t base = static_cast<uint32_t>(task.nodes.size());
    auto relocate = [base](BvhNode n) {
        if (n.count == 0) n.first = base + n.first - 1;
        return n;
    };
    task.nodes[node] = relocate(sub.nodes[0]);
    for (size_t i = 1; i < sub.nodes.size(); ++i) task.nodes.push_back(relocate(sub.nodes[i]));
    task.depth = std::max(task.depth, sub.depth);
}

void make_leaf(Task& task, uint32_t node, const Range& r) {
    task.nodes[node].first = r.begin;
    task.nodes[node].count = r.end - r.begin;
}

void build_node(Shared& s, Task& task, uint32_t node, const Range& r, int depth) {
    set_bounds(task.nodes[node], r.box);
    task.depth = std::max(task.depth, depth);
    const uint32_t n = r.end - r.begin;
    const uint32_t max_leaf = static_cast<uint32_t>(std::clamp(s.opt.max_leaf, 1, kMaxLeafCount));
    if (n == 1) return make_leaf(task, node, r);

    Range left, right;
    bool split_done = false;
    if (depth < kSahDepthCap) {
        Binning binning{};
        Split sp = find_split(s, r, binning, depth);
        if (sp.axis >= 0) {
            float area = r.box.half_area();
            float split_cost = s.opt.traversal_cost +
                               s.opt.intersect_cost * (area > 0 ? sp.cost / area : static_cast<float>(n));
            float leaf_cost = s.opt.intersect_cost * static_cast<float>(n);
            if (n <= max_leaf && leaf_cost <= split_cost) return make_leaf(task, node, r);
            // Partition by the same bin function, collecting each side's centroid bounds.
            const int axis = sp.axis, bin = sp.bin;
            auto first = s.refs.begin() + r.begin, last = s.refs.begin() + r.end;
            Box cl, cr;
            auto mid = std::partition(first, last, [&](const Ref& ref) {
                F4 c = ref.lo4() + ref.hi4();
                int k[3];
                binning.indices(c, k);
                if (k[axis] <= bin) {
                    cl.extend_point(c);
                    return true;
                }
                cr.extend_point(c);
                return false;
            });
            uint32_t m = static_cast<uint32_t>(mid - s.refs.begin());
            left = Range{r.begin, m, sp.left, cl};
            right = Range{m, r.end, sp.right, cr};
            split_done = true;
        } else if (n <= max_leaf) {
            return make_leaf(task, node, r);
        }
    } else if (n <= max_leaf) {
        return make_leaf(task, node, r);
    }
    if (!split_done) median_split(s, r, left, right);

    uint32_t pair = static_cast<uint32_t>(task.nodes.size());
    task.nodes.push_back(BvhNode{});
    task.nodes.push_back(BvhNode{});
    task.nodes[node].first = pair;
    task.nodes[node].count = 0;

    if (right.end - right.begin >= kSubtreeMin && claim_thread(s)) {
        // The right subtree is built on another thread into its own array (root at index 0)
        // and spliced in afterwards. Without a thread it goes straight into ours: the binary
        // layout then differs, but not the tree, so to_bvh_wide (depth first) emits the same nodes.
        Task sub;
        sub.nodes.reserve(2 * size_t{right.end - right.begin});  // < 2n nodes
        sub.nodes.push_back(BvhNode{});
        std::thread worker([&s, &sub, right, depth] {
            build_node(s, sub, 0, right, depth + 1);
            s.idle.fetch_add(1);
        });
        build_node(s, task, pair, left, depth + 1);
        worker.join();
        if (depth == 0) s.built();
        splice(task, pair + 1, sub);
    } else {
        build_node(s, task, pair, left, depth + 1);
        build_node(s, task, pair + 1, right, depth + 1);
    }
}

}  // namespace

Bvh build_bvh(const std::vector<Bounds3f>& bounds, const BvhOptions& options) {
    return build_bvh(
        bounds.size(),
        [&bounds](uint32_t begin, uint32_t end, Bounds3f* out) {
            std::copy(bounds.begin() + begin, bounds.begin() + end, out);
        },
        options);
}

Bvh build_bvh(size_t count, const BvhBoundsFn& bounds, const BvhOptions& options) {
    Bvh bvh;
    const uint32_t n = static_cast<uint32_t>(count);
    if (n == 0) return bvh;
    const int threads = thread_count(options.threads);
    // The references, in fixed chunks on every thread, with each chunk's bounds and centroid
    // bounds; those are merged in chunk order.
    HugePageVector<Ref> refs(n);
    const size_t chunks = (size_t{n} + kBvhChunk - 1) / kBvhChunk;
    std::vector<Range> chunk_bounds(chunks);
    std::vector<std::vector<Bounds3f>> scratch(static_cast<size_t>(threads));
    parallel_chunks(n, kBvhChunk, threads, [&](size_t c, size_t begin, size_t end, int worker) {
        std::vector<Bounds3f>& b = scratch[static_cast<size_t>(worker)];
        b.resize(end - begin);
        bounds(static_cast<uint32_t>(begin), static_cast<uint32_t>(end), b.data());
        Range& cb = chunk_bounds[c];
        for (size_t i = begin; i < end; ++i) {
            refs[i] = Ref(b[i - begin], static_cast<uint32_t>(i));
            const F4 lo = refs[i].lo4(), hi = refs[i].hi4();
            cb.box.extend(lo, hi);
            cb.cbox.extend_point(lo + hi);
        }
    });
    Range root;
    root.end = n;
    for (const Range& cb : chunk_bounds) {
        root.box.extend(cb.box);
        root.cbox.extend(cb.cbox);
    }

    // The leaf order, once every subtree is built; the references are then freed, before the
    // splice of the root's other subtree copies it (on a 10^7-triangle mesh the build's peak
    // memory was that copy with the references still held).
    const auto take_order = [&] {
        bvh.order.resize(n);
        parallel_chunks(n, kBvhChunk, threads, [&](size_t, size_t begin, size_t end, int) {
            for (size_t i = begin; i < end; ++i) bvh.order[i] = refs[i].id();
        });
        HugePageVector<Ref>().swap(refs);
    };
    Shared s{refs, options, {threads - 1}, take_order};

    // Enough for any tree (fewer than 2n nodes), so that splicing never reallocates; untouched
    // capacity costs no memory. The nodes are a temporary for to_bvh_wide, hence no shrink_to_fit.
    Task task;
    task.nodes.reserve(2 * size_t{n});
    task.nodes.push_back(BvhNode{});
    build_node(s, task, 0, root, 0);

    if (bvh.order.empty()) take_order();  // no subtree was built on another thread
    bvh.nodes = std::move(task.nodes);
    bvh.depth = task.depth;
    return bvh;
}

}  // namespace wsd::render
