// Wavefront OBJ reader, written here rather than taken from Debian's tinyobjloader: that would be
// a new dependency, and we need per-line "FILE:LINE: message" errors for every malformed input
// (robustness.md R62) and a 1,000,000-triangle file read in well under a second. So the file is
// read whole, lines are scanned in place and numbers go through std::from_chars.
#include "render/obj.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <set>

#include "render/file_util.h"

namespace wsd::render {

namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;
// Corners of faces without vt, in a mesh that has uvs, get the uv of their role in the triangle:
// (0,0), (1,0), (0,1) — what a mesh without uvs shows. These vt keys stand for those roles.
constexpr uint32_t kBaryRole = 0xFFFFFFF0u;
constexpr size_t kMaxNotes = 16;
constexpr size_t kMaxElements = 0xFFFFFF00u;  // keeps every index below the marker values

struct Corner {
    uint32_t v, vt, vn;  // 0-based once resolved; kNone when absent
};

struct Face {
    uint32_t first;  // into corners
    uint32_t count;
    uint32_t line;
};

// A printable, bounded rendering of a token from an untrusted file, for messages.
std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) {
        const auto u = static_cast<unsigned char>(c);
        out += (u >= 0x20 && u < 0x7f) ? c : '?';
    }
    if (s.size() > 40) out += "...";
    return out;
}

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\f' || c == '\v';
}

// Splits off the next whitespace-separated token of `rest`; false at the end of the line or at a
// '#', which starts a comment (also right after a token: "1#x" is the token "1").
bool next_token(std::string_view& rest, std::string_view& token) {
    size_t i = 0;
    while (i < rest.size() && is_space(rest[i])) ++i;
    if (i == rest.size() || rest[i] == '#') {
        rest = {};
        return false;
    }
    size_t j = i;
    while (j < rest.size() && !is_space(rest[j]) && rest[j] != '#') ++j;
    token = rest.substr(i, j - i);
    rest = rest.substr(j);
    return true;
}

enum class NumberStatus { Ok, Bad, NotFinite };

// For a well-formed decimal that from_chars found out of range: true if it is too large, false
// if too small (the decimal exponent of its leading digit is positive or negative, respectively).
bool decimal_overflows(std::string_view t) {
    size_t i = (!t.empty() && (t[0] == '-' || t[0] == '+')) ? 1 : 0;
    long long lead = 0;  // decimal exponent of the first significant digit, before the 'e' part
    bool seen = false;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') {
        if (seen) ++lead;
        seen = seen || t[i] != '0';
        ++i;
    }
    if (i < t.size() && t[i] == '.') {
        ++i;
        for (long long place = -1; i < t.size() && t[i] >= '0' && t[i] <= '9'; ++i, --place) {
            if (!seen && t[i] != '0') {
                seen = true;
                lead = place;
            }
        }
    }
    long long exponent = 0;
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        const bool negative = i < t.size() && t[i] == '-';
        if (i < t.size() && (t[i] == '-' || t[i] == '+')) ++i;
        for (; i < t.size() && t[i] >= '0' && t[i] <= '9'; ++i)
            exponent = std::min(exponent * 10 + (t[i] - '0'), 1000000LL);
        if (negative) exponent = -exponent;
    }
    return lead + exponent > 0;
}

// A decimal number with optional leading '+'; out-of-range magnitudes become ±Inf (and are then
// refused by the caller), underflow becomes 0, as the language's own literals do.
NumberStatus parse_double(std::string_view t, double& out) {
    if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
    const char* end = t.data() + t.size();
    auto [ptr, ec] = std::from_chars(t.data(), end, out);
    if (ptr != end || t.empty()) return NumberStatus::Bad;
    if (ec == std::errc::result_out_of_range) {
        // from_chars leaves `out` unset here.
        if (decimal_overflows(t)) return NumberStatus::NotFinite;
        out = 0.0;
    } else if (ec != std::errc()) {
        return NumberStatus::Bad;
    }
    return std::isfinite(out) ? NumberStatus::Ok : NumberStatus::NotFinite;
}

