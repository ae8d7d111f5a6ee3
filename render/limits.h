// Every limit a scene, its command line and the files wsd reads are held to, in one place. The
// language's property tables, the renderer's validation, the command line and the image readers
// all take their bounds from here, so a limit is changed by changing one line.
#pragma once

#include <cfloat>
#include <cstddef>
#include <cstdint>

namespace wsd::render {

// The rendered image: each side, and the pixel count (a float RGB frame buffer of 2^28 pixels is
// 3 GiB). Image files read back (tiles, PFM) are held to the same bounds.
inline constexpr int kMaxImageSide = 100000;
inline constexpr long long kMaxPixels = 1LL << 28;

inline constexpr int kMaxSupersamples = 4096;
inline constexpr int kMaxDepth = 256;              // reflection and refraction bounces
inline constexpr int kMaxIndirectSamples = 65536;  // indirect paths a camera sample
inline constexpr int kMaxIndirectBounces = 64;     // diffuse reflections an indirect path makes
inline constexpr double kMaxSeed = 4294967295.0;
// Caustic photons shot (each stored one takes 48 bytes).
inline constexpr int kMaxCausticPhotons = 100000000;

// An area light's sample grid: each side, and the cells of the whole grid. The command line's
// `--light-samples N` makes N×N grids, so its N stops at the square root of the cell limit.
inline constexpr int kMaxLightGridSide = 1024;
inline constexpr int kMaxLightSamples = 65536;
inline constexpr int kMaxSquareLightGridSide = 256;
static_assert(kMaxSquareLightGridSide * kMaxSquareLightGridSide == kMaxLightSamples);

// Primitives of a whole scene, a mesh's triangles counted one by one (primitive ids are 24 bits).
inline constexpr size_t kMaxPrimitives = size_t{1} << 24;
// Instances of shared geometry (each counted once however much it holds), apart from the above.
inline constexpr size_t kMaxInstances = size_t{1} << 24;

// A texture image, decoded (a 20-byte header can claim 4 billion pixels).
inline constexpr long long kMaxTexturePixels = 1LL << 27;

inline constexpr int kMaxOctaves = 64;  // perlin textures

// Colours and light intensities are summed in single precision: a larger value is refused where it
// is written instead of rendering as infinity (geometry stays double precision).
inline constexpr double kMaxSingle = FLT_MAX;

// Two directions (a camera's up and view, an area light's edges) count as parallel when the sine
// of their angle is below this: a frame built from them would be dominated by rounding.
inline constexpr double kParallelSine = 1e-9;

// Magnitude of each `scale` factor: beyond it a transform is as good as singular.
inline constexpr double kMinScale = 1e-12;
inline constexpr double kMaxScale = 1e12;

}  // namespace wsd::render
