// The collapse of the binary build tree into the wide traversal tree (BvhWideNode).
#include <limits>

#include "render/bvh.h"
#include "render/limits.h"
#include "render/parallel.h"

namespace wsd::render {

// Order positions and node indices fit a child's 24 bits (fewer nodes than primitives).
static_assert(kMaxPrimitives <= (size_t{1} << BvhWideNode::kFirstBits));
static_assert(kMaxLeafCount <= BvhWideNode::kMaxCount);

namespace {

float node_area(const BvhNode& n) {
    float x = n.b[3] - n.b[0], y = n.b[4] - n.b[1], z = n.b[5] - n.b[2];
    return x * y + y * z + z * x;
}

// Per binary node: how many primitives its subtree holds (bits 0-30), and whether it is a leaf of
// the wide tree (bit 31).
struct Ranges {
    static constexpr uint32_t kLeafBit = 1u << 31;
    std::vector<uint32_t> size_;
    Ranges(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable) : size_(nodes.size()) {
        fill(nodes, mergeable, 0);
    }
    uint32_t fill(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable, uint32_t n) {
        if (nodes[n].count > 0) {
            size_[n] = nodes[n].count | kLeafBit;
            return nodes[n].count;
        }
        const uint32_t size =
            fill(nodes, mergeable, nodes[n].first) + fill(nodes, mergeable, nodes[n].first + 1);
        const bool leaf = size <= kWideMergeLeaf && mergeable && mergeable(first(nodes, n), size);
        size_[n] = size | (leaf ? kLeafBit : 0);
        return size;
    }
    bool leaf(uint32_t n) const { return (size_[n] & kLeafBit) != 0; }
    uint32_t size(uint32_t n) const { return size_[n] & ~kLeafBit; }
    // The start of the order range of n's subtree: its leftmost leaf's.
    static uint32_t first(const std::vector<BvhNode>& nodes, uint32_t n) {
        while (nodes[n].count == 0) n = nodes[n].first;
        return nodes[n].first;
    }
};

// The children of the wide node for inner node `n`: its two children, opening the largest inner
// one until there are kBvhWidth (ties go to the first in lane order). Returns their number.
int wide_children(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n, uint32_t* kids) {
    kids[0] = nodes[n].first;
    kids[1] = nodes[n].first + 1;
    int count = 2;
    while (count < kBvhWidth) {
        int open = -1;
        for (int i = 0; i < count; ++i)
            if (!r.leaf(kids[i]) && (open < 0 || node_area(nodes[kids[i]]) > node_area(nodes[kids[open]])))
                open = i;
        if (open < 0) break;
        uint32_t inner = kids[open];
        kids[open] = nodes[inner].first;
        kids[count++] = nodes[inner].first + 1;
    }
    return count;
}

// The number of wide nodes emit_wide writes for inner node `n`.
size_t count_wide(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n) {
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
uint32_t write_wide(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n, BvhWideNode* out,
                    uint32_t at, Place&& place) {
    uint32_t kids[kBvhWidth];
    const int count = wide_children(nodes, r, n, kids);
    BvhWideNode node = empty_wide_node();
    uint32_t next = at + 1;
    for (int i = 0; i < count; ++i) {
        set_lane(node, i, nodes[kids[i]]);
        if (r.leaf(kids[i])) {
            node.set_child(i, Ranges::first(nodes, kids[i]), r.size(kids[i]));
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
uint32_t emit_wide(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n, BvhWideNode* out,
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
uint32_t subtrees_below(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n, int levels,
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
uint32_t place_wide(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n, BvhWideNode* out,
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
    const Ranges r(nodes, mergeable);
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
