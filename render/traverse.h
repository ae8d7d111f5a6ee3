// The one walk of the wide BVH (BvhWideNode) that every query uses: the stack, the order children
// are visited in and the dispatch to leaves are written here once. What a query does at an inner
// node (which children to enter: one ray's slab test, a packet's interval test, a shaft's plane
// test) and at a leaf (test primitives, end the walk) is a policy passed in and inlined at
// compile time, after madmann91/bvh's intersect<IsAnyHit>(ray, top, stack, leaf_fn, inner_fn).
// Internal to render/. The walk depends on nodes only, so that a tree of trees (instances) can
// walk its top level with it and call it again from a leaf.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

#include "render/aabb.h"
#include "render/bvh.h"
#include "render/cpu_features.h"
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace wsd::render {

// The order in which the children that a node's test enters are visited.
enum class WalkOrder {
    // Nearest entry distance first (of a node's entered children, and the last child left
    // waiting); a waiting child is skipped when, by the time it is popped, the query no longer
    // finds it open (closest hits, whose limit shrinks with each hit).
    NearestFirst,
    // Depth first, the highest lane first, no distances (any hit: the first one ends the walk).
    DepthFirst,
    // At each node its entered leaves first, in lane order; then its inner children depth first
    // as above (gathering: the primitives near the top are seen before descending).
    LeavesFirst,
};

// A child that the walk reached, as its node holds it (BvhWideNode::child: 8 bytes a stack entry,
// pushed and popped whole): count() == 0 for an inner child (its node is nodes[first()]),
// otherwise a leaf over order[first(), first() + count()); t is the entry distance the node test
// gave.
struct BvhChild {
    uint32_t word;
    float t;
    uint32_t first() const { return word & BvhWideNode::kFirstMask; }
    uint32_t count() const { return word >> BvhWideNode::kFirstBits; }
    static BvhChild at(const BvhWideNode& node, uint32_t, int i, float t) { return {node.child[i], t}; }
};

// The same, and where its box is (lane box & kLaneMask of node box >> kLaneBits), for queries
// that test a leaf's box again ray by ray.
// Bits of BvhChildAt::box that name the lane.
inline constexpr int kLaneBits = std::bit_width(static_cast<unsigned>(kBvhWidth - 1));
inline constexpr uint32_t kLaneMask = (1u << kLaneBits) - 1;

struct BvhChildAt {
    uint32_t word;
    float t;
    uint32_t box;
    uint32_t first() const { return word & BvhWideNode::kFirstMask; }
    uint32_t count() const { return word >> BvhWideNode::kFirstBits; }
    static BvhChildAt at(const BvhWideNode& node, uint32_t index, int i, float t) {
        return {node.child[i], t, index << kLaneBits | static_cast<uint32_t>(i)};
    }
};

// Each level of the tree leaves at most kBvhWidth - 1 children waiting.
inline constexpr int kWalkStack = (kBvhWidth - 1) * kMaxBvhDepth + 1;

namespace detail {

// The number of bits set in each lane mask (std::popcount is a library call on baseline x86-64).
inline constexpr auto kChildCount = [] {
    std::array<uint8_t, 1 << kBvhWidth> n{};
    for (size_t m = 0; m < n.size(); ++m) n[m] = static_cast<uint8_t>(std::popcount(m));
    return n;
}();

// Counts the children (lanes that hold one) of the nodes a walk visits. Per visit it adds each
// lane's "unused" flag (-1 or 0) to a running vector, and the total is visits × width less the
// unused lanes: fewer instructions a node than a table lookup of child_mask().
struct ChildCounter {
#if defined(__SSE2__)
    __m128i unused = _mm_setzero_si128();  // per lane group position: minus the unused lanes seen
    uint64_t visits = 0;
    [[gnu::always_inline]] void add(const BvhWideNode& node) {
        const __m128i zero = _mm_setzero_si128();
        for (int g = 0; g < kBvhGroups; ++g) {
            const __m128i c = _mm_load_si128(reinterpret_cast<const __m128i*>(node.child + 4 * g));
            unused = _mm_add_epi32(unused, _mm_cmpeq_epi32(c, zero));
        }
        ++visits;
    }
    uint64_t total() const {
        alignas(16) int32_t u[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(u), unused);
        const int64_t missing = int64_t{u[0]} + u[1] + u[2] + u[3];  // not above 0
        return visits * kBvhWidth + static_cast<uint64_t>(missing);
    }
#else
    uint64_t n = 0;
    void add(const BvhWideNode& node) {
        n += kChildCount[node.child_mask()];
    }
    uint64_t total() const {
        return n;
    }
#endif
};

// A BvhChild as one integer whose order is (t, word): t's bits above the word. Entry distances
// are never negative or NaN (hit() starts them at 0), so their bits order as the floats do.
[[gnu::always_inline]] inline uint64_t child_key(uint32_t word, float t) {
    return uint64_t{std::bit_cast<uint32_t>(t)} << 32 | word;
}
[[gnu::always_inline]] inline BvhChild child_of_key(uint64_t key) {
    return {static_cast<uint32_t>(key), std::bit_cast<float>(static_cast<uint32_t>(key >> 32))};
}
// Stores the child of `key` at *c: the key's bytes are the BvhChild's (word, then t) on a
// little-endian machine, so one 8-byte store.
template <class Child>
[[gnu::always_inline]] inline void put_key(Child* c, uint64_t key) {
    if constexpr (std::endian::native == std::endian::little) {
        static_assert(sizeof(BvhChild) == 8 && offsetof(BvhChild, t) == 4);
        std::memcpy(static_cast<void*>(c), &key, 8);
    } else {
        *c = child_of_key(key);
    }
}
// Orders a and b (a the lesser), without a branch.
[[gnu::always_inline]] inline void key_order(uint64_t& a, uint64_t& b) {
    const uint64_t lo = a < b ? a : b, hi = a < b ? b : a;
    a = lo;
    b = hi;
}

// The entered children of `node` (bits of mask) that wait on the stack, in the order they are
// to be visited (the next one deepest), and returns the one to visit now.
template <WalkOrder kOrder, class Child>
[[gnu::always_inline]] inline Child push_children(const BvhWideNode& node, uint32_t index, int mask,
                                                  const float* tn, Child* stack, int& sp) {
    if constexpr (kOrder == WalkOrder::NearestFirst) {
        // Nearest next; the others wait, farthest deepest, with their entry distances. One or
        // two children (the common cases) need no sorting loop; ties keep lane order.
        const int i = std::countr_zero(static_cast<unsigned>(mask));
        const int rest = mask & (mask - 1);
        if (rest == 0) return Child::at(node, index, i, tn[i]);
        if ((rest & (rest - 1)) == 0) {
            const int j = std::countr_zero(static_cast<unsigned>(rest));
            const bool swap = tn[j] < tn[i];
            const int near = swap ? j : i, far = swap ? i : j;
            stack[sp++] = Child::at(node, index, far, tn[far]);
            return Child::at(node, index, near, tn[near]);
        }
        if constexpr (std::is_same_v<Child, BvhChild>) {
            // Three or four (nearly every other case): keyed by (distance, word) and ordered by
            // a sorting network. Ties may then go another way than by lane; which of two
            // children at the same distance goes first changes no hit (Best resolves ties).
            const int k = std::countr_zero(static_cast<unsigned>(rest));
            const int rest2 = rest & (rest - 1);
            const int l = std::countr_zero(static_cast<unsigned>(rest2));
            const int rest3 = rest2 & (rest2 - 1);
            uint64_t a = child_key(node.child[i], tn[i]), b = child_key(node.child[k], tn[k]);
            uint64_t c = child_key(node.child[l], tn[l]);
            if (rest3 == 0) {
                key_order(a, b);
                key_order(b, c);
                key_order(a, b);
                put_key(stack + sp, c);
                put_key(stack + sp + 1, b);
                sp += 2;
                return child_of_key(a);
            }
            if ((rest3 & (rest3 - 1)) == 0) {
                const int q = std::countr_zero(static_cast<unsigned>(rest3));
                uint64_t d = child_key(node.child[q], tn[q]);
                key_order(a, b);
                key_order(c, d);
                key_order(a, c);
                key_order(b, d);
                key_order(b, c);
                put_key(stack + sp, d);
                put_key(stack + sp + 1, c);
                put_key(stack + sp + 2, b);
                sp += 3;
                return child_of_key(a);
            }
        }
        // More: sorted by (distance, lane) as one integer key each. Entry distances are never
        // negative or NaN (hit() starts them at 0), so their bits order as the floats do.
        uint64_t key[kBvhWidth];
        int m = 0;
        for (; mask != 0; mask &= mask - 1) {
            const int k = std::countr_zero(static_cast<unsigned>(mask));
            const uint64_t x = uint64_t{std::bit_cast<uint32_t>(tn[k])} << 8 | static_cast<uint64_t>(k);
            int j = m++;
            while (j > 0 && key[j - 1] > x) {
                key[j] = key[j - 1];
                --j;
            }
            key[j] = x;
        }
        for (int k = m - 1; k > 0; --k) {
            const int lane = static_cast<int>(key[k] & 0xff);
            stack[sp++] = Child::at(node, index, lane, tn[lane]);
        }
        const int lane = static_cast<int>(key[0] & 0xff);
        return Child::at(node, index, lane, tn[lane]);
    } else {
        const int top = 31 - std::countl_zero(static_cast<unsigned>(mask));
        for (int rest = mask & ~(1 << top); rest != 0; rest &= rest - 1) {
            const int k = std::countr_zero(static_cast<unsigned>(rest));
            stack[sp++] = Child::at(node, index, k, tn[k]);
        }
        return Child::at(node, index, top, tn[top]);
    }
}

#if defined(WSD_AVX_DISPATCH)
// A leaf in the walk built for AVX: the query's leaf_avx where it has one, else its leaf.
template <class Q, class Child>
[[gnu::target("avx"), gnu::always_inline]] inline bool leaf_avx(Q& q, const Child& c) {
    if constexpr (requires { q.leaf_avx(c); })
        return q.leaf_avx(c);
    else
        return q.leaf(c);
}
#endif

}  // namespace detail

// Walks the non-empty tree `nodes` (node 0 holds the root's children) for one query and returns
// true when the query ended it early. `boxes` counts the child boxes tested: the children (lanes
// that hold one) of every node visited. The query Q provides:
//   static constexpr WalkOrder kOrder;
//   using Child = BvhChild or BvhChildAt;
//   int enter(const BvhWideNode& node, uint32_t index, float* t_entry)
//       inner_fn: bit i set to visit child i of nodes[index]; t_entry[i] its entry distance
//       (any value when the order ignores distances);
//   bool leaf(const Child& c)     leaf_fn: true ends the walk;
//   bool open(float t) const      NearestFirst only: a waiting child entered at t may still
//                                 matter;
//   void prefetch_leaf(uint32_t first) const   optional: fetch the data of a leaf that will be
//                                 visited (a hint; it must not change what the query finds).
//
// walk_bvh_avx is the same walk built for AVX (x86-64 only; call it where avx_walk() is true):
// the query provides enter_avx, with enter's meaning, [[gnu::target("avx"), gnu::always_inline]]
// (RayBoxTest::hit_avx), and may provide leaf_avx, with leaf's meaning, built for AVX (a mesh's
// triangles four at a time), which that walk then calls instead of leaf. Both walks are written
// once, in render/walk_bvh.inc.
#define WSD_WALK_NAME walk_bvh
#define WSD_WALK_ATTRIBUTES gnu::always_inline
#define WSD_WALK_ENTER enter
#define WSD_WALK_LEAF(q, child) q.leaf(child)
#include "render/walk_bvh.inc"
#if defined(WSD_AVX_DISPATCH)
#define WSD_WALK_NAME walk_bvh_avx
#define WSD_WALK_ATTRIBUTES gnu::always_inline, gnu::target("avx")
#define WSD_WALK_ENTER enter_avx
#define WSD_WALK_LEAF(q, child) detail::leaf_avx(q, child)
#include "render/walk_bvh.inc"
#endif

// The node test of a query that walks for one ray: its RayBoxTest within `limit` (a query
// derives from it and keeps `limit` up to date), as enter and enter_avx.
struct OneRayTest {
    const RayBoxTest* box;
    float limit;
    int enter(const BvhWideNode& node, uint32_t, float* tn) const { return box->hit(node, limit, tn); }
#if defined(WSD_AVX_DISPATCH)
    [[gnu::target("avx"), gnu::always_inline]] int enter_avx(const BvhWideNode& node, uint32_t,
                                                             float* tn) const {
        return box->hit_avx(node, limit, tn);
    }
#endif
};

#if defined(WSD_AVX_DISPATCH)
// A function built for AVX, which walk_bvh_avx (always inline) is inlined into.
template <class Q>
[[gnu::target("avx")]] bool walk_bvh_avx_call(const BvhWideNode* nodes, Q& q, uint64_t& boxes) {
    return walk_bvh_avx(nodes, q, boxes);
}
#endif

// walk_bvh, or walk_bvh_avx where avx_walk() says so: for queries with enter_avx.
template <class Q>
[[gnu::always_inline]] inline bool walk_bvh_chosen(const BvhWideNode* nodes, Q& q, uint64_t& boxes) {
#if defined(WSD_AVX_DISPATCH)
    if (avx_walk()) return walk_bvh_avx_call(nodes, q, boxes);
#endif
    return walk_bvh(nodes, q, boxes);
}

}  // namespace wsd::render
