// Encoding and decoding tile files: PFM bytes plus the `WSDTILE` trailer. The trailer's JSON is
// flat (numbers, strings, arrays of numbers), so a small hand parser reads it without a library.
#include "app/tile_file.h"

#include <cctype>
#include <cstring>
#include <map>
#include <sstream>
#include <vector>

#include "app/io_util.h"
#include "render/limits.h"

namespace wsd::app {

namespace {

constexpr const char* trailer_tag = "WSDTILE ";

std::string json_string(const std::string& s) {
    return "\"" + json_escape(s) + "\"";
}

// A value of the trailer: a number, a string, or a list of numbers.
struct JsonValue {
    enum class Kind { Number, String, Array } kind = Kind::Number;
    double number = 0;
    std::string text;
    std::vector<double> array;
};

class TrailerParser {
public:
    explicit TrailerParser(const std::string& s) : s_(s) {}

    bool parse(std::map<std::string, JsonValue>& out) {
        skip();
        if (!eat('{')) return false;
        skip();
        if (eat('}')) return true;
        for (;;) {
            std::string key;
            JsonValue value;
            skip();
            if (!string(key)) return false;
            skip();
            if (!eat(':')) return false;
            skip();
            if (!this->value(value)) return false;
            out[key] = value;
            skip();
            if (eat('}')) break;
            if (!eat(',')) return false;
        }
        skip();
        return pos_ == s_.size();
    }

private:
    void skip() {
        while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    }
    bool eat(char c) {
        if (pos_ < s_.size() && s_[pos_] == c) {
            ++pos_;
            return true;
        }
        return false;
    }
    bool string(std::string& out) {
        if (!eat('"')) return false;
        while (pos_ < s_.size() && s_[pos_] != '"') {
            char c = s_[pos_++];
            if (c == '\\') {
                if (pos_ >= s_.size()) return false;
                c = s_[pos_++];
                if (c == 'u') {
                    if (pos_ + 4 > s_.size()) return false;
                    for (size_t k = 0; k < 4; ++k)
                        if (!std::isxdigit(static_cast<unsigned char>(s_[pos_ + k]))) return false;
                    c = static_cast<char>(std::stoi(s_.substr(pos_, 4), nullptr, 16));
                    pos_ += 4;
                }
            }
            out += c;
        }
        return eat('"');
    }
    bool number(double& out) {
        const char* begin = s_.c_str() + pos_;
        char* end = nullptr;
        out = std::strtod(begin, &end);
        if (end == begin) return false;
        pos_ += static_cast<size_t>(end - begin);
        return true;
    }
    bool value(JsonValue& v) {
        if (pos_ < s_.size() && s_[pos_] == '"') {
            v.kind = JsonValue::Kind::String;
            return string(v.text);
        }
        if (eat('[')) {
            v.kind = JsonValue::Kind::Array;
            skip();
            if (eat(']')) return true;
            for (;;) {
                double d = 0;
                skip();
                if (!number(d)) return false;
                v.array.push_back(d);
                skip();
                if (eat(']')) return true;
                if (!eat(',')) return false;
            }
        }
        v.kind = JsonValue::Kind::Number;
        return number(v.number);
    }