class ObjParser {
public:
    explicit ObjParser(const std::string& name) : name_(name) {}

    MeshFileResult run(std::string_view text);

private:
    bool fail(const std::string& message) {
        error_ = name_ + ":" + std::to_string(line_) + ": " + message;
        return false;
    }
    void note_ignored(std::string_view keyword, bool known);
    void summarise_ignored();
    bool degenerate(const Corner& a, const Corner& b, const Corner& c) const;
    void skip_degenerate(uint32_t line) const;
    bool statement(std::string_view line);
    bool read_numbers(std::string_view keyword, std::string_view rest, double* out, size_t min, size_t max,
                      size_t& count);
    bool vertex(std::string_view rest);
    bool texcoord(std::string_view rest);
    bool normal(std::string_view rest);
    bool face(std::string_view rest);
    bool corner_index(std::string_view token, std::string_view part, size_t defined, uint32_t& out);
    bool check_indices();
    void reserve_for(std::string_view text);
    std::shared_ptr<MeshData> build() const;

    const std::string& name_;
    uint32_t line_ = 0;
    std::string error_;
    std::vector<std::string> notes_;
    // Statements skipped, by kind in order of first appearance: one note sums them up.
    struct Ignored {
        std::string keyword;
        bool known;
        uint32_t first_line;
        size_t count;
    };
    std::vector<Ignored> ignored_;
    size_t ignored_total_ = 0;
    // Zero-area triangles left out of the mesh (build() is const; these are its only output).
    mutable size_t degenerate_ = 0;
    mutable uint32_t first_degenerate_line_ = 0;
    std::vector<glm::vec3> positions_;
    std::vector<glm::vec2> texcoords_;
    std::vector<glm::vec3> normals_;
    std::vector<Corner> corners_;
    std::vector<Face> faces_;
    size_t triangles_ = 0;
    bool any_vt_ = false, any_vn_ = false;
};

void ObjParser::note_ignored(std::string_view keyword, bool known) {
    ++ignored_total_;
    for (Ignored& i : ignored_)
        if (i.keyword == keyword) {
            ++i.count;
            return;
        }
    if (ignored_.size() < kMaxNotes) ignored_.push_back({std::string(keyword), known, line_, 1});
}

// "FILE:LINE: ignored 12 statements that wsd does not use: 'o' (line 1), 'usemtl' (9, from
// line 5), 'foo' (unknown OBJ statement, line 7)", LINE being the first of them.
void ObjParser::summarise_ignored() {
    if (ignored_.empty()) return;
    std::string note = name_ + ":" + std::to_string(ignored_.front().first_line) + ": ignored " +
                       std::to_string(ignored_total_) + (ignored_total_ == 1 ? " statement" : " statements") +
                       " that wsd does not use: ";
    size_t listed = 0;
    for (const Ignored& i : ignored_) {
        note += (listed++ ? ", '" : "'") + printable(i.keyword) + "' (";
        if (!i.known) note += "unknown OBJ statement, ";
        if (i.count > 1) note += std::to_string(i.count) + ", from ";
        note += "line " + std::to_string(i.first_line) + ")";
    }
    size_t shown = 0;
    for (const Ignored& i : ignored_) shown += i.count;
    if (shown < ignored_total_) note += ", and " + std::to_string(ignored_total_ - shown) + " of other kinds";
    notes_.push_back(std::move(note));
}

