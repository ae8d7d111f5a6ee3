// Tile files (`wsd render --tile I/N` or `--region`, merged by `wsd merge`): a standard PFM of the
// region's pixels followed by one trailing line `WSDTILE {json}` that says where the tile belongs
// and what produced it. PFM readers stop after the float data, so the trailer is invisible to them.
// A tile rendered with auxiliary images names them in the trailer ("aovs") and carries one PFM
// of each after the trailer line, in the order named (depth as a one-channel "Pf").
#pragma once

#include <cstdint>
#include <string>

#include "app/image_files.h"
#include "render/renderer.h"

namespace wsd::app {

struct TileMeta {
    int full_width = 0, full_height = 0;  // the whole image
    render::Region region;                // this tile's pixels in the whole image
    std::string scene_hash;               // FNV-1a 64 of the scene text and every included file
    std::string settings_hash;            // FNV-1a 64 of every effective setting but the seed
    std::string defines_hash;             // FNV-1a 64 of the --define values; "" without any
    uint32_t seed = 0;
    int tile_index = 0, tile_count = 0;  // from --tile I/N; 0 for --region
    std::string scene;                   // the scene path as given, for messages
    AovSelection aovs;                   // the auxiliary images the tile carries
    long long frame = -1;                // the frame of --frames; -1 for a still
    double clock = 0;                    // the scene's `clock`
};

// The bytes of a tile file: PFM ("PF", bottom row first, little-endian floats) + trailer, then
// the auxiliary images meta.aovs selects (`aovs` holds them).
std::string encode_tile(const render::Film& film, const render::AovFilm& aovs, const TileMeta& meta);

// Parses a tile file; false + error for a malformed PFM, a missing or malformed trailer, a
// region that disagrees with the PFM's size, or auxiliary images missing or of the wrong size.
bool decode_tile(const std::string& bytes, render::Film& film, render::AovFilm& aovs, TileMeta& meta,
                 std::string& error);

}  // namespace wsd::app
