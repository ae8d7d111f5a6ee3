// Caustic photons (wsd-language.md §5, docs/wsd-language.md "caustics"): which objects can focus
// light and which can receive it, and the photon map shot from the lights through them.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/photon_map.h"
#include "render/scene_spec.h"

namespace wsd::render {

class Scene;

// The shapes (indices into SceneSpec::shapes) that call for caustics. Focusing: a material with
// reflection or transmission (a CSG's or an instance's members count for it); only bounded ones
// are aimed at (`unbounded` lists the planes and other shapes photons cannot aim at). Receiving: a
// diffuse material, (1 − transmission)·diffuse > 0.
struct CausticObjects {
    std::vector<uint32_t> focusing, unbounded, receiving;
};
CausticObjects caustic_objects(const SceneSpec& spec);

// Why a scene that asks for caustic photons shoots none (empty when it shoots them).
std::string caustics_skipped(const SceneSpec& spec, const CausticObjects& objects);

struct CausticBuild {
    std::unique_ptr<PhotonMap> map;  // null when no photon was stored
    uint64_t shot = 0, stored = 0;
    double seconds = 0;
    std::string skipped;  // caustics_skipped()
    bool cancelled = false;
};

// Shoots settings.caustic_photons photons over `threads` threads (0 = all cores). Photon i draws
// its random numbers from (seed, i) and photons are stored in index order, so the map is the same
// for any thread count. Once `*cancel` holds true no more photons are shot and `cancelled` is set
// (the map is then incomplete).
CausticBuild build_caustics(const Scene& scene, const SceneSpec& spec, int threads,
                            const std::atomic<bool>* cancel = nullptr);

}  // namespace wsd::render