bool ObjParser::read_numbers(std::string_view keyword, std::string_view rest, double* out, size_t min,
                             size_t max, size_t& count) {
    std::string_view token;
    count = 0;
    while (next_token(rest, token)) {
        if (count == max)
            return fail("too many numbers in '" + std::string(keyword) + "' (at most " + std::to_string(max) +
                        ")");
        switch (parse_double(token, out[count])) {
            case NumberStatus::Ok:
                break;
            case NumberStatus::Bad:
                return fail("bad number '" + printable(token) + "'");
            case NumberStatus::NotFinite:
                return fail("number '" + printable(token) + "' is not finite (NaN, infinite or too large)");
        }
        ++count;
    }
    if (count < min)
        return fail("'" + std::string(keyword) + "' needs " + (min == max ? "" : "at least ") +
                    std::to_string(min) + (min == 1 ? " number" : " numbers") + ", found " +
                    std::to_string(count));
    return true;
}

// Coordinates are stored as float (MeshData), so a double beyond float range is refused too.
bool fits_float(const double* x, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (std::fabs(x[i]) > static_cast<double>(std::numeric_limits<float>::max())) return false;
    return true;
}

bool ObjParser::vertex(std::string_view rest) {
    // x y z, then an optional w or a vertex colour r g b (some exporters write them); ignored.
    double x[7];
    size_t n = 0;
    if (!read_numbers("v", rest, x, 3, 7, n)) return false;
    if (!fits_float(x, 3)) return fail("vertex coordinate out of range (beyond single precision)");
    if (positions_.size() >= kMaxElements) return fail("too many vertices");
    positions_.emplace_back(static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2]));
    return true;
}

bool ObjParser::texcoord(std::string_view rest) {
    double x[3] = {0, 0, 0};
    size_t n = 0;
    if (!read_numbers("vt", rest, x, 1, 3, n)) return false;
    if (!fits_float(x, 2)) return fail("texture coordinate out of range (beyond single precision)");
    if (texcoords_.size() >= kMaxElements) return fail("too many texture coordinates");
    texcoords_.emplace_back(static_cast<float>(x[0]), static_cast<float>(x[1]));
    return true;
}

bool ObjParser::normal(std::string_view rest) {
    double x[3];
    size_t n = 0;
    if (!read_numbers("vn", rest, x, 3, 3, n)) return false;
    if (!fits_float(x, 3)) return fail("normal component out of range (beyond single precision)");
    if (normals_.size() >= kMaxElements) return fail("too many normals");
    normals_.emplace_back(static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2]));
    return true;
}

// One index of a face corner: 1-based, or negative counting back from the last element defined
// so far (-1 is the last). Positive indices are checked against the final counts afterwards.
bool ObjParser::corner_index(std::string_view token, std::string_view part, size_t defined, uint32_t& out) {
    // Hand-rolled: this runs three times per triangle corner. Magnitudes stop growing past
    // kMaxElements, so nothing overflows however many digits there are.
    const bool negative = !part.empty() && part[0] == '-';
    const size_t digits_from = negative ? 1 : 0;
    if (part.size() == digits_from)
        return fail("bad face vertex '" + printable(token) + "' (expected v, v/vt, v/vt/vn or v//vn)");
    long long k = 0;
    for (size_t i = digits_from; i < part.size(); ++i) {
        const unsigned d = static_cast<unsigned char>(part[i]) - unsigned{'0'};
        if (d > 9)
            return fail("bad face vertex '" + printable(token) + "' (expected v, v/vt, v/vt/vn or v//vn)");
        if (k <= static_cast<long long>(kMaxElements)) k = k * 10 + d;
    }
    if (k > static_cast<long long>(kMaxElements)) return fail("index " + printable(part) + " out of range");
    if (negative) k = -k;
    if (k == 0) return fail("index 0 in face vertex '" + printable(token) + "' (OBJ indices start at 1)");
    if (k < 0) {
        if (-k > static_cast<long long>(defined))
            return fail("relative index " + std::to_string(k) + " in face vertex '" + printable(token) +
                        "' reaches before the first element (" + std::to_string(defined) +
                        " defined so far)");
        out = static_cast<uint32_t>(static_cast<long long>(defined) + k);
    } else {
        out = static_cast<uint32_t>(k - 1);
    }
    return true;
}

