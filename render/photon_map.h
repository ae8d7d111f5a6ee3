// The caustic photon map (wsd-language.md §5 "caustics"): photons stored where they landed on
// diffuse surfaces, in a balanced kd-tree, and the irradiance estimate at a shading point from the
// k nearest photons within a maximum radius, weighted by a cone filter.
#pragma once

#include <cstdint>
#include <vector>

#include "render/math.h"
#include "render/stats.h"

namespace wsd::render {

struct Photon {
    Vec3 p;       // where it landed
    Vec3f power;  // flux it carries (RGB)
    Vec3f n;      // the surface's geometric normal on the side it arrived from
};

class PhotonMap {
public:
    // Builds the tree over `photons` (reordered; the same input gives the same tree). `k`: the
    // photons an estimate uses; `max_radius`: the farthest one it looks.
    PhotonMap(std::vector<Photon> photons, int k, double max_radius);

    // Irradiance at p on the surface whose geometric normal on the viewer's side is n: the k
    // nearest photons within max_radius that arrived on the same side of a surface facing the same
    // way (normals within kNormalCos), E = 3 Σ Φ_i (1 − d_i / r) / (π r²), r the distance of the
    // k-th (or max_radius when fewer are found). Counts stats.photon_lookups and photons_visited.
    Color irradiance(const Vec3& p, const Vec3& n, RayStats& stats) const;

    size_t size() const { return photons_.size(); }
    int k() const { return k_; }
    double max_radius() const { return max_radius_; }
    const std::vector<Photon>& photons() const { return photons_; }  // in tree order

    // Normals of photons counted at a point agree this well (cos 25°): a wall meeting the floor
    // does not take the floor's photons.
    static constexpr double kNormalCos = 0.9;

private:
    void build(size_t lo, size_t hi);
    struct Heap;
    void search(size_t lo, size_t hi, const Vec3& p, const Vec3& n, Heap& heap, uint64_t& visited) const;

    std::vector<Photon> photons_;  // node of [lo, hi) is its median (lo + hi) / 2
    std::vector<uint8_t> axis_;    // the split axis of each node
    int k_;
    double max_radius_;
};

}  // namespace wsd::render
