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

// The least cost of a binary node's subtree as j lanes of a wide node (cost[j - 1], j = 1 ..
// kBvhWidth): one lane (a leaf or a wide node of its own), or its children's subtrees spread over
// j lanes. The optimal collapse by dynamic programming, after Ylitie, Karras and Laine,
// "Efficient incoherent ray traversal on GPUs through compressed wide BVHs" (2017).
using Costs = std::array<float, kBvhWidth>;

// The least cost of spreading two children whose costs are a and b over j lanes (2 <= j), and
// how many of them go to the first child (the fewest of those that tie). One lane for the first
// child is the answer to beat, so that one is chosen even when every cost is infinite (boxes
// near the float range) and none compares less.
float spread(const Costs& a, const Costs& b, int j, int& first_lanes) {
    float best = a[0] + b[j - 2];
    first_lanes = 1;
    for (int k = 2; k < j; ++k) {
        const float c = a[k - 1] + b[j - k - 1];
        if (c < best) {
            best = c;
            first_lanes = k;
        }
    }
    return best;
}

// Per binary node, what the collapse decided, in 64 bits (the costs themselves, 32 bytes a node,
// are needed only while its parent is filled, and are kept on the stack): whether it is a leaf of
// the wide tree and then how many primitives it holds; how its children's subtrees spread over a
// wide node's kBvhWidth lanes; and, given at most j lanes (j = 2 .. kBvhWidth), how many it takes
// (the fewest that cost the least) and how many of those go to its first child.
class Collapse {
public:
    // Filled bottom up: the subtrees below depth kSplitDepth on `threads` threads, then the top.
    static constexpr int kSplitDepth = 6;
    Collapse(const HugePageVector<BvhNode>& nodes, const WideLeafFn& mergeable, int threads)
        : nodes_(nodes), mergeable_(mergeable), plan_(nodes.size()) {
        below(0, kSplitDepth, roots_);
        std::sort(roots_.begin(), roots_.end());  // looked up by fill
        ParallelOptions options;
        options.threads = threads;
        filled_.resize(roots_.size());
        parallel_for(roots_.size(), options, [&](size_t j, int) { filled_[j] = fill(roots_[j], -1); });
        fill(0, kSplitDepth);
        roots_.clear();
        filled_.clear();
    }
    bool leaf(uint32_t n) const { return (plan_[n] & kLeafBit) != 0; }
    // The primitives of a leaf of the wide tree.
    uint32_t size(uint32_t n) const { return static_cast<uint32_t>(plan_[n] & kSizeMask); }
    // How many of the kBvhWidth lanes of the wide node for inner node n its first child's
    // subtree takes.
    int first_lanes(uint32_t n) const { return static_cast<int>(plan_[n] >> kWideShift & 7u); }
    // The lanes of binary node n's subtree given at most j of them, appended to kids.
    void lanes(uint32_t n, int j, uint32_t* kids, int& count) const {
        if (j > 1) {
            const uint64_t choice = plan_[n] >> (kChoiceShift + 6 * (j - 2));
            j = static_cast<int>(choice & 7u) + 1;  // the fewest lanes that cost the least
            if (j > 1 && nodes_[n].count == 0) {
                const int k = static_cast<int>(choice >> 3 & 7u);
                lanes(nodes_[n].first, k, kids, count);
                lanes(nodes_[n].first + 1, j - k, kids, count);
                return;
            }
        }
        kids[count++] = n;
    }
    // The start of the order range of n's subtree: its leftmost leaf's.
    uint32_t first(uint32_t n) const {
        while (nodes_[n].count == 0) n = nodes_[n].first;
        return nodes_[n].first;
    }

private:
    // Bits of a plan: the size of a leaf, the leaf bit, first_lanes, then for j = 2 ..
    // kBvhWidth six bits each: the lanes taken less one, and how many go to the first child.
    static constexpr uint64_t kSizeMask = 0xff;
    static constexpr uint64_t kLeafBit = 1u << 8;
    static constexpr int kWideShift = 9;
    static constexpr int kChoiceShift = 12;
    static_assert(kBvhWidth == 8 && kChoiceShift + 6 * (kBvhWidth - 1) <= 64);
    static_assert(kMaxLeafCount <= kSizeMask && kWideMergeLeaf <= kSizeMask);

    struct Filled {
        uint32_t size = 0;  // primitives in the subtree
        Costs cost{};
    };