bool ObjParser::face(std::string_view rest) {
    const auto first = static_cast<uint32_t>(corners_.size());
    std::string_view token;
    int has_vt = -1, has_vn = -1;  // unknown until the first corner
    while (next_token(rest, token)) {
        // v, v/vt, v/vt/vn or v//vn, split in one pass.
        std::string_view part[3];
        size_t parts = 0, start = 0;
        for (size_t i = 0; i <= token.size() && parts < 3; ++i) {
            if (i == token.size() || token[i] == '/') {
                part[parts++] = token.substr(start, i - start);
                start = i + 1;
            }
        }
        const bool bad_shape = start <= token.size() ||  // a fourth part
                               (parts == 2 && part[1].empty()) || (parts == 3 && part[2].empty());
        if (bad_shape)
            return fail("bad face vertex '" + printable(token) + "' (expected v, v/vt, v/vt/vn or v//vn)");
        Corner c{kNone, kNone, kNone};
        if (!corner_index(token, part[0], positions_.size(), c.v)) return false;
        if (parts >= 2 && !part[1].empty() && !corner_index(token, part[1], texcoords_.size(), c.vt))
            return false;
        if (parts == 3 && !corner_index(token, part[2], normals_.size(), c.vn)) return false;
        const int cvt = c.vt != kNone, cvn = c.vn != kNone;
        if (has_vt < 0) {
            has_vt = cvt;
            has_vn = cvn;
        } else if (has_vt != cvt) {
            return fail("face mixes vertices with and without texture coordinates");
        } else if (has_vn != cvn) {
            return fail("face mixes vertices with and without normals");
        }
        corners_.push_back(c);
    }
    const auto count = static_cast<uint32_t>(corners_.size() - first);
    if (count < 3)
        return fail("face has " + std::to_string(count) + (count == 1 ? " vertex" : " vertices") +
                    "; a face needs at least 3");
    triangles_ += count - 2;
    if (triangles_ > kMaxObjTriangles)
        return fail("too many triangles (a mesh may have at most " + std::to_string(kMaxObjTriangles) + ")");
    any_vt_ = any_vt_ || has_vt == 1;
    any_vn_ = any_vn_ || has_vn == 1;
    faces_.push_back({first, count, line_});
    return true;
}

bool ObjParser::statement(std::string_view line) {
    std::string_view keyword;
    if (!next_token(line, keyword)) return true;
    if (keyword == "v") return vertex(line);
    if (keyword == "f") return face(line);
    if (keyword == "vt") return texcoord(line);
    if (keyword == "vn") return normal(line);
    static constexpr std::string_view kKnown[] = {
        "usemtl",     "mtllib",    "o",     "g",     "s",      "l",     "p",        "vp",       "cstype",
        "deg",        "bmat",      "step",  "curv",  "curv2",  "surf",  "parm",     "trim",     "hole",
        "scrv",       "sp",        "end",   "con",   "mg",     "bevel", "c_interp", "d_interp", "lod",
        "shadow_obj", "trace_obj", "ctech", "stech", "maplib", "usemap"};
    bool known = false;
    for (std::string_view k : kKnown) known = known || k == keyword;
    note_ignored(keyword, known);
    return true;
}

bool ObjParser::check_indices() {
    for (const Face& f : faces_) {
        for (uint32_t i = f.first; i < f.first + f.count; ++i) {
            const Corner& c = corners_[i];
            const char* what = nullptr;
            size_t index = 0, count = 0;
            if (c.v >= positions_.size()) {
                what = "vertex", index = c.v, count = positions_.size();
            } else if (c.vt != kNone && c.vt >= texcoords_.size()) {
                what = "texture coordinate", index = c.vt, count = texcoords_.size();
            } else if (c.vn != kNone && c.vn >= normals_.size()) {
                what = "normal", index = c.vn, count = normals_.size();
            }
            if (what) {
                line_ = f.line;
                return fail(std::string(what) + " index " + std::to_string(index + 1) +
                            " out of range (the file defines " + std::to_string(count) + ")");
            }
        }
    }
    return true;
}

