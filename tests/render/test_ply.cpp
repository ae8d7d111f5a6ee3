// The PLY reader: one mesh written as ASCII and in both binary byte orders reads back identically;
// polygons are fanned; normals and each spelling of texture coordinates are read; properties and
// elements wsd does not use are skipped with a note; every malformed input is an error naming
// where it is; and a mutation run over the three encodings never crashes (robustness.md).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "render/mesh_file.h"
#include "render/obj.h"
#include "render/ply.h"

using namespace wsd::render;

namespace {

enum class Enc { Ascii, Little, Big };

// A small test mesh: a pentagon fan, a quad and a triangle over 8 vertices, with normals and
// uvs, a colour property and an extra element, in any of the three encodings.
struct PlyWriter {
    Enc enc;
    std::string out;

    void raw(const void* p, size_t n) {
        std::string b(static_cast<const char*>(p), n);
        if (enc == Enc::Big) std::reverse(b.begin(), b.end());
        out += b;
    }
    void f32(float v) {
        if (enc == Enc::Ascii) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.9g ", static_cast<double>(v));
            out += buf;
        } else {
            raw(&v, 4);
        }
    }
    void u8(uint8_t v) {
        if (enc == Enc::Ascii)
            out += std::to_string(v) + " ";
        else
            out.push_back(static_cast<char>(v));
    }
    void i32(int32_t v) {
        if (enc == Enc::Ascii)
            out += std::to_string(v) + " ";
        else
            raw(&v, 4);
    }
    void end_line() {
        if (enc == Enc::Ascii) out += "\n";
    }
};

const float kPos[8][3] = {{0, 0, 0},     {1, 0, 0}, {1.5f, 1, 0}, {0.5f, 1.6f, 0},
                          {-0.5f, 1, 0}, {0, 0, 1}, {1, 0, 1},    {1, 1, 1}};

std::string test_ply(Enc enc) {
    PlyWriter w{enc, {}};
    w.out = std::string("ply\nformat ") +
            (enc == Enc::Ascii    ? "ascii"
             : enc == Enc::Little ? "binary_little_endian"
                                  : "binary_big_endian") +
            " 1.0\ncomment made by a test\nelement vertex 8\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
            "property float texture_u\nproperty float texture_v\nproperty uchar red\n"
            "element face 3\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
            "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    for (int i = 0; i < 8; ++i) {
        for (float c : kPos[i]) w.f32(c);
        w.f32(0), w.f32(0), w.f32(1);
        w.f32(kPos[i][0] * 0.5f), w.f32(kPos[i][1] * 0.25f);
        w.u8(200);
        w.end_line();
    }
    const std::vector<std::vector<int>> faces = {{0, 1, 2, 3, 4}, {0, 1, 6, 5}, {1, 2, 7}};
    for (const auto& f : faces) {
        w.u8(static_cast<uint8_t>(f.size()));
        for (int i : f) w.i32(i);
        w.u8(7);
        w.end_line();
    }
    w.i32(0), w.i32(1), w.end_line();
    return w.out;
}

}  // namespace

TEST_CASE("PLY: ASCII and both binary byte orders read the same mesh", "[ply]") {
    const MeshFileResult a = parse_ply("a.ply", test_ply(Enc::Ascii));
    REQUIRE(a.error == "");
    REQUIRE(a.mesh);
    const MeshData& m = *a.mesh;
    CHECK(m.vertices.size() == 8);
    CHECK(m.faces.size() == 3 + 2 + 1);  // pentagon fanned into 3, quad into 2
    CHECK(m.faces[0] == glm::uvec3(0, 1, 2));
    CHECK(m.faces[2] == glm::uvec3(0, 3, 4));
    CHECK(m.faces[4] == glm::uvec3(0, 6, 5));
    CHECK(m.face_lines == std::vector<uint32_t>{0, 0, 0, 1, 1, 2});
    REQUIRE(m.normals.size() == 8);
    REQUIRE(m.uvs.size() == 8);
    CHECK(m.uvs[3] == glm::vec2(0.25f, 0.4f));
    CHECK(m.vertices[3] == glm::vec3(0.5f, 1.6f, 0));
    REQUIRE(a.notes.size() == 1);
    CHECK(a.notes[0] == "a.ply: ignored what wsd does not use: vertex red, face flags, edge");
    for (Enc enc : {Enc::Little, Enc::Big}) {
        const MeshFileResult b = parse_ply("b.ply", test_ply(enc));
        REQUIRE(b.error == "");
        REQUIRE(b.mesh);
        CHECK(b.mesh->vertices == m.vertices);
        CHECK(b.mesh->normals == m.normals);
        CHECK(b.mesh->uvs == m.uvs);
        CHECK(b.mesh->faces == m.faces);
        CHECK(b.mesh->face_lines == m.face_lines);
    }
}