    // The nodes `depth` levels below n (or leaves above that), into roots.
    void below(uint32_t n, int depth, std::vector<uint32_t>& roots) const {
        if (depth == 0 || nodes_[n].count > 0) {
            roots.push_back(n);
            return;
        }
        below(nodes_[n].first, depth - 1, roots);
        below(nodes_[n].first + 1, depth - 1, roots);
    }
    // Plans n's subtree and returns its size and costs; a node `depth` levels below n is taken as
    // planned already, its result in filled_ (depth < 0: none is).
    Filled fill(uint32_t n, int depth) {
        if (depth == 0) {
            const auto at = std::lower_bound(roots_.begin(), roots_.end(), n);
            return filled_[static_cast<size_t>(at - roots_.begin())];
        }
        const BvhNode& node = nodes_[n];
        const float area = node_area(node);
        Filled out;
        if (node.count > 0) {
            plan_[n] = node.count | kLeafBit;
            out.size = node.count;
            out.cost.fill(leaf_cost(area, node.count));
            return out;
        }
        const Filled a = fill(node.first, depth - 1);
        const Filled b = fill(node.first + 1, depth - 1);
        out.size = a.size + b.size;
        // The least cost over j lanes and its first child's share, j = 2 .. kBvhWidth.
        float spread_cost[kBvhWidth + 1];
        int share[kBvhWidth + 1];
        for (int j = 2; j <= kBvhWidth; ++j) spread_cost[j] = spread(a.cost, b.cost, j, share[j]);
        const float inner = area * kNodeCost + spread_cost[kBvhWidth];
        const float as_leaf = leaf_cost(area, out.size);
        const bool leaf =
            out.size <= kWideMergeLeaf && as_leaf <= inner && mergeable_ && mergeable_(first(n), out.size);
        auto& c = out.cost;
        c[0] = leaf ? as_leaf : inner;
        for (int j = 2; j <= kBvhWidth; ++j) c[j - 1] = std::min(c[j - 2], spread_cost[j]);
        uint64_t plan = (leaf ? out.size | kLeafBit : 0) | uint64_t(share[kBvhWidth]) << kWideShift;
        for (int j = 2; j <= kBvhWidth; ++j) {
            int taken = j;
            while (taken > 1 && c[taken - 2] <= c[taken - 1]) --taken;
            const uint64_t choice = uint64_t(taken - 1) | uint64_t(taken > 1 ? share[taken] : 0) << 3;
            plan |= choice << (kChoiceShift + 6 * (j - 2));
        }
        plan_[n] = plan;
        return out;
    }

    const HugePageVector<BvhNode>& nodes_;
    const WideLeafFn& mergeable_;
    std::vector<uint64_t> plan_;
    std::vector<uint32_t> roots_;  // while filling: the subtrees filled first, in node order
    std::vector<Filled> filled_;
};

// The children of the wide node for inner node `n`: its two children's subtrees spread over at
// most kBvhWidth lanes at the least cost. Returns their number.
int wide_children(const HugePageVector<BvhNode>& nodes, const Collapse& r, uint32_t n, uint32_t* kids) {
    const int k = r.first_lanes(n);
    int count = 0;
    r.lanes(nodes[n].first, k, kids, count);
    r.lanes(nodes[n].first + 1, kBvhWidth - k, kids, count);
    return count;
}

// The number of wide nodes emit_wide writes for inner node `n`.
size_t count_wide(const HugePageVector<BvhNode>& nodes, const Collapse& r, uint32_t n) {
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
uint32_t write_wide(const HugePageVector<BvhNode>& nodes, const Collapse& r, uint32_t n, BvhWideNode* out,
                    uint32_t at, Place&& place) {
    uint32_t kids[kBvhWidth];
    const int count = wide_children(nodes, r, n, kids);
    BvhWideNode node = empty_wide_node();
    uint32_t next = at + 1;
    for (int i = 0; i < count; ++i) {
        set_lane(node, i, nodes[kids[i]]);
        if (r.leaf(kids[i])) {
            node.set_child(i, r.first(kids[i]), r.size(kids[i]));
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
uint32_t emit_wide(const HugePageVector<BvhNode>& nodes, const Collapse& r, uint32_t n, BvhWideNode* out,
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
uint32_t subtrees_below(const HugePageVector<BvhNode>& nodes, const Collapse& r, uint32_t n, int levels,
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
uint32_t place_wide(const HugePageVector<BvhNode>& nodes, const Collapse& r, uint32_t n, BvhWideNode* out,
                    uint32_t at, int levels, const std::vector<uint32_t>& sizes, std::vector<WideJob>& jobs) {
    return write_wide(nodes, r, n, out, at, [&](uint32_t kid, uint32_t next) {
        if (levels > 0) return place_wide(nodes, r, kid, out, next, levels - 1, sizes, jobs);
        const uint32_t size = sizes[jobs.size()];
        jobs.push_back({kid, next});
        return next + size;
    });
}

}  // namespace

HugePageVector<BvhWideNode> to_bvh_wide(const HugePageVector<BvhNode>& nodes, const WideLeafFn& mergeable,
                                        int threads) {
    HugePageVector<BvhWideNode> out;
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