// Open-addressing map from a corner's (v, vt, vn) to its output vertex.
class CornerMap {
public:
    explicit CornerMap(size_t expected) {
        size_t cap = 64;
        while (cap < expected * 2) cap *= 2;
        slots_.assign(cap, Slot{{kNone, kNone, kNone}, 0});
    }
    // The vertex for `key`, or kNone after inserting it with value `fresh`.
    uint32_t find_or_insert(const Corner& key, uint32_t fresh) {
        if ((size_ + 1) * 2 > slots_.size()) grow();
        size_t i = hash(key) & (slots_.size() - 1);
        for (;; i = (i + 1) & (slots_.size() - 1)) {
            Slot& s = slots_[i];
            if (s.key.v == kNone) {
                s = {key, fresh};
                ++size_;
                return kNone;
            }
            if (s.key.v == key.v && s.key.vt == key.vt && s.key.vn == key.vn) return s.value;
        }
    }

private:
    struct Slot {
        Corner key;
        uint32_t value;
    };
    static size_t hash(const Corner& k) {
        uint64_t h = k.v * 0x9E3779B97F4A7C15ull ^ (uint64_t{k.vt} * 0xC2B2AE3D27D4EB4Full) ^
                     (uint64_t{k.vn} * 0x165667B19E3779F9ull);
        h ^= h >> 32;
        return static_cast<size_t>(h);
    }
    void grow() {
        std::vector<Slot> old(slots_.size() * 2, Slot{{kNone, kNone, kNone}, 0});
        old.swap(slots_);
        size_ = 0;
        for (const Slot& s : old)
            if (s.key.v != kNone) find_or_insert(s.key, s.value);
    }
    std::vector<Slot> slots_;
    size_t size_ = 0;
};

glm::vec3 flat_normal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::dvec3 n = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
    const double len = glm::length(n);
    // A zero-area triangle has no normal; geometry reports it by its line, so any unit vector does.
    if (!(len > 0.0) || !std::isfinite(len)) return {0.0f, 0.0f, 1.0f};
    return glm::vec3(n / len);
}

// Zero area by the scene builder's own test (|e1 × e2| ≤ 1e-12·|e1||e2|), here in the file's
// coordinates: a pole quad of a UV sphere that repeats a vertex fans into one such triangle.
bool ObjParser::degenerate(const Corner& a, const Corner& b, const Corner& c) const {
    const glm::dvec3 v0(positions_[a.v]), v1(positions_[b.v]), v2(positions_[c.v]);
    const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0;
    const double cr = glm::length(glm::cross(e1, e2));
    return !(cr > 1e-12 * glm::length(e1) * glm::length(e2));
}

void ObjParser::skip_degenerate(uint32_t line) const {
    if (degenerate_++ == 0) first_degenerate_line_ = line;
}

