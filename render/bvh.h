// A bounding volume hierarchy over boxes and indices only (no shapes): binned SAH build into flat
// 32-byte nodes whose two children sit side by side, with a primitive permutation. Large inputs
// are split into subtrees built on std::threads; the result does not depend on the thread count.
// For traversal the binary tree is collapsed into a wide one (BvhWideNode: about the same bytes
// per child, a third of the levels), so that SIMD slab tests cover its children together.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "render/aabb.h"
#include "render/huge_pages.h"

namespace wsd::render {

// The most primitives a leaf may hold, whatever BvhOptions::max_leaf asks (the wide tree packs a
// leaf's count into 8 bits).
inline constexpr int kMaxLeafCount = 255;

struct BvhOptions {
    int max_leaf = 4;  // primitives per leaf at most (taken as 1 to kMaxLeafCount)
    int bins = 16;     // SAH bins per axis (at least kTopBins for the first levels: render/bvh.cpp)
    float traversal_cost = 1.0f;
    float intersect_cost = 1.0f;
    int threads = 1;  // 0 = all cores
};

struct Bvh {
    HugePageVector<BvhNode> nodes;   // nodes[0] is the root (empty when there are no primitives)
    HugePageVector<uint32_t> order;  // leaves refer to order[first, first + count)
    int depth = 0;                   // longest root-to-leaf path, in edges
};

// Every bound must be finite and non-empty. Depth stays below kMaxBvhDepth: past a depth cap
// the builder splits at the object median instead of by SAH.
inline constexpr int kMaxBvhDepth = 64;
Bvh build_bvh(const std::vector<Bounds3f>& bounds, const BvhOptions& options);
// The same over `count` primitives whose bounds the caller writes, chunk by chunk, so that
// callers that can compute bounds (a mesh's triangles from their vertices) need not store them:
// bounds(begin, end, out) writes those of primitives [begin, end) to out[0, end - begin). It is
// called once for each chunk [k * kBvhChunk, min(count, (k + 1) * kBvhChunk)), in any order and
// from several threads at once.
inline constexpr uint32_t kBvhChunk = 1u << 14;
using BvhBoundsFn = std::function<void(uint32_t begin, uint32_t end, Bounds3f* out)>;
Bvh build_bvh(size_t count, const BvhBoundsFn& bounds, const BvhOptions& options);

// Collapses built nodes into the wide traversal tree (see BvhWideNode in aabb.h), in depth-first
// order; node 0 holds the root's children (or the root itself when it is a leaf). Which subtrees
// become a wide node's lanes, and which small subtrees become one leaf, is chosen for the least
// cost by the surface area heuristic over the whole tree (render/bvh_wide.cpp): nodes fill,
// where opening the largest child first left 45 % of a mesh's nodes with two leaves. A subtree
// of a few primitives over order[first, first + count) may become one leaf when
// mergeable(first, count) says so (cheap primitives: triangles); without the function, leaves
// stay as built. Subtrees are collapsed on `threads` threads (0 = all cores); the result does
// not depend on their number.
using WideLeafFn = std::function<bool(uint32_t first, uint32_t count)>;
// The most primitives such a merged leaf holds: one group of four triangles, which the walk built
// for AVX tests at once (render/bvh_wide.cpp prices a leaf by its groups). On a million-triangle
// mesh this left camera rays 3 % fewer boxes and 1.5 times the triangle tests, at the same rate;
// shadow and diffuse rays went faster, and the tree took a fifth less memory.
inline constexpr uint32_t kWideMergeLeaf = 4;
HugePageVector<BvhWideNode> to_bvh_wide(const HugePageVector<BvhNode>& nodes,
                                        const WideLeafFn& mergeable = {}, int threads = 1);

}  // namespace wsd::render
