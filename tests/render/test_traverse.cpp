// The shared BVH walk (render/traverse.h) on trees of random boxes: every order visits exactly
// the leaves a brute-force slab test over all leaf boxes selects, each once; a leaf that ends the
// walk ends it; a nearest-first walk that shrinks its limit finds the nearest leaf while skipping
// others. And Scene::may_cross_transmissive's segment test: conservative, and it culls.
#include <algorithm>
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "render/bvh.h"
#include "render/traverse.h"
#include "scene_builders.h"

using namespace wsd::render;

namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

struct Boxes {
    std::vector<Bounds3f> bounds;
    HugePageVector<BvhWideNode> nodes;
};

// n random boxes of assorted sizes in [−10, 10]³, and their 4-wide BVH.
Boxes random_tree(std::mt19937_64& gen, int n, int max_leaf, bool merge = false) {
    std::uniform_real_distribution<float> pos(-10, 10), size(0.01f, 3);
    Boxes b;
    for (int i = 0; i < n; ++i) {
        Bounds3f box;
        const Vec3f c{pos(gen), pos(gen), pos(gen)}, h{size(gen), size(gen), size(gen)};
        box.extend(c - h);
        box.extend(c + h);
        b.bounds.push_back(box);
    }
    BvhOptions options;
    options.max_leaf = max_leaf;
    b.nodes = to_bvh_wide(build_bvh(b.bounds, options).nodes,
                          merge ? WideLeafFn([](uint32_t, uint32_t) { return true; }) : WideLeafFn());
    return b;
}

RayBoxTest random_ray(std::mt19937_64& gen) {
    std::uniform_real_distribution<double> u(-1, 1);
    const Vec3 o{15 * u(gen), 15 * u(gen), 15 * u(gen)};
    const Vec3 target{8 * u(gen), 8 * u(gen), 8 * u(gen)};
    RayBoxTest r;
    r.init(o, target - o);
    return r;
}

using Leaf = std::pair<uint32_t, uint32_t>;  // first, count

// The leaves (by their order range) whose own box the ray enters within t_limit, found by testing
// every leaf lane of every node. A box's slab test never rejects a ray its descendant's accepts
// (rounded products are monotone), so a walk without pruning must visit exactly these.
std::vector<Leaf> brute_force_leaves(const HugePageVector<BvhWideNode>& nodes, const RayBoxTest& r,
                                     float t_limit) {
    std::vector<Leaf> out;
    for (const BvhWideNode& node : nodes) {
        alignas(16) float tn[kBvhWidth];
        const int mask = r.hit(node, t_limit, tn);
        for (int i = 0; i < kBvhWidth; ++i)
            if ((mask >> i & 1) && node.count(i) > 0) out.push_back({node.first(i), node.count(i)});
    }
    std::sort(out.begin(), out.end());
    return out;
}

// A query that records every leaf it reaches; with kStopAt > 0 it ends the walk at that leaf.
template <WalkOrder kWalkOrder, int kStopAt = 0>
struct Recorder {
    static constexpr WalkOrder kOrder = kWalkOrder;
    using Child = BvhChild;
    const RayBoxTest& r;
    float limit;
    std::vector<Leaf> leaves;

    int enter(const BvhWideNode& node, uint32_t, float* tn) const { return r.hit(node, limit, tn); }
    bool leaf(const Child& c) {
        leaves.push_back({c.first(), c.count()});
        return static_cast<int>(leaves.size()) == kStopAt;
    }
    bool open(float) const { return true; }
};

template <WalkOrder kWalkOrder, int kStopAt = 0>
std::pair<bool, std::vector<Leaf>> record(const HugePageVector<BvhWideNode>& nodes, const RayBoxTest& r,
                                          float limit, uint64_t& visits) {
    Recorder<kWalkOrder, kStopAt> q{r, limit, {}};
    const bool stopped = walk_bvh(nodes.data(), q, visits);
    return {stopped, q.leaves};
}

