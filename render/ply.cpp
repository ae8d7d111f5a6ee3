// PLY reader. The header is read line by line; the body is read by one template over its source
// (ASCII tokens through std::from_chars, or binary values of either byte order), element by
// element in the header's order. Every malformed input is an error naming where it is; element
// counts are checked against the bytes that follow before anything is reserved, so a header that
// claims 10^12 vertices costs nothing.
#include "render/ply.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <new>

#include "render/limits.h"

namespace wsd::render {

namespace {

enum class Scalar : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };

bool scalar_named(std::string_view n, Scalar& out) {
    static constexpr std::pair<std::string_view, Scalar> kNames[] = {
        {"char", Scalar::I8},   {"int8", Scalar::I8},     {"uchar", Scalar::U8},   {"uint8", Scalar::U8},
        {"short", Scalar::I16}, {"int16", Scalar::I16},   {"ushort", Scalar::U16}, {"uint16", Scalar::U16},
        {"int", Scalar::I32},   {"int32", Scalar::I32},   {"uint", Scalar::U32},   {"uint32", Scalar::U32},
        {"float", Scalar::F32}, {"float32", Scalar::F32}, {"double", Scalar::F64}, {"float64", Scalar::F64}};
    for (const auto& [name, s] : kNames)
        if (n == name) {
            out = s;
            return true;
        }
    return false;
}

size_t scalar_size(Scalar s) {
    switch (s) {
        case Scalar::I8:
        case Scalar::U8:
            return 1;
        case Scalar::I16:
        case Scalar::U16:
            return 2;
        case Scalar::I32:
        case Scalar::U32:
        case Scalar::F32:
            return 4;
        case Scalar::F64:
            return 8;
    }
    return 8;
}

bool is_integer(Scalar s) {
    return s != Scalar::F32 && s != Scalar::F64;
}

// What a property means to the mesh.
enum class Role : uint8_t { None, X, Y, Z, NX, NY, NZ, U, V, Indices };
constexpr size_t kRoles = 10;

struct Property {
    std::string name;
    bool list = false;
    Scalar count_type = Scalar::U8;  // lists only
    Scalar type = Scalar::F32;
    Role role = Role::None;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
    uint32_t line = 0;  // its header line
    // The fewest body bytes one instance can take (binary: its fixed-size values and list counts;
    // ASCII: one character and one separator per value).
    size_t min_bytes() const;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

constexpr uint64_t kMaxElements = 0xFFFFFF00u;  // counts and indices stay within uint32

std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u < 0x7f) {
            out.push_back(c);
        } else {
            static const char hex[] = "0123456789abcdef";
            out += "\\x";
            out.push_back(hex[u >> 4]);
            out.push_back(hex[u & 15]);
        }
    }
    if (s.size() > 40) out += "...";
    return out;
}

// A PLY error: the message, already prefixed with where it is.
struct PlyError {
    std::string message;
};

// ASCII body: whitespace-separated tokens; lines are counted for messages.
class AsciiSource {
public:
    AsciiSource(std::string_view body, uint32_t first_line)
        : p_(body.data()), end_(p_ + body.size()), line_(first_line) {}

