// The collapse of the binary build tree into the wide traversal tree (BvhWideNode).
#include <limits>

#include "render/bvh.h"
#include "render/limits.h"

namespace wsd::render {

// Order positions and node indices fit a child's 24 bits (fewer nodes than primitives).
static_assert(kMaxPrimitives <= (size_t{1} << BvhWideNode::kFirstBits));
static_assert(kMaxLeafCount <= BvhWideNode::kMaxCount);

namespace {

float node_area(const BvhNode& n) {
    float x = n.b[3] - n.b[0], y = n.b[4] - n.b[1], z = n.b[5] - n.b[2];
    return x * y + y * z + z * x;
}

// A binary subtree of at most this many primitives becomes one leaf of the wide tree (its
// primitives are contiguous in the order) when the caller allows it: fewer, fuller nodes, for a
// primitive test or two more.
inline constexpr uint32_t kMergeLeaf = 3;

// Per binary node: the order range its subtree covers, and whether it is a leaf of the wide tree.
struct Ranges {
    std::vector<uint32_t> first, size;
    std::vector<uint8_t> leaf_;
    Ranges(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable)
        : first(nodes.size()), size(nodes.size()), leaf_(nodes.size()) {
        fill(nodes, mergeable, 0);
    }
    void fill(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable, uint32_t n) {
        if (nodes[n].count > 0) {
            first[n] = nodes[n].first;
            size[n] = nodes[n].count;
            leaf_[n] = 1;
            return;
        }
        const uint32_t a = nodes[n].first, b = a + 1;
        fill(nodes, mergeable, a);
        fill(nodes, mergeable, b);
        first[n] = first[a];
        size[n] = size[a] + size[b];
        leaf_[n] = size[n] <= kMergeLeaf && mergeable && mergeable(first[n], size[n]);
    }
    bool leaf(const std::vector<BvhNode>&, uint32_t n) const { return leaf_[n] != 0; }
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
            if (!r.leaf(nodes, kids[i]) &&
                (open < 0 || node_area(nodes[kids[i]]) > node_area(nodes[kids[open]])))
                open = i;
        if (open < 0) break;
        uint32_t inner = kids[open];
        kids[open] = nodes[inner].first;
        kids[count++] = nodes[inner].first + 1;
    }
    return count;
}

// The number of wide nodes emit_wide makes for inner node `n`.
size_t count_wide(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n) {
    uint32_t kids[kBvhWidth];
    const int count = wide_children(nodes, r, n, kids);
    size_t total = 1;
    for (int i = 0; i < count; ++i)
        if (!r.leaf(nodes, kids[i])) total += count_wide(nodes, r, kids[i]);
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

// Emits the wide node for inner node `n` and, depth first, the nodes below it; returns its index.
uint32_t emit_wide(const std::vector<BvhNode>& nodes, const Ranges& r, uint32_t n,
                   std::vector<BvhWideNode>& out) {
    uint32_t kids[kBvhWidth];
    const int count = wide_children(nodes, r, n, kids);
    const uint32_t index = static_cast<uint32_t>(out.size());
    out.push_back(BvhWideNode{});
    BvhWideNode node = empty_wide_node();
    for (int i = 0; i < count; ++i) {
        const BvhNode& k = nodes[kids[i]];
        set_lane(node, i, k);
        if (r.leaf(nodes, kids[i]))
            node.set_child(i, r.first[kids[i]], r.size[kids[i]]);
        else
            node.set_child(i, emit_wide(nodes, r, kids[i], out), 0);
    }
    out[index] = node;
    return index;
}

}  // namespace

std::vector<BvhWideNode> to_bvh_wide(const std::vector<BvhNode>& nodes, const WideLeafFn& mergeable) {
    std::vector<BvhWideNode> out;
    if (nodes.empty()) return out;
    // Counted first: the exact size, without a shrinking copy. Traversal reads these nodes, so
    // no huge pages (see prefer_huge_pages).
    const Ranges r(nodes, mergeable);
    out.reserve(nodes[0].count > 0 ? 1 : count_wide(nodes, r, 0));
    if (nodes[0].count > 0) {
        BvhWideNode root = empty_wide_node();
        set_lane(root, 0, nodes[0]);
        out.push_back(root);
    } else {
        emit_wide(nodes, r, 0, out);
    }
    return out;
}

}  // namespace wsd::render