// The closest-hit pattern on boxes: the "hit" at a leaf is its entry distance, which becomes the
// limit; waiting children entered beyond it are skipped.
struct NearestLeaf {
    static constexpr WalkOrder kOrder = WalkOrder::NearestFirst;
    using Child = BvhChild;
    const RayBoxTest& r;
    float limit = kInfF;
    int leaves = 0;

    int enter(const BvhWideNode& node, uint32_t, float* tn) const { return r.hit(node, limit, tn); }
    bool leaf(const Child& c) {
        ++leaves;
        limit = std::min(limit, c.t);
        return false;
    }
    bool open(float t) const { return t <= limit * RayBoxTest::kWiden; }
};

}  // namespace

TEST_CASE("every walk order visits exactly the leaves a brute-force slab test selects, each once") {
    std::mt19937_64 gen(20261125);
    for (int tree = 0; tree < 30; ++tree) {
        const Boxes b = random_tree(gen, 1 + 37 * tree, 1 + tree % 4, tree % 2 == 1);
        REQUIRE(!b.nodes.empty());
        for (int k = 0; k < 300; ++k) {
            const RayBoxTest r = random_ray(gen);
            const float limit = k % 3 == 0 ? kInfF : 30.0f * float(k % 7) / 7.0f;
            const std::vector<Leaf> expect = brute_force_leaves(b.nodes, r, limit);
            uint64_t visits = 0;
            auto [stop_d, depth] = record<WalkOrder::DepthFirst>(b.nodes, r, limit, visits);
            auto [stop_l, leaves_first] = record<WalkOrder::LeavesFirst>(b.nodes, r, limit, visits);
            auto [stop_n, nearest] = record<WalkOrder::NearestFirst>(b.nodes, r, limit, visits);
            CHECK_FALSE(stop_d);
            CHECK_FALSE(stop_l);
            CHECK_FALSE(stop_n);
            for (auto* got : {&depth, &leaves_first, &nearest}) {
                std::sort(got->begin(), got->end());
                REQUIRE(*got == expect);  // sorted equal: each leaf exactly once
            }
        }
    }
}

namespace {

// Checks the lanes of a wide tree over `primitives` primitives: empty lanes hold no child and an
// empty box, every node but the root is one lane's child, and the leaves cover each primitive
// once. Returns the largest leaf.
uint32_t check_lanes(const HugePageVector<BvhWideNode>& nodes, size_t primitives) {
    std::vector<int> covered(primitives, 0);
    uint32_t largest = 0;
    size_t inner_lanes = 0;
    for (const BvhWideNode& node : nodes)
        for (int i = 0; i < kBvhWidth; ++i) {
            if ((node.child_mask() >> i & 1) == 0) {
                CHECK(node.child[i] == 0);
                CHECK_FALSE(node.lo[0][i] <= node.hi[0][i]);
                continue;
            }
            if (node.count(i) == 0) {
                ++inner_lanes;
                REQUIRE(node.first(i) > 0);
                REQUIRE(node.first(i) < nodes.size());
                continue;
            }
            largest = std::max(largest, node.count(i));
            for (uint32_t k = node.first(i); k < node.first(i) + node.count(i); ++k) ++covered.at(k);
        }
    CHECK(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }));
    CHECK(inner_lanes == nodes.size() - 1);
    return largest;
}

}  // namespace

TEST_CASE("the wide tree's leaves cover every primitive once; small subtrees merge only when allowed") {
    std::mt19937_64 gen(5);
    for (int n : {1, 2, 3, 9, 100, 2000}) {
        for (bool merge : {false, true}) {
            INFO(n << " boxes, merge " << merge);
            const Boxes b = random_tree(gen, n, 1, merge);
            const uint32_t largest = check_lanes(b.nodes, static_cast<size_t>(n));
            // Built with one primitive a leaf: only a merge makes larger ones, and never past
            // kWideMergeLeaf (the collapse merges where that costs less: among many small boxes).
            if (merge && n >= 100)
                CHECK(largest > 1);
            else if (!merge)
                CHECK(largest == 1);
            CHECK(largest <= kWideMergeLeaf);
        }
    }
}

