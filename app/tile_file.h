// Tile files (`wsd render --tile I/N` or `--region`, merged by `wsd merge`): a standard PFM of the
// region's pixels followed by one trailing line `WSDTILE {json}` that says where the tile belongs
// and what produced it. PFM readers stop after the float data, so the trailer is invisible to them.
#pragma once

#include <cstdint>
#include <string>

#include "render/renderer.h"

namespace wsd::app {

struct TileMeta {
    int full_width = 0, full_height = 0;  // the whole image
    render::Region region;                // this tile's pixels in the whole image
    std::string scene_hash;               // FNV-1a 64 of the scene text and every included file
    std::string settings_hash;            // FNV-1a 64 of every effective setting but the seed
    uint32_t seed = 0;
    int tile_index = 0, tile_count = 0;  // from --tile I/N; 0 for --region
    std::string scene;                   // the scene path as given, for messages
    long long frame = -1;                // the frame of --frames; -1 for a still
    double clock = 0;                    // the scene's `clock`
};

// The bytes of a tile file: PFM ("PF", bottom row first, little-endian floats) + trailer.
std::string encode_tile(const render::Film& film, const TileMeta& meta);

// Parses a tile file; false + error for a malformed PFM, a missing or malformed trailer, or
// a region that disagrees with the PFM's size.
bool decode_tile(const std::string& bytes, render::Film& film, TileMeta& meta, std::string& error);

}  // namespace wsd::app
