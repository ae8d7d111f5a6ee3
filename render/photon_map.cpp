// The photon kd-tree: a median split along the longest side of each range's box, stored in place
// (the node of the range [lo, hi) is element (lo + hi) / 2, its children the halves either side),
// so it is balanced by construction and needs no pointers. k-nearest search with a bounded
// max-heap, pruning subtrees by the distance to their splitting plane.
#include "render/photon_map.h"

#include <algorithm>

namespace wsd::render {

struct PhotonMap::Heap {
    struct Entry {
        double d2;
        uint32_t index;
        bool operator<(const Entry& o) const { return d2 < o.d2 || (d2 == o.d2 && index < o.index); }
    };
    std::vector<Entry> items;
    size_t k;
    double limit2;  // the squared search radius: the k-th distance once full, max_radius² before

    void offer(double d2, uint32_t index) {
        if (!(d2 < limit2)) return;
        if (items.size() < k) {
            items.push_back({d2, index});
            std::push_heap(items.begin(), items.end());
            if (items.size() == k) limit2 = items.front().d2;
            return;
        }
        std::pop_heap(items.begin(), items.end());
        items.back() = {d2, index};
        std::push_heap(items.begin(), items.end());
        limit2 = items.front().d2;
    }
};

PhotonMap::PhotonMap(std::vector<Photon> photons, int k, double max_radius)
    : photons_(std::move(photons)), axis_(photons_.size(), 0), k_(std::max(1, k)), max_radius_(max_radius) {
    build(0, photons_.size());
}

void PhotonMap::build(size_t lo, size_t hi) {
    if (hi - lo <= 1) return;
    Vec3 a = photons_[lo].p, b = a;
    for (size_t i = lo + 1; i < hi; ++i) {
        a = glm::min(a, photons_[i].p);
        b = glm::max(b, photons_[i].p);
    }
    const Vec3 e = b - a;
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    const size_t mid = (lo + hi) / 2;
    // Ties on the axis are broken by the whole position; photons at one point keep an order that
    // follows from the input order alone (photon index order), so the tree never depends on the
    // number of threads that shot them.
    std::nth_element(photons_.begin() + long(lo), photons_.begin() + long(mid), photons_.begin() + long(hi),
                     [axis](const Photon& x, const Photon& y) {
                         if (x.p[axis] != y.p[axis]) return x.p[axis] < y.p[axis];
                         if (x.p.x != y.p.x) return x.p.x < y.p.x;
                         if (x.p.y != y.p.y) return x.p.y < y.p.y;
                         return x.p.z < y.p.z;
                     });
    axis_[mid] = uint8_t(axis);
    build(lo, mid);
    build(mid + 1, hi);
}

void PhotonMap::search(size_t lo, size_t hi, const Vec3& p, const Vec3& n, Heap& heap,
                       uint64_t& visited) const {
    while (lo < hi) {
        const size_t mid = (lo + hi) / 2;
        const Photon& ph = photons_[mid];
        const int axis = axis_[mid];
        const double delta = p[axis] - ph.p[axis];
        // The near side first; the far side only if the splitting plane is within the radius.
        if (hi - lo > 1) {
            if (delta < 0) {
                search(lo, mid, p, n, heap, visited);
            } else {
                search(mid + 1, hi, p, n, heap, visited);
            }
        }
        ++visited;
        const Vec3 d = ph.p - p;
        const double d2 = glm::dot(d, d);
        if (d2 < heap.limit2 && glm::dot(Vec3(ph.n), n) >= kNormalCos) heap.offer(d2, uint32_t(mid));
        if (!(delta * delta < heap.limit2)) return;
        if (delta < 0) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
}

Color PhotonMap::irradiance(const Vec3& p, const Vec3& n, RayStats& stats) const {
    ++stats.photon_lookups;
    if (photons_.empty()) return Color(0);
    thread_local Heap heap;
    heap.items.clear();
    heap.k = size_t(k_);
    heap.limit2 = max_radius_ * max_radius_;
    uint64_t visited = 0;
    search(0, photons_.size(), p, n, heap, visited);
    stats.photons_visited += visited;
    if (heap.items.empty()) return Color(0);
    const double r2 = heap.items.size() == heap.k ? heap.limit2 : max_radius_ * max_radius_;
    if (!(r2 > 0)) return Color(0);
    const double r = std::sqrt(r2);
    // Summed in index order, so the estimate does not depend on the heap's internal order.
    std::sort(heap.items.begin(), heap.items.end(),
              [](const Heap::Entry& a, const Heap::Entry& b) { return a.index < b.index; });
    Color sum(0);
    for (const Heap::Entry& e : heap.items)
        sum += Color(photons_[e.index].power) * (1.0 - std::sqrt(e.d2) / r);
    // The cone filter's weights integrate to π r² / 3 over the disc.
    return sum * (3.0 / (kPi * r2));
}

}  // namespace wsd::render