TEST_CASE("the collapse fills wide nodes: few hold only two children") {
    // A grid of small boxes, as a mesh's triangles are: built with leaves of one or two, the
    // binary tree has many subtrees of four or five, which a collapse that opens children
    // greedily turns into nodes of two leaves (45 % of a mesh's nodes were, at 54 % lanes used).
    std::vector<Bounds3f> boxes;
    for (int x = 0; x < 60; ++x)
        for (int z = 0; z < 60; ++z) {
            const Vec3f c{static_cast<float>(x), 0.01f * static_cast<float>((x * 7 + z * 13) % 11),
                          static_cast<float>(z)};
            boxes.push_back(Bounds3f::around(c, c + Vec3f(0.9f, 0.05f, 0.9f)));
        }
    BvhOptions options;
    options.max_leaf = 2;
    const auto nodes = to_bvh_wide(build_bvh(boxes, options).nodes, [](uint32_t, uint32_t) { return true; });
    size_t lanes = 0, two = 0;
    for (const BvhWideNode& node : nodes) {
        const int used = std::popcount(static_cast<unsigned>(node.child_mask()));
        lanes += static_cast<size_t>(used);
        two += used == 2 ? 1 : 0;
    }
    INFO(nodes.size() << " nodes, " << lanes << " lanes used, " << two << " of two");
    CHECK(static_cast<double>(lanes) >= 0.7 * kBvhWidth * static_cast<double>(nodes.size()));
    CHECK(static_cast<double>(two) <= 0.05 * static_cast<double>(nodes.size()));
}

TEST_CASE("the collapse copes with boxes as large as floats go") {
    // Extents past the float range, flat boxes among them: the collapse's areas must not turn
    // into NaN and leave a leaf to be split as if it were inner.
    constexpr float kBig = std::numeric_limits<float>::max();
    std::vector<Bounds3f> boxes;
    for (int i = 0; i < 40; ++i) {
        const float s = static_cast<float>(i % 5);
        Bounds3f b;
        b.extend(Vec3f{-kBig, s, i % 2 == 0 ? 0.0f : -kBig});
        b.extend(Vec3f{kBig, s + (i % 3 == 0 ? 0.0f : 1.0f), i % 2 == 0 ? 0.0f : kBig});
        boxes.push_back(b);
    }
    BvhOptions options;
    options.max_leaf = 1;
    const auto nodes = to_bvh_wide(build_bvh(boxes, options).nodes, [](uint32_t, uint32_t) { return true; });
    check_lanes(nodes, boxes.size());
}

TEST_CASE("a leaf that ends the walk ends it, in every order") {
    std::mt19937_64 gen(7);
    const Boxes b = random_tree(gen, 500, 2);
    int met = 0;
    for (int k = 0; k < 2000; ++k) {
        const RayBoxTest r = random_ray(gen);
        const size_t all = brute_force_leaves(b.nodes, r, kInfF).size();
        uint64_t visits = 0;
        auto [stop_d, depth] = record<WalkOrder::DepthFirst, 1>(b.nodes, r, kInfF, visits);
        auto [stop_l, leaves_first] = record<WalkOrder::LeavesFirst, 1>(b.nodes, r, kInfF, visits);
        auto [stop_n, nearest] = record<WalkOrder::NearestFirst, 2>(b.nodes, r, kInfF, visits);
        REQUIRE(stop_d == (all >= 1));
        REQUIRE(stop_l == (all >= 1));
        REQUIRE(stop_n == (all >= 2));
        REQUIRE(depth.size() == std::min<size_t>(all, 1));
        REQUIRE(leaves_first.size() == std::min<size_t>(all, 1));
        REQUIRE(nearest.size() == std::min<size_t>(all, 2));
        met += all >= 2 ? 1 : 0;
    }
    CHECK(met > 500);  // the early end was exercised, not just rays that meet nothing
}