    // Reads one value of type `t` (an integer type accepts only integers).
    bool value(Scalar t, double& out, std::string_view& token) {
        if (!next(token)) return false;
        const char* b = token.data();
        const char* end = token.data() + token.size();
        if (*b == '+') {
            ++b;  // from_chars takes no plus sign (integers and floats alike), and "+-1" is no number
            if (b != end && *b == '-') return bad_ = true, false;
        }
        if (is_integer(t)) {
            int64_t i = 0;
            auto [ptr, ec] = std::from_chars(b, end, i);
            if (ec != std::errc() || ptr != end) return bad_ = true, false;
            out = static_cast<double>(i);
            return in_range(t, i) || (bad_ = true, false);
        }
        auto [ptr, ec] = std::from_chars(b, end, out);
        if (ec != std::errc() || ptr != end) return bad_ = true, false;
        return true;
    }
    bool at_end() {
        skip_space();
        return p_ == end_;
    }
    bool bad() const { return bad_; }  // false: the body ended; true: a token was malformed
    uint32_t line() const { return line_; }
    uint32_t next_line() {  // the line of the next token
        skip_space();
        return line_;
    }

private:
    static bool in_range(Scalar t, int64_t i) {
        switch (t) {
            case Scalar::I8:
                return i >= -128 && i <= 127;
            case Scalar::U8:
                return i >= 0 && i <= 255;
            case Scalar::I16:
                return i >= -32768 && i <= 32767;
            case Scalar::U16:
                return i >= 0 && i <= 65535;
            case Scalar::I32:
                return i >= INT32_MIN && i <= INT32_MAX;
            case Scalar::U32:
                return i >= 0 && i <= int64_t(UINT32_MAX);
            default:
                return true;
        }
    }
    void skip_space() {
        while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\n' || *p_ == '\r')) {
            if (*p_ == '\n') ++line_;
            ++p_;
        }
    }
    bool next(std::string_view& token) {
        skip_space();
        const char* b = p_;
        while (p_ < end_ && *p_ != ' ' && *p_ != '\t' && *p_ != '\n' && *p_ != '\r') ++p_;
        token = {b, size_t(p_ - b)};
        return p_ > b;
    }
    const char* p_;
    const char* end_;
    uint32_t line_;
    bool bad_ = false;
};

// Binary body: fixed-size values in the file's byte order.
class BinarySource {
public:
    BinarySource(std::string_view body, bool big)
        : p_(body.data()), end_(p_ + body.size()), swap_(big != (std::endian::native == std::endian::big)) {}

    bool value(Scalar t, double& out, std::string_view&) {
        const size_t n = scalar_size(t);
        if (size_t(end_ - p_) < n) return false;
        unsigned char b[8];
        std::memcpy(b, p_, n);
        p_ += n;
        if (swap_) std::reverse(b, b + n);
        switch (t) {
            case Scalar::I8:
                out = static_cast<int8_t>(b[0]);
                break;
            case Scalar::U8:
                out = b[0];
                break;
            case Scalar::I16:
                out = load<int16_t>(b);
                break;
            case Scalar::U16:
                out = load<uint16_t>(b);
                break;
            case Scalar::I32:
                out = load<int32_t>(b);
                break;
            case Scalar::U32:
                out = load<uint32_t>(b);
                break;
            case Scalar::F32:
                out = load<float>(b);
                break;
            case Scalar::F64:
                out = load<double>(b);
                break;
        }
        return true;
    }
    bool at_end() const { return p_ == end_; }
    bool bad() const { return false; }
    size_t remaining() const { return size_t(end_ - p_); }

private:
    template <class T>
    static T load(const unsigned char* b) {
        T v;
        std::memcpy(&v, b, sizeof v);
        return v;
    }
    const char* p_;
    const char* end_;
    bool swap_;
};

size_t Element::min_bytes() const {
    size_t n = 0;
    for (const Property& p : properties) n += p.list ? scalar_size(p.count_type) : scalar_size(p.type);
    return std::max<size_t>(n, 1);
}

class PlyParser {
public:
    PlyParser(const std::string& name, std::string_view bytes) : name_(name), bytes_(bytes) {}
    MeshFileResult run();

private:
    void header();
    void header_line(std::string_view line, uint32_t number);
    void assign_roles();
    template <class Source>
    void body(Source& src);
    template <class Source>
    void element(Source& src, const Element& e, bool vertices, bool faces);
    [[noreturn]] void fail_line(uint32_t line, const std::string& message) const {
        throw PlyError{name_ + ":" + std::to_string(line) + ": " + message};
    }
    [[noreturn]] void fail(const std::string& message) const { throw PlyError{name_ + ": " + message}; }
    std::string where(const Element& e, uint64_t index, uint32_t ascii_line) const {
        if (format_ == Format::Ascii) return name_ + ":" + std::to_string(ascii_line) + ": ";
        return name_ + ": " + e.name + " " + std::to_string(index) + ": ";
    }
    void build_mesh(MeshFileResult& result);