std::shared_ptr<MeshData> ObjParser::build() const {
    auto mesh = std::make_shared<MeshData>();
    mesh->source_name = name_;
    mesh->faces.reserve(triangles_);
    mesh->face_lines.reserve(triangles_);
    if (!any_vt_ && !any_vn_) {
        // Positions are the vertices: no unwelding needed.
        mesh->vertices = positions_;
        for (const Face& f : faces_) {
            for (uint32_t k = 1; k + 1 < f.count; ++k) {
                const Corner &a = corners_[f.first], &b = corners_[f.first + k],
                             &c = corners_[f.first + k + 1];
                if (degenerate(a, b, c)) {
                    skip_degenerate(f.line);
                    continue;
                }
                mesh->faces.emplace_back(a.v, b.v, c.v);
                mesh->face_lines.push_back(f.line);
            }
        }
        return mesh;
    }
    static const glm::vec2 kRoleUv[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}};
    // Most positions are used with one (vt, vn) only: first[v] is the vertex made for v's first
    // pair, checked before the hash map, which then holds just the positions used with several.
    std::vector<uint32_t> first(positions_.size(), kNone);
    std::vector<uint64_t> pair_of;  // (vt, vn) of each output vertex
    CornerMap others(0);
    const auto pair_key = [](const Corner& c) { return uint64_t{c.vt} << 32 | c.vn; };
    const auto add_vertex = [&](const Corner& c, const glm::vec3& flat) {
        mesh->vertices.push_back(positions_[c.v]);
        if (any_vt_) mesh->uvs.push_back(c.vt >= kBaryRole ? kRoleUv[c.vt - kBaryRole] : texcoords_[c.vt]);
        if (any_vn_) mesh->normals.push_back(c.vn == kNone ? flat : normals_[c.vn]);
        pair_of.push_back(pair_key(c));
        return static_cast<uint32_t>(mesh->vertices.size() - 1);
    };
    const auto shared_vertex = [&](const Corner& c) {
        uint32_t& f = first[c.v];
        if (f == kNone) return f = add_vertex(c, glm::vec3(0.0f));
        if (pair_of[f] == pair_key(c)) return f;
        const uint32_t found = others.find_or_insert(c, static_cast<uint32_t>(mesh->vertices.size()));
        return found != kNone ? found : add_vertex(c, glm::vec3(0.0f));
    };
    for (const Face& f : faces_) {
        for (uint32_t k = 1; k + 1 < f.count; ++k) {
            Corner tri[3] = {corners_[f.first], corners_[f.first + k], corners_[f.first + k + 1]};
            if (degenerate(tri[0], tri[1], tri[2])) {
                skip_degenerate(f.line);
                continue;
            }
            uint32_t out[3];
            const bool flat = any_vn_ && tri[0].vn == kNone;
            const glm::vec3 fn =
                flat ? flat_normal(positions_[tri[0].v], positions_[tri[1].v], positions_[tri[2].v])
                     : glm::vec3(0.0f);
            for (uint32_t r = 0; r < 3; ++r) {
                if (any_vt_ && tri[r].vt == kNone) tri[r].vt = kBaryRole + r;
                // A flat corner is never shared: its normal belongs to this triangle alone.
                out[r] = flat ? add_vertex(tri[r], fn) : shared_vertex(tri[r]);
            }
            mesh->faces.emplace_back(out[0], out[1], out[2]);
            mesh->face_lines.push_back(f.line);
        }
    }
    return mesh;
}

// Takes the line at p (without its terminator) and moves p past "\r\n", "\n" or a lone "\r".
// False, with p left at it, when the line holds a NUL byte. `plain` says the text has neither
// '\r' nor NUL, so memchr can find the line end.
bool take_line(const char*& p, const char* end, std::string_view& line, bool plain) {
    const char* e = p;
    if (plain) {
        e = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
        if (!e) e = end;
    } else {
        while (e < end && *e != '\n' && *e != '\r' && *e != '\0') ++e;
    }
    line = std::string_view(p, static_cast<size_t>(e - p));
    p = e;
    if (p == end) return true;
    if (*p == '\0') return false;
    if (*p++ == '\r' && p < end && *p == '\n') ++p;
    return true;
}

// A statement continues on the next line when its last non-blank character is a backslash
// outside a comment ("# C:\\models\\" must not swallow the next line).
bool continues(std::string_view s) {
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return !s.empty() && s.back() == '\\' && s.find('#') == std::string_view::npos;
}

std::string_view without_backslash(std::string_view s) {
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s.substr(0, s.size() - 1);
}