TEST_CASE("PLY: files are told from OBJ by their first line", "[ply]") {
    CHECK(looks_like_ply("ply\nformat ascii 1.0\n"));
    CHECK(looks_like_ply("ply\r\nformat ascii 1.0\r\n"));
    CHECK(looks_like_ply("ply \t\nformat ascii 1.0\n"));  // trailing blanks, as on any header line
    CHECK(looks_like_ply("ply  \r\nformat ascii 1.0\r\n"));
    CHECK_FALSE(looks_like_ply("v 0 0 0\n"));
    CHECK_FALSE(looks_like_ply("plywood\n"));
}

TEST_CASE("PLY: CRLF headers, other type names and texture coordinate spellings", "[ply]") {
    const std::string text =
        "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty double x\r\nproperty float32 y\r\n"
        "property int16 z\r\nproperty float s\r\nproperty float t\r\nelement face 1\r\n"
        "property list uint8 uint32 vertex_index\r\nend_header\r\n0 0 0 0 0\r\n1 0 0 1 0\r\n0 1 -2 0 1\r\n3 "
        "0 1 2\r\n";
    const MeshFileResult r = parse_ply("c.ply", text);
    REQUIRE(r.error == "");
    REQUIRE(r.mesh);
    CHECK(r.mesh->vertices[2] == glm::vec3(0, 1, -2));
    CHECK(r.mesh->uvs[1] == glm::vec2(1, 0));
    CHECK(r.mesh->normals.empty());
    CHECK(r.notes.empty());
}

TEST_CASE("PLY: ASCII integers take a plus sign as floats do; '+-' is no number", "[ply]") {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty int z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const MeshFileResult r = parse_ply("p.ply", head + "+0 0 0\n1 +0 0\n0 1 +2\n+3 +0 1 +2\n");
    REQUIRE(r.error == "");
    REQUIRE(r.mesh);
    CHECK(r.mesh->vertices[2] == glm::vec3(0, 1, 2));
    CHECK(r.mesh->faces.size() == 1);
    CHECK_FALSE(parse_ply("p.ply", head + "0 0 0\n1 0 0\n0 1 +-2\n3 0 1 2\n").error.empty());
    CHECK_FALSE(parse_ply("p.ply", head + "0 0 0\n1 0 0\n0 1 2\n3 0 1 ++2\n").error.empty());
}

TEST_CASE("PLY: zero-area triangles are skipped with one note, as in OBJ files", "[ply]") {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n";
    const MeshFileResult r = parse_ply("d.ply", text);
    REQUIRE(r.mesh);
    CHECK(r.mesh->faces.size() == 1);
    REQUIRE(r.notes.size() == 1);
    CHECK(r.notes[0] == "d.ply: skipped 1 degenerate triangle (zero area), the first from face element 1");
}

