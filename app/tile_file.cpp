// Encoding and decoding tile files: PFM bytes (render/image_io) plus the `WSDTILE` trailer, whose
// JSON nlohmann-json writes and reads.
#include "app/tile_file.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string_view>

#include "app/io_util.h"
#include "render/image_io.h"

namespace wsd::app {

namespace {

using Json = nlohmann::ordered_json;  // keys stay in the order written

constexpr const char* trailer_tag = "WSDTILE ";

// `v` as an integer in [lo, hi]; false when it is not a whole number in that range.
template <class T>
bool whole_number(const Json& v, double lo, double hi, T& out) {
    if (!v.is_number()) return false;
    const double d = v.get<double>();
    if (!(d >= lo && d <= hi) || d != std::floor(d)) return false;
    out = static_cast<T>(d);
    return true;
}

// The field `key` of the trailer, or null when it is absent.
const Json& field(const Json& fields, const char* key) {
    static const Json absent;
    const auto it = fields.find(key);
    return it == fields.end() ? absent : *it;
}

bool whole_numbers(const Json& v, size_t count, int* out) {
    if (!v.is_array() || v.size() != count) return false;
    for (size_t i = 0; i < count; ++i)
        if (!whole_number(v[i], 0, 1e9, out[i])) return false;
    return true;
}

// Reads the trailer's fields into `meta`; false + what is wrong.
bool read_trailer(const Json& fields, TileMeta& meta, std::string& error) {
    auto missing = [&](const char* what) {
        error = std::string("incomplete WSDTILE metadata: ") + what;
        return false;
    };
    if (!fields.is_object()) return missing("not a JSON object");
    if (!whole_number(field(fields, "width"), 0, 1e9, meta.full_width))
        return missing("no whole-number 'width'");
    if (!whole_number(field(fields, "height"), 0, 1e9, meta.full_height))
        return missing("no whole-number 'height'");
    int r[4];
    if (!whole_numbers(field(fields, "region"), 4, r))
        return missing("'region' is not four whole numbers [x0, y0, x1, y1]");
    meta.region = {r[0], r[1], r[2], r[3]};
    const Json& scene_hash = field(fields, "scene_hash");
    const Json& settings_hash = field(fields, "settings_hash");
    if (!scene_hash.is_string() || !settings_hash.is_string())
        return missing("no 'scene_hash' or 'settings_hash' string");
    meta.scene_hash = scene_hash.get<std::string>();
    meta.settings_hash = settings_hash.get<std::string>();
    meta.defines_hash.clear();
    if (const Json& defines_hash = field(fields, "defines_hash"); !defines_hash.is_null()) {
        if (!defines_hash.is_string()) return missing("'defines_hash' is not a string");
        meta.defines_hash = defines_hash.get<std::string>();
    }
    if (!whole_number(field(fields, "seed"), 0, 4294967295.0, meta.seed))
        return missing("no 'seed' in [0, 4294967295]");
    if (int t[2]; whole_numbers(field(fields, "tile"), 2, t)) {
        meta.tile_index = t[0];
        meta.tile_count = t[1];
    }
    if (const Json& scene = field(fields, "scene"); scene.is_string()) meta.scene = scene.get<std::string>();
    if (const Json& frame = field(fields, "frame");
        !frame.is_null() && !whole_number(frame, 0, 1e15, meta.frame))
        return missing("'frame' is not a whole number");
    if (const Json& clock = field(fields, "clock"); !clock.is_null()) {
        if (!clock.is_number()) return missing("'clock' is not a number");
        meta.clock = clock.get<double>();
    }
    meta.aovs = {};
    if (const Json& aovs = field(fields, "aovs"); !aovs.is_null()) {
        if (!aovs.is_array()) return missing("'aovs' is not a list of names");
        for (const Json& name : aovs)
            if (!name.is_string() || !select_aov(name.get<std::string>(), meta.aovs))
                return missing("'aovs' names an unknown auxiliary image");
    }
    return true;
}

// The auxiliary images after the trailer line, starting at `at`; false + error.
bool read_aovs(std::string_view bytes, size_t at, const TileMeta& meta, render::AovFilm& aovs,
               std::string& error) {
    const int w = meta.region.x1 - meta.region.x0, h = meta.region.y1 - meta.region.y0;
    const size_t pixels = static_cast<size_t>(w) * static_cast<size_t>(h);
    aovs = {};
    for (const std::string& name : meta.aovs.names()) {
        render::Film image;
        const size_t used = at < bytes.size() ? render::decode_pfm(bytes.substr(at), image, error) : 0;
        if (used == 0 || image.width != w || image.height != h) {
            error = "the " + name + " image after the WSDTILE metadata is missing or malformed" +
                    (used == 0 && at < bytes.size() ? " (" + error + ")" : std::string());
            return false;
        }
        at += used;
        if (name == "depth" || name == "samples") {
            std::vector<float>& one = name == "depth" ? aovs.depth : aovs.samples;
            one.resize(pixels);
            for (size_t i = 0; i < pixels; ++i) one[i] = image.rgb[3 * i];
        } else {
            (name == "albedo" ? aovs.albedo : aovs.normal) = std::move(image.rgb);
        }
    }
    // An AovFilm holds all three images or none: those the tile does not carry are zero-filled.
    if (meta.aovs.traced()) {
        if (aovs.albedo.empty()) aovs.albedo.assign(pixels * 3, 0.0f);
        if (aovs.normal.empty()) aovs.normal.assign(pixels * 3, 0.0f);
        if (aovs.depth.empty()) aovs.depth.assign(pixels, 0.0f);
    }
    return true;
}

}  // namespace

std::string encode_tile(const render::Film& film, const render::AovFilm& aovs, const TileMeta& meta) {
    const render::Region& r = meta.region;
    Json json = {{"format", 1},
                 {"width", meta.full_width},
                 {"height", meta.full_height},
                 {"region", {r.x0, r.y0, r.x1, r.y1}},
                 {"tile", {meta.tile_index, meta.tile_count}},
                 {"seed", meta.seed},
                 {"scene_hash", meta.scene_hash},
                 {"settings_hash", meta.settings_hash},
                 {"scene", meta.scene}};
    if (meta.aovs.any()) json["aovs"] = meta.aovs.names();
    // Without --define the bytes stay those of a tile before the hash of defines existed.
    if (!meta.defines_hash.empty()) json["defines_hash"] = meta.defines_hash;
    // A still's tile has neither: its bytes stay those of a tile before animation existed.
    if (meta.frame >= 0) json["frame"] = meta.frame;
    if (meta.frame >= 0 || meta.clock != 0) json["clock"] = meta.clock;
    // A scene path that is not UTF-8 is only for messages: its bad bytes become U+FFFD.
    std::string out = render::encode_pfm(film);
    out += "\n";
    out += trailer_tag;
    out += json.dump(-1, ' ', false, Json::error_handler_t::replace);
    out += "\n";
    if (meta.aovs.albedo) out += render::encode_pfm(film.width, film.height, 3, aovs.albedo.data());
    if (meta.aovs.normal) out += render::encode_pfm(film.width, film.height, 3, aovs.normal.data());
    if (meta.aovs.depth) out += render::encode_pfm(film.width, film.height, 1, aovs.depth.data());
    if (meta.aovs.samples) out += render::encode_pfm(film.width, film.height, 1, aovs.samples.data());
    return out;
}

namespace {

// The deepest nesting of arrays and objects in the JSON text (strings skipped): the metadata is
// two levels deep, and nlohmann-json copies nested values recursively, so a hostile file with
// thousands of levels would overflow the stack.
size_t json_depth(std::string_view text) {
    size_t depth = 0, deepest = 0;
    bool in_string = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

}  // namespace

bool decode_tile(const std::string& bytes, render::Film& film, render::AovFilm& aovs, TileMeta& meta,
                 std::string& error) {
    if (bytes.rfind("PF", 0) != 0) {
        error = "not a colour PFM file (no 'PF' header)";
        return false;
    }
    const size_t end = render::decode_pfm(bytes, film, error);
    if (end == 0) return false;
    const size_t tag = bytes.find(trailer_tag, end);
    if (tag == std::string::npos) {
        error = "no WSDTILE metadata after the PFM data (not a tile written by `wsd render --tile`)";
        return false;
    }
    // The trailer is one line (the JSON is written without newlines); auxiliary images follow it.
    const size_t json_start = tag + std::strlen(trailer_tag);
    const size_t line_end = std::min(bytes.find('\n', json_start), bytes.size());
    if (json_depth(std::string_view(bytes).substr(json_start, line_end - json_start)) > 16) {
        error = "malformed WSDTILE metadata (nested too deep)";
        return false;
    }
    const Json fields = Json::parse(bytes.begin() + std::ptrdiff_t(json_start),
                                    bytes.begin() + std::ptrdiff_t(line_end), nullptr, false);
    if (fields.is_discarded()) {
        error = "malformed WSDTILE metadata (not valid JSON)";
        return false;
    }
    if (!read_trailer(fields, meta, error)) return false;
    const render::Region& g = meta.region;
    if (g.x1 > meta.full_width || g.y1 > meta.full_height || g.x1 - g.x0 != film.width ||
        g.y1 - g.y0 != film.height) {
        error = "WSDTILE region does not match the PFM size or lies outside the image";
        return false;
    }
    return read_aovs(bytes, line_end + 1, meta, aovs, error);
}

}  // namespace wsd::app
