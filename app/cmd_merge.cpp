// `wsd merge TILE... -o OUT`: reads tile files, checks that they come from one scene with one set
// of settings and one seed and that they cover the image exactly once, then assembles them and
// writes OUT atomically, with the auxiliary images the tiles carry (as `wsd render` writes them).
// Any problem names the tile at fault and nothing is written.
#include <algorithm>
#include <iostream>
#include <map>
#include <set>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/image_files.h"
#include "app/io_util.h"
#include "app/tile_file.h"
#include "render/image_io.h"

namespace wsd::app {

namespace {

struct Tile {
    std::string path;
    TileMeta meta;
    render::Film film;
    render::AovFilm aovs;
};

std::string aov_list(const AovSelection& s) {
    std::string out;
    for (const std::string& name : s.names()) out += (out.empty() ? "" : ", ") + name;
    return out.empty() ? "none" : out;
}

// Copies the rows of a tile's image (`channels` floats a pixel) into the whole image's.
void paste(const std::vector<float>& tile, const render::Region& r, int width, size_t channels,
           std::vector<float>& image) {
    const size_t row = static_cast<size_t>(r.x1 - r.x0) * channels;
    for (int y = r.y0; y < r.y1; ++y)
        std::copy_n(
            tile.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y - r.y0) * row), row,
            image.begin() + static_cast<std::ptrdiff_t>(
                                (static_cast<size_t>(y) * static_cast<size_t>(width) + r.x0) * channels));
}

std::string describe(const render::Region& r) {
    return "x " + std::to_string(r.x0) + ".." + std::to_string(r.x1 - 1) + ", y " + std::to_string(r.y0) +
           ".." + std::to_string(r.y1 - 1);
}

bool intersects(const render::Region& a, const render::Region& b) {
    return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

std::string frame_name(const TileMeta& meta) {
    return meta.frame < 0 ? std::string("a still") : "frame " + std::to_string(meta.frame);
}

// Every tile must agree with the first on the scene and its --define values, the frame and its
// clock, the settings, the size and the seed.
int check_consistency(const std::vector<Tile>& tiles) {
    const Tile& first = tiles.front();
    for (const Tile& t : tiles) {
        if (t.meta.scene_hash != first.meta.scene_hash)
            return fail(exit_code::input_error,
                        "tile '" + t.path + "' was rendered from a different scene than '" + first.path +
                            "' (scene hash " + t.meta.scene_hash + " vs " + first.meta.scene_hash + ")");
        if (t.meta.defines_hash != first.meta.defines_hash)
            return fail(
                exit_code::input_error,
                "tile '" + t.path + "' was rendered with other --define values than '" + first.path + "'");
        if (t.meta.seed != first.meta.seed)
            return fail(exit_code::input_error, "tile '" + t.path + "' was rendered with seed " +
                                                    std::to_string(t.meta.seed) + ", but '" + first.path +
                                                    "' with seed " + std::to_string(first.meta.seed));
        if (t.meta.full_width != first.meta.full_width || t.meta.full_height != first.meta.full_height)
            return fail(exit_code::input_error,
                        "tile '" + t.path + "' belongs to a " + std::to_string(t.meta.full_width) + "x" +
                            std::to_string(t.meta.full_height) + " image, but '" + first.path + "' to a " +
                            std::to_string(first.meta.full_width) + "x" +
                            std::to_string(first.meta.full_height) + " one");
        if (t.meta.frame != first.meta.frame)
            return fail(exit_code::input_error, "tile '" + t.path + "' is of " + frame_name(t.meta) +
                                                    ", but '" + first.path + "' of " +
                                                    frame_name(first.meta));
        if (t.meta.clock != first.meta.clock)
            return fail(exit_code::input_error,
                        "tile '" + t.path + "' was rendered at another clock than '" + first.path + "'");
        if (t.meta.settings_hash != first.meta.settings_hash)
            return fail(
                exit_code::input_error,
                "tile '" + t.path + "' was rendered with different settings than '" + first.path + "'");
        if (!(t.meta.aovs == first.meta.aovs))
            return fail(exit_code::input_error, "tile '" + t.path + "' carries the auxiliary images " +
                                                    aov_list(t.meta.aovs) + ", but '" + first.path + "' " +
                                                    aov_list(first.meta.aovs));
    }
    return exit_code::ok;
}

// Duplicates and overlaps name both tiles; a gap names the uncovered rectangle and, for
// --tile I/N tiles, the tile numbers that are missing.
int check_coverage(const std::vector<Tile>& tiles) {
    for (size_t i = 0; i < tiles.size(); ++i)
        for (size_t j = 0; j < i; ++j) {
            const render::Region &a = tiles[i].meta.region, &b = tiles[j].meta.region;
            if (a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1)
                return fail(exit_code::input_error, "tile '" + tiles[i].path + "' duplicates '" +
                                                        tiles[j].path + "' (" + describe(a) + ")");
            if (intersects(a, b))
                return fail(exit_code::input_error, "tile '" + tiles[i].path + "' (" + describe(a) +
                                                        ") overlaps '" + tiles[j].path + "' (" + describe(b) +
                                                        ")");
        }
    // With no overlaps, the image is covered iff the areas add up; otherwise find a gap on the
    // grid of tile edges (each cell of that grid is wholly covered or wholly not).
    const int w = tiles.front().meta.full_width, h = tiles.front().meta.full_height;
    long long area = 0;
    for (const Tile& t : tiles)
        area += static_cast<long long>(t.meta.region.x1 - t.meta.region.x0) *
                (t.meta.region.y1 - t.meta.region.y0);
    if (area == static_cast<long long>(w) * h) return exit_code::ok;
    std::set<int> xs{0, w}, ys{0, h};
    for (const Tile& t : tiles) {
        xs.insert({t.meta.region.x0, t.meta.region.x1});
        ys.insert({t.meta.region.y0, t.meta.region.y1});
    }
    std::string gap;
    for (auto y = ys.begin(); gap.empty() && std::next(y) != ys.end(); ++y)
        for (auto x = xs.begin(); gap.empty() && std::next(x) != xs.end(); ++x) {
            const render::Region cell{*x, *y, *std::next(x), *std::next(y)};
            const bool covered = std::any_of(tiles.begin(), tiles.end(),
                                             [&](const Tile& t) { return intersects(t.meta.region, cell); });
            if (!covered) gap = describe(cell);
        }
    std::string missing;
    int missing_count = 0;
    const int count = tiles.front().meta.tile_count;
    if (count > 0) {
        std::set<int> present;
        for (const Tile& t : tiles) present.insert(t.meta.tile_index);
        for (int i = 1; i <= count; ++i)
            if (!present.count(i)) {
                missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(count);
                ++missing_count;
            }
    }
    return fail(
        exit_code::input_error,
        "the tiles do not cover the image: pixels " + gap + " are missing" +
            (missing.empty()
                 ? std::string()
                 : std::string(missing_count == 1 ? " (missing tile " : " (missing tiles ") + missing + ")"));
}

}  // namespace