    const std::string& name_;
    std::string_view bytes_;
    Format format_ = Format::Ascii;
    bool format_seen_ = false;
    std::vector<Element> elements_;
    size_t body_offset_ = 0;
    uint32_t body_line_ = 1;
    int vertex_element_ = -1, face_element_ = -1;
    bool has_normals_ = false, has_uvs_ = false;
    std::vector<std::string> skipped_;  // "element.property" names skipped, for the note

    std::vector<glm::vec3> positions_, normals_;
    std::vector<glm::vec2> uvs_;
    std::vector<glm::uvec3> triangles_;
    std::vector<uint32_t> triangle_faces_;  // the face element each triangle was fanned from
};

bool starts_with(std::string_view s, std::string_view p) {
    return s.substr(0, p.size()) == p;
}

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        const size_t b = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > b) out.push_back(line.substr(b, i - b));
    }
    return out;
}

void PlyParser::header() {
    size_t pos = 0;
    uint32_t number = 0;
    bool ended = false;
    while (pos < bytes_.size()) {
        const size_t nl = bytes_.find('\n', pos);
        if (nl == std::string_view::npos) break;
        std::string_view line = bytes_.substr(pos, nl - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos = nl + 1;
        ++number;
        if (number == 1) continue;  // "ply", checked by looks_like_ply
        if (line.find('\0') != std::string_view::npos) fail_line(number, "NUL byte in the header");
        if (words(line) == std::vector<std::string_view>{"end_header"}) {
            ended = true;
            break;
        }
        header_line(line, number);
    }
    if (!ended) fail("the header has no 'end_header' line");
    if (!format_seen_) fail("the header has no 'format' line");
    body_offset_ = pos;
    body_line_ = number + 1;
}

void PlyParser::header_line(std::string_view line, uint32_t number) {
    const std::vector<std::string_view> w = words(line);
    if (w.empty()) return;
    const std::string_view key = w[0];
    if (key == "comment" || key == "obj_info") return;
    if (key == "format") {
        if (w.size() != 3)
            fail_line(number, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
        if (w[1] == "ascii")
            format_ = Format::Ascii;
        else if (w[1] == "binary_little_endian")
            format_ = Format::BinaryLittle;
        else if (w[1] == "binary_big_endian")
            format_ = Format::BinaryBig;
        else
            fail_line(number, "unknown PLY format '" + printable(w[1]) + "'");
        if (w[2] != "1.0" && w[2] != "1")
            fail_line(number, "unsupported PLY version '" + printable(w[2]) + "' (1.0 is read)");
        if (format_seen_) fail_line(number, "'format' is given twice");
        format_seen_ = true;
        return;
    }
    // Comments may come before the format line (some writers put them there); nothing else.
    if (!format_seen_)
        fail_line(number, number == 2 ? std::string("expected 'format' on the header's second line")
                                      : "expected 'format' before '" + printable(key) + "'");
    if (key == "element") {
        if (w.size() != 3) fail_line(number, "expected 'element NAME COUNT'");
        Element e;
        e.name = std::string(w[1]);
        auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
        if (ec != std::errc() || ptr != w[2].data() + w[2].size())
            fail_line(number, "element count '" + printable(w[2]) + "' is not a non-negative integer");
        for (const Element& other : elements_)
            if (other.name == e.name)
                fail_line(number, "element '" + printable(e.name) + "' is declared twice");
        e.line = number;
        elements_.push_back(std::move(e));
        return;
    }
    if (key == "property") {
        if (elements_.empty()) fail_line(number, "'property' before any 'element'");
        Property p;
        if (w.size() == 5 && w[1] == "list") {
            p.list = true;
            if (!scalar_named(w[2], p.count_type) || !is_integer(p.count_type))
                fail_line(number, "list count type '" + printable(w[2]) + "' is not an integer type");
            if (!scalar_named(w[3], p.type))
                fail_line(number, "unknown property type '" + printable(w[3]) + "'");
            p.name = std::string(w[4]);
        } else if (w.size() == 3 && w[1] != "list") {
            if (!scalar_named(w[1], p.type))
                fail_line(number, "unknown property type '" + printable(w[1]) + "'");
            p.name = std::string(w[2]);
        } else {
            fail_line(number, "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
        }
        for (const Property& other : elements_.back().properties)
            if (other.name == p.name)
                fail_line(number, "property '" + printable(p.name) + "' is declared twice");
        elements_.back().properties.push_back(std::move(p));
        return;
    }
    fail_line(number, "unknown header line '" + printable(line) + "'");
}

Role role_of(std::string_view n) {
    static constexpr std::pair<std::string_view, Role> kRolesByName[] = {
        {"x", Role::X},         {"y", Role::Y},        {"z", Role::Z},         {"nx", Role::NX},
        {"ny", Role::NY},       {"nz", Role::NZ},      {"u", Role::U},         {"v", Role::V},
        {"s", Role::U},         {"t", Role::V},        {"texture_u", Role::U}, {"texture_v", Role::V},
        {"texture_s", Role::U}, {"texture_t", Role::V}};
    for (const auto& [name, role] : kRolesByName)
        if (n == name) return role;
    return Role::None;
}

void PlyParser::assign_roles() {
    for (size_t i = 0; i < elements_.size(); ++i) {
        if (elements_[i].name == "vertex") vertex_element_ = static_cast<int>(i);
        if (elements_[i].name == "face") face_element_ = static_cast<int>(i);
    }
    if (vertex_element_ < 0) fail("no 'vertex' element: a PLY mesh needs vertices and faces");
    if (face_element_ < 0) fail("no 'face' element: a PLY mesh needs faces (point clouds are not drawn)");
    Element& ve = elements_[size_t(vertex_element_)];
    bool seen[kRoles] = {};
    for (Property& p : ve.properties) {
        const Role r = role_of(p.name);
        if (r == Role::None || p.list || seen[size_t(r)]) {
            skipped_.push_back("vertex " + p.name);
            continue;
        }
        p.role = r;
        seen[size_t(r)] = true;
    }
    const auto has = [&](Role r) { return seen[size_t(r)]; };
    if (!has(Role::X) || !has(Role::Y) || !has(Role::Z))
        fail_line(ve.line, "the 'vertex' element needs properties x, y and z");
    has_normals_ = has(Role::NX) && has(Role::NY) && has(Role::NZ);
    if (!has_normals_ && (has(Role::NX) || has(Role::NY) || has(Role::NZ)))
        fail_line(ve.line, "vertex normals need all of nx, ny and nz");
    has_uvs_ = has(Role::U) && has(Role::V);
    if (!has_uvs_ && (has(Role::U) || has(Role::V)))
        fail_line(ve.line, "texture coordinates need both u and v (or s and t)");
    Element& fe = elements_[size_t(face_element_)];
    bool indices = false;
    for (Property& p : fe.properties) {
        if (!indices && p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
            if (!is_integer(p.type)) fail_line(fe.line, "face vertex indices must have an integer type");
            p.role = Role::Indices;
            indices = true;
        } else {
            skipped_.push_back("face " + p.name);
        }
    }
    if (!indices) fail_line(fe.line, "the 'face' element needs a list property 'vertex_indices'");
    for (const Element& e : elements_)
        if (&e != &ve && &e != &fe) skipped_.push_back(e.name);
    if (ve.count > kMaxElements) fail_line(ve.line, "too many vertices (" + std::to_string(ve.count) + ")");
    if (fe.count > kMaxElements) fail_line(fe.line, "too many faces (" + std::to_string(fe.count) + ")");
}

template <class Source>
void PlyParser::element(Source& src, const Element& e, bool vertices, bool faces) {
    // An element without properties has nothing to read, however many instances it declares.
    if (e.properties.empty()) return;
    // Never reserve more than the remaining bytes could hold.
    const size_t room = (bytes_.size() - body_offset_) / (format_ == Format::Ascii ? 2 : e.min_bytes()) + 1;
    const size_t expected = static_cast<size_t>(std::min<uint64_t>(e.count, room));
    if (vertices) {
        positions_.reserve(expected);
        if (has_normals_) normals_.reserve(expected);
        if (has_uvs_) uvs_.reserve(expected);
    }
    if (faces) {
        triangles_.reserve(expected);
        triangle_faces_.reserve(expected);
    }
    // Indices are checked against the header's vertex count: the file ends in an error unless it
    // holds that many vertices, so this is the final count even when the faces come first.
    const uint64_t nv = elements_[size_t(vertex_element_)].count;
    std::vector<uint32_t> corners;
    double slot[kRoles] = {};
    std::string_view token;
    for (uint64_t i = 0; i < e.count; ++i) {
        uint32_t line = 0;
        if constexpr (std::is_same_v<Source, AsciiSource>) line = src.next_line();
        const auto value = [&](Scalar t, const char* what) {
            double v = 0;
            if (!src.value(t, v, token)) {
                if constexpr (std::is_same_v<Source, AsciiSource>) line = src.line();
                if (src.bad())
                    throw PlyError{where(e, i, line) + "'" + printable(token) + "' is not a valid " + what};
                throw PlyError{where(e, i, line) + "the file ends in " + e.name + " " + std::to_string(i) +
                               " of " + std::to_string(e.count)};
            }
            return v;
        };
        for (const Property& p : e.properties) {
            if (!p.list) {
                const double v =
                    value(p.type, is_integer(p.type) ? "integer of the declared type" : "number");
                if (p.role != Role::None) slot[size_t(p.role)] = v;
                continue;
            }
            const double count = value(p.count_type, "list length");
            if (count < 0) throw PlyError{where(e, i, line) + "negative list length"};
            const auto n = static_cast<uint64_t>(count);
            if (p.role != Role::Indices) {
                for (uint64_t k = 0; k < n; ++k) value(p.type, "number");
                continue;
            }
            if (n < 3)
                throw PlyError{where(e, i, line) + "a face needs at least 3 vertices, this one has " +
                               std::to_string(n)};
            corners.clear();
            for (uint64_t k = 0; k < n; ++k) {
                const double v = value(p.type, "vertex index");
                if (v < 0 || v >= static_cast<double>(nv))
                    throw PlyError{where(e, i, line) + "vertex index " +
                                   std::to_string(static_cast<long long>(v)) +
                                   " out of range (the file has " + std::to_string(nv) + " vertices)"};
                corners.push_back(static_cast<uint32_t>(v));
            }
            for (size_t k = 1; k + 1 < corners.size(); ++k) {
                triangles_.emplace_back(corners[0], corners[k], corners[k + 1]);
                triangle_faces_.push_back(static_cast<uint32_t>(i));
            }
        }
        if (!vertices) continue;
        const auto finite_float = [&](Role r, const char* what) {
            const double v = slot[size_t(r)];
            if (!std::isfinite(v) || std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max()))
                throw PlyError{where(e, i, line) + what + " is not finite in single precision"};
            return static_cast<float>(v);
        };
        positions_.emplace_back(finite_float(Role::X, "x"), finite_float(Role::Y, "y"),
                                finite_float(Role::Z, "z"));
        if (has_normals_)
            normals_.emplace_back(finite_float(Role::NX, "nx"), finite_float(Role::NY, "ny"),
                                  finite_float(Role::NZ, "nz"));
        if (has_uvs_) uvs_.emplace_back(finite_float(Role::U, "u"), finite_float(Role::V, "v"));
    }
}

template <class Source>
void PlyParser::body(Source& src) {
    for (size_t k = 0; k < elements_.size(); ++k)
        element(src, elements_[k], int(k) == vertex_element_, int(k) == face_element_);
}

// Zero area by the scene builder's own test (|e1 × e2| ≤ 1e-12·|e1||e2|), as for OBJ files.
bool degenerate(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::dvec3 e1 = glm::dvec3(b) - glm::dvec3(a), e2 = glm::dvec3(c) - glm::dvec3(a);
    return !(glm::length(glm::cross(e1, e2)) > 1e-12 * glm::length(e1) * glm::length(e2));
}

void PlyParser::build_mesh(MeshFileResult& result) {
    auto mesh = std::make_shared<MeshData>();
    mesh->source_name = name_;
    mesh->face_origin = "face element";
    size_t skipped = 0, first_skipped = 0, kept = 0;
    for (size_t t = 0; t < triangles_.size(); ++t) {
        const glm::uvec3 f = triangles_[t];
        if (degenerate(positions_[f.x], positions_[f.y], positions_[f.z])) {
            if (skipped++ == 0) first_skipped = triangle_faces_[t];
            continue;
        }
        triangles_[kept] = f;
        triangle_faces_[kept++] = triangle_faces_[t];
    }
    triangles_.resize(kept);
    triangle_faces_.resize(kept);
    if (triangles_.empty()) {
        fail(skipped ? "every face is degenerate (zero area): the mesh has no triangle to draw"
                     : "no faces: the 'face' element is empty");
    }
    if (skipped)
        result.notes.push_back(name_ + ": skipped " + std::to_string(skipped) +
                               (skipped == 1 ? " degenerate triangle" : " degenerate triangles") +
                               " (zero area), the first from face element " + std::to_string(first_skipped));
    if (!skipped_.empty()) {
        std::string list;
        for (size_t k = 0; k < skipped_.size() && k < 8; ++k)
            list += (k ? ", " : "") + printable(skipped_[k]);
        if (skipped_.size() > 8) list += ", ...";
        result.notes.push_back(name_ + ": ignored what wsd does not use: " + list);
    }
    mesh->vertices = std::move(positions_);
    mesh->normals = std::move(normals_);
    mesh->uvs = std::move(uvs_);
    mesh->faces = std::move(triangles_);
    mesh->face_lines = std::move(triangle_faces_);
    result.mesh = std::move(mesh);
}

MeshFileResult PlyParser::run() {
    MeshFileResult result;
    try {
        header();
        assign_roles();
        const std::string_view rest = bytes_.substr(body_offset_);
        if (format_ == Format::Ascii) {
            AsciiSource src(rest, body_line_);
            body(src);
            if (!src.at_end()) fail_line(src.line(), "unexpected data after the last element");
        } else {
            BinarySource src(rest, format_ == Format::BinaryBig);
            body(src);
            if (!src.at_end())
                result.notes.push_back(name_ + ": ignored " + std::to_string(src.remaining()) +
                                       " bytes after the last element");
        }
        build_mesh(result);
    } catch (const PlyError& e) {
        result.error = e.message;
        result.mesh.reset();
    }
    return result;
}

}  // namespace

bool looks_like_ply(std::string_view bytes) {
    if (!starts_with(bytes, "ply")) return false;
    size_t i = 3;  // trailing blanks are allowed, as on every header line
    while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t')) ++i;
    return starts_with(bytes.substr(i), "\n") || starts_with(bytes.substr(i), "\r\n");
}

MeshFileResult parse_ply(const std::string& name, std::string_view bytes) {
    try {
        PlyParser parser(name, bytes);
        return parser.run();
    } catch (const std::bad_alloc&) {
        MeshFileResult result;
        result.error = name + ": out of memory while reading the mesh";
        return result;
    }
}

}  // namespace wsd::render