TEST_CASE("a nearest-first walk that shrinks its limit finds the nearest leaf and skips others") {
    std::mt19937_64 gen(11);
    long visited = 0, entered = 0;
    for (int tree = 0; tree < 10; ++tree) {
        const Boxes b = random_tree(gen, 1000, 1);
        for (int k = 0; k < 300; ++k) {
            const RayBoxTest r = random_ray(gen);
            float nearest = kInfF;
            for (const BvhWideNode& node : b.nodes) {
                alignas(16) float tn[kBvhWidth];
                const int mask = r.hit(node, kInfF, tn);
                for (int i = 0; i < kBvhWidth; ++i)
                    if ((mask >> i & 1) && node.count(i) > 0) {
                        nearest = std::min(nearest, tn[i]);
                        ++entered;
                    }
            }
            NearestLeaf q{r};
            uint64_t visits = 0;
            walk_bvh(b.nodes.data(), q, visits);
            REQUIRE(q.limit == nearest);
            visited += q.leaves;
        }
    }
    CHECK(visited * 2 < entered);  // pruning: well under the leaves a full walk visits
}

TEST_CASE("may_cross_transmissive: conservative for segments meeting a glass shape's box, false far away") {
    using wsd::test::basic_scene;
    SceneSpec spec = basic_scene(8, 8);
    const uint32_t glass = wsd::test::add_material(spec, wsd::test::glass());
    const uint32_t matte = wsd::test::add_material(spec, wsd::test::matte(Color(1)));
    spec.shapes.push_back(wsd::test::sphere({0, 0, 0}, 1, glass));
    spec.shapes.push_back(wsd::test::box({2, -1, -1}, {3, 1, 1}, glass));
    spec.shapes.push_back(wsd::test::sphere({0, 5, 0}, 1, matte));
    std::vector<SpecError> errors;
    const auto scene = build_scene(spec, errors);
    REQUIRE(scene);
    // Through, into, out of and inside the glass; along a box face (a zero direction component);
    // a point inside; directions far below and above unit length.
    CHECK(scene->may_cross_transmissive({-5, 0, 0}, {5, 0, 0}));
    CHECK(scene->may_cross_transmissive({-5, 0.2, 0.1}, {0, 0, 0}));
    CHECK(scene->may_cross_transmissive({0.1, 0, 0}, {0, 0, 9}));
    CHECK(scene->may_cross_transmissive({2, -5, 1}, {2, 5, 1}));
    CHECK(scene->may_cross_transmissive({2.5, 0, 0}, {2.5, 0, 0}));
    CHECK(scene->may_cross_transmissive({2.5, 0, 0}, {2.5, 0, 1e-300}));
    CHECK(scene->may_cross_transmissive({2.5, 0, -1e300}, {2.5, 0, 1e300}));
    // Segments that end before the glass, pass it by, or only meet the opaque sphere.
    CHECK_FALSE(scene->may_cross_transmissive({-5, 0, 0}, {-2, 0, 0}));
    CHECK_FALSE(scene->may_cross_transmissive({-5, 3, 0}, {5, 3, 0}));
    CHECK_FALSE(scene->may_cross_transmissive({0, 7, 0}, {0, 5, 0}));
    CHECK_FALSE(scene->may_cross_transmissive({2.5, 2, 0}, {2.5, 2, 1e-300}));
    // Random segments: true whenever one meets the unit sphere (distance to its centre ≤ 1).
    std::mt19937_64 gen(3);
    std::uniform_real_distribution<double> u(-4, 4);
    int met = 0, culled = 0;
    for (int k = 0; k < 20000; ++k) {
        const Vec3 a{u(gen), u(gen), u(gen)}, b{u(gen), u(gen), u(gen)};
        const Vec3 d = b - a;
        const double t = std::clamp(-glm::dot(a, d) / glm::dot(d, d), 0.0, 1.0);
        const bool meets = glm::length(a + t * d) <= 1;
        const bool may = scene->may_cross_transmissive(a, b);
        if (meets) {
            REQUIRE(may);
            ++met;
        }
        culled += may ? 0 : 1;
    }
    CHECK(met > 1000);
    CHECK(culled > 1000);
}