TEST_CASE("PLY: malformed files are errors that say where", "[ply]") {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    struct Case {
        std::string text, error;
    };
    const std::vector<Case> cases = {
        {"ply\nelement vertex 3\n", "e.ply:2: expected 'format' on the header's second line"},
        {"ply\ncomment x\nelement vertex 3\n", "e.ply:3: expected 'format' before 'element'"},
        {"ply\nformat ascii 1.0\nformat ascii 1.0\nend_header\n", "e.ply:3: 'format' is given twice"},
        {"ply\nformat ascii 2.0\nend_header\n", "e.ply:2: unsupported PLY version '2.0' (1.0 is read)"},
        {"ply\nformat text 1.0\nend_header\n", "e.ply:2: unknown PLY format 'text'"},
        {"ply\nformat ascii 1.0\nelement vertex 3\n", "e.ply: the header has no 'end_header' line"},
        {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "e.ply:3: 'property' before any 'element'"},
        {"ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
         "e.ply:3: element count '-3' is not a non-negative integer"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\nend_header\n",
         "e.ply:4: unknown property type 'half'"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
         "e.ply: no 'face' element: a PLY mesh needs faces (point clouds are not drawn)"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement face 0\n"
         "property list uchar int vertex_indices\nend_header\n0\n",
         "e.ply:3: the 'vertex' element needs properties x, y and z"},
        {head + "0 0 0\n1 0 0\n", "e.ply:12: the file ends in vertex 2 of 3"},
        {head + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "e.ply:11: 'zero' is not a valid number"},
        {head + "+-1 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "e.ply:10: '+-1' is not a valid number"},
        {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
         "e.ply:13: vertex index 3 out of range (the file has 3 vertices)"},
        {head + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "e.ply:13: a face needs at least 3 vertices, this one has 2"},
        {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n", "e.ply:13: '2.5' is not a valid vertex index"},
        {head + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n", "e.ply:13: '300' is not a valid list length"},
        {head + body + "9\n", "e.ply:14: unexpected data after the last element"},
        {head + "0 0 0\n1 0 0\n0 1e39 0\n3 0 1 2\n", "e.ply:12: y is not finite in single precision"},
        {"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000000\nproperty float x\nproperty "
         "float y\n"
         "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
         "e.ply:3: too many vertices (4000000000000)"},
        {"ply\nformat binary_little_endian 1.0\nelement vertex 100000\nproperty float x\nproperty float y\n"
         "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\nabc",
         "e.ply: vertex 0: the file ends in vertex 0 of 100000"},
    };
    for (const Case& c : cases) {
        INFO(c.text);
        const MeshFileResult r = parse_ply("e.ply", c.text);
        CHECK_FALSE(r.mesh);
        CHECK(r.error == c.error);
    }
    CHECK(parse_ply("e.ply", head + body).mesh);
    // Comments (and blank lines) may come before the format line, as some writers put them there.
    CHECK(parse_ply("e.ply", "ply\ncomment by a scanner\n\nobj_info x\n" + head.substr(4) + body).mesh);
    CHECK(parse_ply("e.ply", head + "+0 0 0\n+1 0 0\n0 +1 0\n3 0 1 2\n").mesh);
}

TEST_CASE("PLY: an element without properties is read as nothing, whatever its count", "[ply]") {
    // Its instances hold no values: the reader must not step through them one by one (2^64 - 1
    // of them would never end).
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        INFO(format);
        std::string text = "ply\nformat ";
        text.append(format).append(
            " 1.0\nelement junk 18446744073709551615\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\n"
            "property list uchar int vertex_indices\nend_header\n");
        if (std::string(format) == "ascii") {
            text += "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        } else {
            PlyWriter w{std::string(format) == "binary_big_endian" ? Enc::Big : Enc::Little, {}};
            for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) w.f32(v);
            w.u8(3), w.i32(0), w.i32(1), w.i32(2);
            text += w.out;
        }
        const MeshFileResult r = parse_ply("e.ply", text);
        INFO(r.error);
        REQUIRE(r.mesh);
        CHECK(r.mesh->faces.size() == 1);
    }
}

TEST_CASE("PLY: the face element may come before the vertex element", "[ply]") {
    // Elements may be declared in any order; the indices are checked against the vertex count.
    for (Enc enc : {Enc::Ascii, Enc::Little, Enc::Big}) {
        INFO(static_cast<int>(enc));
        const auto file = [&](int last_index) {
            PlyWriter w{enc, {}};
            w.out = std::string("ply\nformat ") +
                    (enc == Enc::Ascii    ? "ascii"
                     : enc == Enc::Little ? "binary_little_endian"
                                          : "binary_big_endian") +
                    " 1.0\nelement face 2\nproperty list uchar int vertex_indices\nelement vertex 4\n"
                    "property float x\nproperty float y\nproperty float z\nend_header\n";
            w.u8(3), w.i32(0), w.i32(1), w.i32(2), w.end_line();
            w.u8(3), w.i32(0), w.i32(2), w.i32(last_index), w.end_line();
            for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) w.f32(v);
            w.end_line();
            return w.out;
        };
        const MeshFileResult r = parse_ply("f.ply", file(3));
        INFO(r.error);
        REQUIRE(r.mesh);
        CHECK(r.mesh->vertices.size() == 4);
        CHECK(r.mesh->vertices[2] == glm::vec3(1, 1, 0));
        CHECK(r.mesh->faces == std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}});
        const MeshFileResult bad = parse_ply("f.ply", file(4));
        CHECK_FALSE(bad.mesh);
        CHECK(bad.error.find("vertex index 4 out of range (the file has 4 vertices)") != std::string::npos);
    }
}

TEST_CASE("PLY: a mesh reads the same from PLY and OBJ", "[ply]") {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 1.6 0\nv -0.5 1 0\nf 1 2 3 4 5\n";
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n1.5 1 0\n0.5 1.6 0\n-0.5 1 0\n5 0 1 2 3 4\n";
    const MeshFileResult a = parse_obj("m.obj", obj), b = parse_ply("m.ply", ply);
    REQUIRE(a.mesh);
    REQUIRE(b.mesh);
    CHECK(a.mesh->vertices == b.mesh->vertices);
    CHECK(a.mesh->faces == b.mesh->faces);
}

TEST_CASE("PLY: mutated files never crash the reader", "[ply][mutation]") {
    std::mt19937 rng(12345);
    for (Enc enc : {Enc::Ascii, Enc::Little, Enc::Big}) {
        const std::string good = test_ply(enc);
        for (int round = 0; round < 3000; ++round) {
            std::string s = good;
            const int edits = 1 + static_cast<int>(rng() % 4);
            for (int e = 0; e < edits; ++e) {
                const size_t at = rng() % s.size();
                switch (rng() % 3) {
                    case 0:
                        s[at] = static_cast<char>(rng() & 0xff);
                        break;
                    case 1:
                        s.erase(at, 1 + rng() % 8);
                        break;
                    default:
                        s.resize(at);
                        break;
                }
                if (s.empty()) s.push_back('p');  // not s = "p": GCC 12's -Wrestrict misreads that here
            }
            const MeshFileResult r = parse_ply("f.ply", s);
            if (r.mesh) {
                for (const auto& f : r.mesh->faces)
                    for (int k = 0; k < 3; ++k) REQUIRE(f[k] < r.mesh->vertices.size());
                REQUIRE(r.mesh->face_lines.size() == r.mesh->faces.size());
            } else {
                REQUIRE_FALSE(r.error.empty());
            }
        }
    }
}
