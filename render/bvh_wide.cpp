// The collapse of the binary build tree into the wide traversal tree (BvhWideNode).
#include <algorithm>
#include <array>
#include <limits>

#include "render/bvh.h"
#include "render/limits.h"
#include "render/parallel.h"

namespace wsd::render {

// Order positions and node indices fit a child's 24 bits (fewer nodes than primitives).
static_assert(kMaxPrimitives <= (size_t{1} << BvhWideNode::kFirstBits));
static_assert(kMaxLeafCount <= BvhWideNode::kMaxCount);

namespace {

// A binary node's surface area (half of it), in double and capped at the largest float: never
// NaN (a float extent can overflow to infinity, and infinity times a flat box's zero is NaN),
// so that the costs stay ordered.
float node_area(const BvhNode& n) {
    const double x = double{n.b[3]} - n.b[0], y = double{n.b[4]} - n.b[1], z = double{n.b[5]} - n.b[2];
    return static_cast<float>(std::min(x * y + y * z + z * x, double{std::numeric_limits<float>::max()}));
}

// Cost weights of the collapse (the surface area heuristic on the wide tree): visiting a wide
// node, and testing a leaf's primitives, each per unit of area of the box that leads there. A
// leaf is tested kLeafGroup primitives at a time (the walk built for AVX tests four triangles at
// once: render/prim_test.h), each group at the cost of two single tests (kPrimCost each).
// Weights of a primitive from 0.3 to 3 node visits traced a million-triangle mesh's rays at the
// same rates, within the machine's noise; so did a group priced at 1.25 to 3 single tests.
constexpr float kNodeCost = 1.0f;
constexpr float kPrimCost = 0.8f;
constexpr uint32_t kLeafGroup = 4;
float leaf_cost(float area, uint32_t count) {
    return area * 2 * kPrimCost * static_cast<float>((count + kLeafGroup - 1) / kLeafGroup);
}

// Per binary node: how many primitives its subtree holds (bits 0-30), whether it is a leaf of the
// wide tree (bit 31), and the least cost of its subtree as j lanes of a wide node (cost[j - 1],
// j = 1 .. kBvhWidth): one lane (a leaf or a wide node of its own), or its children's subtrees
// spread over j lanes. The optimal collapse by dynamic programming, after Ylitie, Karras and
// Laine, "Efficient incoherent ray traversal on GPUs through compressed wide BVHs" (2017).
struct Collapse {
    static constexpr uint32_t kLeafBit = 1u << 31;
    std::vector<uint32_t> size_;
    std::vector<std::array<float, kBvhWidth>> cost_;
    // Filled bottom up: the subtrees below depth kSplitDepth on `threads` threads, then the top.
    static constexpr int kSplitDepth = 6;
    Collapse(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable, int threads)
        : size_(nodes.size()), cost_(nodes.size()) {
        std::vector<uint32_t> roots;
        below(nodes, 0, kSplitDepth, roots);
        ParallelOptions options;
        options.threads = threads;
        parallel_for(roots.size(), options, [&](size_t j, int) { fill(nodes, mergeable, roots[j], -1); });
        fill(nodes, mergeable, 0, kSplitDepth);
    }
    // The nodes `depth` levels below n (or leaves above that), into roots.
    static void below(const std::vector<BvhNode>& nodes, uint32_t n, int depth,
                      std::vector<uint32_t>& roots) {
        if (depth == 0 || nodes[n].count > 0) {
            roots.push_back(n);
            return;
        }
        below(nodes, nodes[n].first, depth - 1, roots);
        below(nodes, nodes[n].first + 1, depth - 1, roots);
    }
    // The least cost of binary node n's children over j lanes (2 <= j), and how many of them
    // go to the first child (the fewest of those that tie).
    float spread(const std::vector<BvhNode>& nodes, uint32_t n, int j, int* first_lanes) const {
        const auto& a = cost_[nodes[n].first];
        const auto& b = cost_[nodes[n].first + 1];
        float best = std::numeric_limits<float>::infinity();
        for (int k = 1; k < j; ++k) {
            const float c = a[k - 1] + b[j - k - 1];
            if (c < best) {
                best = c;
                if (first_lanes) *first_lanes = k;
            }
        }
        return best;
    }
    // Fills n's subtree and returns its size; a node `depth` levels below n is taken as filled
    // already (depth < 0: none is).
    uint32_t fill(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable, uint32_t n, int depth) {
        if (depth == 0) return size(n);
        const float area = node_area(nodes[n]);
        auto& c = cost_[n];
        if (nodes[n].count > 0) {
            size_[n] = nodes[n].count | kLeafBit;
            c.fill(leaf_cost(area, nodes[n].count));
            return nodes[n].count;
        }
        const uint32_t size = fill(nodes, mergeable, nodes[n].first, depth - 1) +
                              fill(nodes, mergeable, nodes[n].first + 1, depth - 1);
        const float inner = area * kNodeCost + spread(nodes, n, kBvhWidth, nullptr);
        const float as_leaf = leaf_cost(area, size);
        const bool leaf =
            size <= kWideMergeLeaf && as_leaf <= inner && mergeable && mergeable(first(nodes, n), size);
        size_[n] = size | (leaf ? kLeafBit : 0);
        c[0] = leaf ? as_leaf : inner;
        for (int j = 2; j <= kBvhWidth; ++j) c[j - 1] = std::min(c[j - 2], spread(nodes, n, j, nullptr));
        return size;
    }
    bool leaf(uint32_t n) const { return (size_[n] & kLeafBit) != 0; }
    uint32_t size(uint32_t n) const { return size_[n] & ~kLeafBit; }
    // The start of the order range of n's subtree: its leftmost leaf's.
    static uint32_t first(const std::vector<BvhNode>& nodes, uint32_t n) {
        while (nodes[n].count == 0) n = nodes[n].first;
        return nodes[n].first;
    }
    // The lanes of binary node n's subtree given at most j of them, appended to kids.
    void lanes(const std::vector<BvhNode>& nodes, uint32_t n, int j, uint32_t* kids, int& count) const {
        const auto& c = cost_[n];
        while (j > 1 && c[j - 2] <= c[j - 1]) --j;  // the fewest lanes that cost the least
        if (j == 1 || nodes[n].count > 0) {
            kids[count++] = n;
            return;
        }
        int k = 1;
        spread(nodes, n, j, &k);
        lanes(nodes, nodes[n].first, k, kids, count);
        lanes(nodes, nodes[n].first + 1, j - k, kids, count);
    }
};

// The children of the wide node for inner node `n`: its two children's subtrees spread over at
// most kBvhWidth lanes at the least cost. Returns their number.
int wide_children(const std::vector<BvhNode>& nodes, const Collapse& r, uint32_t n, uint32_t* kids) {
    int k = 1;
    r.spread(nodes, n, kBvhWidth, &k);
    int count = 0;
    r.lanes(nodes, nodes[n].first, k, kids, count);
    r.lanes(nodes, nodes[n].first + 1, kBvhWidth - k, kids, count);
    return count;
}

// The number of wide nodes emit_wide writes for inner node `n`.
size_t count_wide(const std::vector<BvhNode>& nodes, const Collapse& r, uint32_t n) {
    uint32_t kids[kBvhWidth];
    const int count = wide_children(nodes, r, n, kids);
    size_t total = 1;
    for (int i = 0; i < count; ++i)
        if (!r.leaf(kids[i])) total += count_wide(nodes, r, kids[i]);
    return total;
}

// A node whose lanes are all empty boxes.
BvhWideNode empty_wide_node() {
    BvhWideNode node{};
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (int i = 0; i < kBvhWidth; ++i)
        for (int a = 0; a < 3; ++a) {
            node.lo[a][i] = kInf;
            node.hi[a][i] = -kInf;
        }
    return node;
}

void set_lane(BvhWideNode& node, int i, const BvhNode& child) {
    for (int a = 0; a < 3; ++a) {
        node.lo[a][i] = child.b[a];
        node.hi[a][i] = child.b[a + 3];
    }
    node.set_child(i, child.first, child.count);
}

// Writes the wide node for inner node `n` at out[at]; its inner children's subtrees go from
// out[at + 1] on, in lane order, each placed by place(kid, index) which returns the index after
// that subtree's last node. Returns the index after the last.
template <class Place>
uint32_t write_wide(const std::vector<BvhNode>& nodes, const Collapse& r, uint32_t n, BvhWideNode* out,
                    uint32_t at, Place&& place) {
    uint32_t kids[kBvhWidth];
    const int count = wide_children(nodes, r, n, kids);
    BvhWideNode node = empty_wide_node();
    uint32_t next = at + 1;
    for (int i = 0; i < count; ++i) {
        set_lane(node, i, nodes[kids[i]]);
        if (r.leaf(kids[i])) {
            node.set_child(i, Collapse::first(nodes, kids[i]), r.size(kids[i]));
        } else {
            node.set_child(i, next, 0);
            next = place(kids[i], next);
        }
    }
    out[at] = node;
    return next;
}

// Writes the wide node for inner node `n` at out[at] and, depth first, the nodes below it;
// returns the index after the last.
uint32_t emit_wide(const std::vector<BvhNode>& nodes, const Collapse& r, uint32_t n, BvhWideNode* out,
                   uint32_t at) {
    return write_wide(nodes, r, n, out, at,
                      [&](uint32_t kid, uint32_t next) { return emit_wide(nodes, r, kid, out, next); });
}

// A subtree that emit_wide writes on its own: binary node n's wide nodes go to out[at, ...).
struct WideJob {
    uint32_t n, at;
};

// The subtrees below the wide node for inner node `n` and `levels` more levels of its inner
// children, in the order place_wide meets them, into `roots`. Returns the number of wide nodes in
// those levels.
uint32_t subtrees_below(const std::vector<BvhNode>& nodes, const Collapse& r, uint32_t n, int levels,
                        std::vector<uint32_t>& roots) {
    uint32_t kids[kBvhWidth];
    const int count = wide_children(nodes, r, n, kids);
    uint32_t top = 1;
    for (int i = 0; i < count; ++i) {
        if (r.leaf(kids[i])) continue;
        if (levels > 0)
            top += subtrees_below(nodes, r, kids[i], levels - 1, roots);
        else
            roots.push_back(kids[i]);
    }
    return top;
}

// Writes the wide node for inner node `n` at out[at]; its inner children's subtrees, placed where
// emit_wide puts them, are written here down to `levels` more levels and left to `jobs` below.
// The subtree of the k-th job holds sizes[k] wide nodes. Returns the index after the last.
uint32_t place_wide(const std::vector<BvhNode>& nodes, const Collapse& r, uint32_t n, BvhWideNode* out,
                    uint32_t at, int levels, const std::vector<uint32_t>& sizes, std::vector<WideJob>& jobs) {
    return write_wide(nodes, r, n, out, at, [&](uint32_t kid, uint32_t next) {
        if (levels > 0) return place_wide(nodes, r, kid, out, next, levels - 1, sizes, jobs);
        const uint32_t size = sizes[jobs.size()];
        jobs.push_back({kid, next});
        return next + size;
    });
}

}  // namespace

std::vector<BvhWideNode> to_bvh_wide(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable,
                                     int threads) {
    std::vector<BvhWideNode> out;
    if (nodes.empty()) return out;
    if (nodes[0].count > 0) {
        BvhWideNode root = empty_wide_node();
        set_lane(root, 0, nodes[0]);
        out.push_back(root);
        return out;
    }
    // Counted first: the exact size, without a shrinking copy. The top two levels are written
    // here; the subtrees below them are counted, then written each to its own depth-first place,
    // in parallel: the same nodes as one depth-first walk, whatever the thread count.
    const Collapse r(nodes, mergeable, threads);
    std::vector<uint32_t> roots;
    size_t total = subtrees_below(nodes, r, 0, 1, roots);
    std::vector<uint32_t> sizes(roots.size());
    ParallelOptions options;
    options.threads = threads;
    parallel_for(roots.size(), options,
                 [&](size_t j, int) { sizes[j] = static_cast<uint32_t>(count_wide(nodes, r, roots[j])); });
    for (uint32_t size : sizes) total += size;
    out.resize(total);
    std::vector<WideJob> jobs;
    place_wide(nodes, r, 0, out.data(), 0, 1, sizes, jobs);
    parallel_for(jobs.size(), options,
                 [&](size_t j, int) { emit_wide(nodes, r, jobs[j].n, out.data(), jobs[j].at); });
    return out;
}

}  // namespace wsd::render