// Counts the statements of each kind (by their first letters, before any validation) so that the
// parser's arrays are allocated once: growing them by doubling copied about as many bytes again
// as the file holds.
void ObjParser::reserve_for(std::string_view text) {
    size_t v = 0, vt = 0, vn = 0, f = 0;
    const char* p = text.data();
    const char* const end = p + text.size();
    while (p < end) {
        while (p < end && (*p == ' ' || *p == '\t')) ++p;
        if (end - p >= 2) {
            if (p[0] == 'v' && p[1] == ' ')
                ++v;
            else if (p[0] == 'v' && p[1] == 't')
                ++vt;
            else if (p[0] == 'v' && p[1] == 'n')
                ++vn;
            else if (p[0] == 'f' && p[1] == ' ')
                ++f;
        }
        const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p));
        p = nl ? static_cast<const char*>(nl) + 1 : end;
    }
    positions_.reserve(v);
    texcoords_.reserve(vt);
    normals_.reserve(vn);
    faces_.reserve(f);
    corners_.reserve(3 * f);  // triangles; polygons grow it once or twice
}

MeshFileResult ObjParser::run(std::string_view text) {
    MeshFileResult result;
    reserve_for(text);
    const char* p = text.data();
    const char* const end = p + text.size();
    if (text.substr(0, 3) == "\xEF\xBB\xBF") p += 3;  // a UTF-8 byte-order mark
    const bool plain = text.find('\r') == std::string_view::npos && text.find('\0') == std::string_view::npos;
    std::string joined;  // only for statements continued over several lines
    bool ok = true;
    const auto nul = [&] { return fail("NUL byte: this is not a text OBJ file"); };
    while (ok && p < end) {
        ++line_;
        std::string_view line;
        if (!take_line(p, end, line, plain)) {
            ok = nul();
            break;
        }
        if (!continues(line)) {
            ok = statement(line);
            continue;
        }
        // Errors in a continued statement name its first line.
        const uint32_t first_line = line_;
        joined.clear();
        while (ok && continues(line) && p < end) {
            joined.append(without_backslash(line)).push_back(' ');
            ++line_;
            if (!take_line(p, end, line, plain)) ok = nul();
        }
        if (!ok) break;
        joined.append(continues(line) ? without_backslash(line) : line);
        const uint32_t last_line = line_;
        line_ = first_line;
        ok = statement(joined);
        line_ = last_line;
    }
    if (ok && faces_.empty()) {
        line_ = std::max<uint32_t>(line_, 1);
        ok = fail("no faces: an OBJ mesh needs at least one 'f' statement");
    }
    if (ok) ok = check_indices();
    summarise_ignored();
    std::shared_ptr<MeshData> mesh;
    if (ok) mesh = build();
    if (mesh && degenerate_ > 0) {
        line_ = first_degenerate_line_;
        if (mesh->faces.empty()) {
            ok = fail("every face is degenerate (zero area): the mesh has no triangle to draw");
        } else {
            notes_.push_back(name_ + ":" + std::to_string(first_degenerate_line_) + ": skipped " +
                             std::to_string(degenerate_) +
                             (degenerate_ == 1 ? " degenerate triangle" : " degenerate triangles") +
                             " (zero area), the first from this line's face");
        }
    }
    result.notes = std::move(notes_);
    if (!ok) {
        result.error = std::move(error_);
        return result;
    }
    result.mesh = std::move(mesh);
    return result;
}

}  // namespace

MeshFileResult parse_obj(const std::string& name, std::string_view text) {
    try {
        ObjParser parser(name);
        return parser.run(text);
    } catch (const std::bad_alloc&) {
        MeshFileResult result;
        result.error = name + ": out of memory while reading the mesh";
        return result;
    }
}

MeshFileResult load_obj(const std::string& path) {
    FileBytes file;
    std::string reason;
    if (!read_whole_file(path, file, reason)) {
        MeshFileResult result;
        result.error = "cannot read mesh file '" + path + "': " + reason;
        return result;
    }
    return parse_obj(path, file.view());
}

}  // namespace wsd::render