int run_merge(const MergeArgs& args) {
    std::string error;
    if (!known_image_format(args.output)) return fail(exit_code::usage, unknown_format_message(args.output));
    if (!output_directory_exists(args.output, error)) return fail(exit_code::io, error);
    // `-o` naming one of the tiles would replace it with the merged image.
    for (const std::string& path : args.tiles)
        if (same_path(path, args.output))
            return fail(exit_code::usage, "-o '" + args.output + "' names the tile '" + path + "'");

    std::vector<Tile> tiles;
    for (const std::string& path : args.tiles) {
        std::string bytes;
        if (!read_input_file(path, bytes, error)) return fail(exit_code::io, error);
        Tile tile;
        tile.path = path;
        if (!decode_tile(bytes, tile.film, tile.aovs, tile.meta, error))
            return fail(exit_code::input_error, "tile '" + path + "': " + error);
        tiles.push_back(std::move(tile));
    }
    if (const int s = check_consistency(tiles); s != exit_code::ok) return s;
    if (const int s = check_coverage(tiles); s != exit_code::ok) return s;

    render::Film image;
    image.width = tiles.front().meta.full_width;
    image.height = tiles.front().meta.full_height;
    const size_t pixels = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
    image.rgb.assign(pixels * 3, 0.0f);
    const AovSelection& selection = tiles.front().meta.aovs;
    render::AovFilm aovs;
    if (selection.traced())
        aovs = {std::vector<float>(pixels * 3, 0.0f),
                std::vector<float>(pixels * 3, 0.0f),
                std::vector<float>(pixels, 0.0f),
                {}};
    if (selection.samples) aovs.samples.assign(pixels, 0.0f);
    for (const Tile& t : tiles) {
        paste(t.film.rgb, t.meta.region, image.width, 3, image.rgb);
        if (selection.samples) paste(t.aovs.samples, t.meta.region, image.width, 1, aovs.samples);
        if (!selection.traced()) continue;
        paste(t.aovs.albedo, t.meta.region, image.width, 3, aovs.albedo);
        paste(t.aovs.normal, t.meta.region, image.width, 3, aovs.normal);
        paste(t.aovs.depth, t.meta.region, image.width, 1, aovs.depth);
    }
    if (!write_image_with_aovs(args.output, image, aovs, selection, error)) return fail(exit_code::io, error);
    return exit_code::ok;
}

}  // namespace wsd::app