    const std::string& s_;
    size_t pos_ = 0;
};

// Reads one whitespace-delimited token of the PFM header.
bool header_token(const std::string& bytes, size_t& pos, std::string& token) {
    while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
    const size_t begin = pos;
    while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
    token = bytes.substr(begin, pos - begin);
    return !token.empty();
}

bool parse_int(const std::string& token, long long lo, long long hi, int& out) {
    if (token.empty() || token.size() > 12) return false;
    for (const char c : token)
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    const long long v = std::stoll(token);
    if (v < lo || v > hi) return false;
    out = static_cast<int>(v);
    return true;
}

bool integer_field(const std::map<std::string, JsonValue>& fields, const char* key, int& out) {
    const auto it = fields.find(key);
    if (it == fields.end() || it->second.kind != JsonValue::Kind::Number) return false;
    const double v = it->second.number;
    if (v != static_cast<double>(static_cast<long long>(v)) || v < 0 || v > 1e9) return false;
    out = static_cast<int>(v);
    return true;
}

}  // namespace

std::string encode_tile(const render::Film& film, const TileMeta& meta) {
    std::string out = "PF\n" + std::to_string(film.width) + " " + std::to_string(film.height) + "\n-1.0\n";
    const size_t header = out.size();
    const size_t row_floats = static_cast<size_t>(film.width) * 3;
    out.resize(header + row_floats * film.height * sizeof(float));
    // PFM stores the bottom row first; -1.0 in the header means little-endian floats.
    for (int y = 0; y < film.height; ++y) {
        const float* src = film.rgb.data() + static_cast<size_t>(film.height - 1 - y) * row_floats;
        for (size_t i = 0; i < row_floats; ++i) {
            uint32_t bits;
            std::memcpy(&bits, &src[i], sizeof bits);
            char* dst = out.data() + header + (static_cast<size_t>(y) * row_floats + i) * 4;
            for (int b = 0; b < 4; ++b) dst[b] = static_cast<char>((bits >> (8 * b)) & 0xffu);
        }
    }
    std::ostringstream json;
    json << "{\"format\":1,\"width\":" << meta.full_width << ",\"height\":" << meta.full_height
         << ",\"region\":[" << meta.region.x0 << "," << meta.region.y0 << "," << meta.region.x1 << ","
         << meta.region.y1 << "],\"tile\":[" << meta.tile_index << "," << meta.tile_count
         << "],\"seed\":" << meta.seed << ",\"scene_hash\":" << json_string(meta.scene_hash)
         << ",\"settings_hash\":" << json_string(meta.settings_hash)
         << ",\"scene\":" << json_string(meta.scene) << "}";
    out += "\n";
    out += trailer_tag;
    out += json.str();
    out += "\n";
    return out;
}

bool decode_tile(const std::string& bytes, render::Film& film, TileMeta& meta, std::string& error) {
    size_t pos = 0;
    std::string magic, w_token, h_token, scale_token;
    if (!header_token(bytes, pos, magic) || magic != "PF") {
        error = "not a colour PFM file (no 'PF' header)";
        return false;
    }
    int w = 0, h = 0;
    if (!header_token(bytes, pos, w_token) || !parse_int(w_token, 1, render::kMaxImageSide, w) ||
        !header_token(bytes, pos, h_token) || !parse_int(h_token, 1, render::kMaxImageSide, h)) {
        error = "malformed PFM header (bad width or height)";
        return false;
    }
    if (!header_token(bytes, pos, scale_token)) {
        error = "malformed PFM header (no scale)";
        return false;
    }
    const double scale = std::strtod(scale_token.c_str(), nullptr);
    if (!(scale < 0)) {
        error = "big-endian PFM files are not supported as tiles";
        return false;
    }
    ++pos;  // the single whitespace byte after the scale
    const size_t row_floats = static_cast<size_t>(w) * 3;
    const size_t data_bytes = row_floats * static_cast<size_t>(h) * 4;
    if (pos > bytes.size() || bytes.size() - pos < data_bytes) {
        error = "truncated PFM data";
        return false;
    }
    film.width = w;
    film.height = h;
    film.rgb.assign(row_floats * static_cast<size_t>(h), 0.0f);
    for (int y = 0; y < h; ++y) {
        float* dst = film.rgb.data() + static_cast<size_t>(h - 1 - y) * row_floats;
        for (size_t i = 0; i < row_floats; ++i) {
            const char* src = bytes.data() + pos + (static_cast<size_t>(y) * row_floats + i) * 4;
            uint32_t bits = 0;
            for (int b = 0; b < 4; ++b)
                bits |= static_cast<uint32_t>(static_cast<unsigned char>(src[b])) << (8 * b);
            std::memcpy(&dst[i], &bits, sizeof bits);
        }
    }
    std::string rest = bytes.substr(pos + data_bytes);
    const size_t tag = rest.find(trailer_tag);
    if (tag == std::string::npos) {
        error = "no WSDTILE metadata after the PFM data (not a tile written by `wsd render --tile`)";
        return false;
    }
    std::string json = rest.substr(tag + std::strlen(trailer_tag));
    while (!json.empty() && (json.back() == '\n' || json.back() == '\r')) json.pop_back();
    std::map<std::string, JsonValue> fields;
    if (!TrailerParser(json).parse(fields)) {
        error = "malformed WSDTILE metadata";
        return false;
    }
    const auto region = fields.find("region");
    const auto tile = fields.find("tile");
    const auto scene_hash = fields.find("scene_hash");
    const auto settings_hash = fields.find("settings_hash");
    const auto seed = fields.find("seed");
    if (!integer_field(fields, "width", meta.full_width) ||
        !integer_field(fields, "height", meta.full_height) || region == fields.end() ||
        region->second.array.size() != 4 || scene_hash == fields.end() || settings_hash == fields.end() ||
        seed == fields.end() || seed->second.kind != JsonValue::Kind::Number || seed->second.number < 0 ||
        seed->second.number > 4294967295.0) {
        error = "incomplete WSDTILE metadata";
        return false;
    }
    const auto& r = region->second.array;
    for (const double v : r)
        if (!(v >= 0 && v <= 1e9) || v != static_cast<double>(static_cast<long long>(v))) {
            error = "malformed WSDTILE region";
            return false;
        }
    meta.region = {static_cast<int>(r[0]), static_cast<int>(r[1]), static_cast<int>(r[2]),
                   static_cast<int>(r[3])};
    meta.scene_hash = scene_hash->second.text;
    meta.settings_hash = settings_hash->second.text;
    meta.seed = static_cast<uint32_t>(seed->second.number);
    if (tile != fields.end() && tile->second.array.size() == 2 && tile->second.array[0] >= 0 &&
        tile->second.array[0] <= 1e9 && tile->second.array[1] >= 0 && tile->second.array[1] <= 1e9) {
        meta.tile_index = static_cast<int>(tile->second.array[0]);
        meta.tile_count = static_cast<int>(tile->second.array[1]);
    }
    if (const auto scene = fields.find("scene"); scene != fields.end()) meta.scene = scene->second.text;
    const render::Region& g = meta.region;
    if (g.x0 < 0 || g.y0 < 0 || g.x1 > meta.full_width || g.y1 > meta.full_height || g.x1 - g.x0 != w ||
        g.y1 - g.y0 != h) {
        error = "WSDTILE region does not match the PFM size or lies outside the image";
        return false;
    }
    return true;
}

}  // namespace wsd::app
