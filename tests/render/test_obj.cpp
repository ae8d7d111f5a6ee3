// The OBJ reader: the golden files in tests/golden/obj (each states its expected triangle count or
// exact error in its leading "# expect-..." comments), plus unit tests for unwelding, fanning,
// line endings, notes, numbers and a mutation run that must never crash (robustness.md R62).
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "render/obj.h"

using namespace wsd::render;
namespace fs = std::filesystem;

namespace {

struct Expectation {
    long triangles = -1, vertices = -1;
    std::string error;
    std::vector<std::string> notes;
};

Expectation read_expectation(const std::string& text) {
    Expectation e;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line) && line.rfind("#", 0) == 0) {
        while (!line.empty() && line.back() == '\r') line.pop_back();
        const auto value = [&](const std::string& key) -> std::optional<std::string> {
            const std::string prefix = "# " + key + ": ";
            if (line.rfind(prefix, 0) != 0) return std::nullopt;
            return line.substr(prefix.size());
        };
        if (auto v = value("expect-triangles")) e.triangles = std::stol(*v);
        if (auto v = value("expect-vertices")) e.vertices = std::stol(*v);
        if (auto v = value("expect-error")) e.error = *v;
        if (auto v = value("expect-note")) e.notes.push_back(*v);
    }
    return e;
}

std::string strip_prefix(std::string s, const std::string& prefix) {
    if (s.rfind(prefix, 0) == 0) s.erase(0, prefix.size());
    return s;
}

// Every index in range, per-vertex arrays consistent, one source line per triangle.
void check_mesh_invariants(const MeshData& m) {
    REQUIRE(m.face_lines.size() == m.faces.size());
    REQUIRE((m.uvs.empty() || m.uvs.size() == m.vertices.size()));
    REQUIRE((m.normals.empty() || m.normals.size() == m.vertices.size()));
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) REQUIRE(f[k] < m.vertices.size());
    for (const auto& v : m.vertices)
        for (int k = 0; k < 3; ++k) REQUIRE(std::isfinite(v[k]));
}

MeshFileResult parse(std::string_view text) {
    return parse_obj("t.obj", text);
}

}  // namespace

TEST_CASE("R62: golden OBJ files", "[obj]") {
    const fs::path dir = fs::path(WSD_SOURCE_DIR) / "tests" / "golden" / "obj";
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().extension() == ".obj") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    REQUIRE(files.size() >= 15);
    for (const fs::path& path : files) {
        std::ifstream in(path, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const Expectation want = read_expectation(text);
        INFO(path.filename().string());
        REQUIRE((want.triangles >= 0) != !want.error.empty());  // each file says exactly one of them

        const MeshFileResult got = load_obj(path.string());
        const std::string prefix = dir.string() + "/";
        if (!want.error.empty()) {
            CHECK_FALSE(got.mesh);
            CHECK(strip_prefix(got.error, prefix) == want.error);
        } else {
            INFO(got.error);
            REQUIRE(got.mesh);
            check_mesh_invariants(*got.mesh);
            CHECK(static_cast<long>(got.mesh->faces.size()) == want.triangles);
            if (want.vertices >= 0) CHECK(static_cast<long>(got.mesh->vertices.size()) == want.vertices);
            CHECK(got.mesh->source_name == path.string());
        }
        for (const std::string& note : want.notes) {
            std::vector<std::string> notes;
            for (const auto& n : got.notes) notes.push_back(strip_prefix(n, prefix));
            INFO("expected note: " << note);
            CHECK(std::find(notes.begin(), notes.end(), note) != notes.end());
        }
    }
}

TEST_CASE("polygons are fanned from their first corner, each triangle keeps its line", "[obj]") {
    const auto r = parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\nf 1 2 3 4\nf 4 3 2\n");
    REQUIRE(r.mesh);
    const auto& m = *r.mesh;
    REQUIRE(m.faces.size() == 3);
    CHECK(m.faces[0] == glm::uvec3(0, 1, 2));
    CHECK(m.faces[1] == glm::uvec3(0, 2, 3));
    CHECK(m.faces[2] == glm::uvec3(3, 2, 1));
    CHECK(m.face_lines == std::vector<uint32_t>{6, 6, 7});
    CHECK(m.uvs.empty());
    CHECK(m.normals.empty());
    CHECK(m.source_name == "t.obj");

    std::string big = "v 0 0 0\n";
    for (int i = 0; i < 63; ++i)
        big += "v " + std::to_string(std::cos(i * 0.1)) + " " + std::to_string(std::sin(i * 0.1)) + " 1\n";
    big += "f";
    for (int i = 1; i <= 64; ++i) big += " " + std::to_string(i);
    const auto r64 = parse(big);
    REQUIRE(r64.mesh);
    CHECK(r64.mesh->faces.size() == 62);
}

TEST_CASE("corners sharing a position but not a uv or normal are unwelded", "[obj]") {
    const auto r = parse(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
        "vn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1\n"
        "f 2/2/1 4/4/1 3/4/1\n");  // vertex 3 with a second uv
    REQUIRE(r.mesh);
    const auto& m = *r.mesh;
    check_mesh_invariants(m);
    CHECK(m.vertices.size() == 5);  // 1, 2, 3/3, 4, 3/4
    REQUIRE(m.uvs.size() == 5);
    REQUIRE(m.normals.size() == 5);
    CHECK(m.faces[1][0] == m.faces[0][1]);  // 2/2/1 shared
    CHECK(m.faces[1][2] != m.faces[0][2]);  // 3/3 and 3/4 differ
    CHECK(m.vertices[m.faces[1][2]] == m.vertices[m.faces[0][2]]);
    CHECK(m.uvs[m.faces[1][2]] == glm::vec2(0.5f, 0.5f));
    CHECK(m.uvs[m.faces[0][2]] == glm::vec2(0.0f, 1.0f));
}

TEST_CASE("files mixing faces with and without vt or vn stay representable", "[obj]") {
    const auto r = parse(
        "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 2 2 0\n"
        "vt 0.25 0.75\nvn 0 0 -1\n"
        "f 1/1/1 2/1/1 3/1/1\n"
        "f 2 4 3\n");
    REQUIRE(r.mesh);
    const auto& m = *r.mesh;
    check_mesh_invariants(m);
    REQUIRE(m.uvs.size() == m.vertices.size());
    REQUIRE(m.normals.size() == m.vertices.size());
    // The face without vt gets what a mesh without uvs shows: its barycentric coordinates.
    const glm::uvec3 f = m.faces[1];
    CHECK(m.uvs[f[0]] == glm::vec2(0, 0));
    CHECK(m.uvs[f[1]] == glm::vec2(1, 0));
    CHECK(m.uvs[f[2]] == glm::vec2(0, 1));
    // ... and a flat normal, cross(v1 − v0, v2 − v0) normalized.
    for (int k = 0; k < 3; ++k) CHECK(m.normals[f[k]] == glm::vec3(0, 0, 1));
    CHECK(m.normals[m.faces[0][0]] == glm::vec3(0, 0, -1));
    // Within one face, mixing forms is an error.
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3\n").error ==
          "t.obj:5: face mixes vertices with and without normals");
}

TEST_CASE("R62: relative and forward indices", "[obj]") {
    const auto fwd = parse("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    REQUIRE(fwd.mesh);
    CHECK(fwd.mesh->faces.size() == 1);
    const auto rel = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n");
    REQUIRE(rel.mesh);
    CHECK(rel.mesh->uvs[rel.mesh->faces[0][2]] == glm::vec2(0, 1));
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n").error ==
          "t.obj:5: texture coordinate index 2 out of range (the file defines 1)");
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n").error ==
          "t.obj:4: normal index 1 out of range (the file defines 0)");
    CHECK(parse("v 0 0 0\nf 1 1 99999999999999999999\n").error ==
          "t.obj:2: index 99999999999999999999 out of range");
    // A repeated vertex makes a zero-area triangle, skipped; here nothing is left.
    CHECK(parse("v 0 0 0\nv 1 0 0\nf 1 1 2\n").error ==
          "t.obj:3: every face is degenerate (zero area): the mesh has no triangle to draw");
}

TEST_CASE("line endings, comments and continuation lines", "[obj]") {
    for (const char* text : {"v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n",
                             "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3",
                             "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3" /* byte-order mark */}) {
        const auto r = parse(text);
        INFO(r.error);
        REQUIRE(r.mesh);
        CHECK(r.mesh->face_lines == std::vector<uint32_t>{4});
    }
    const auto cont = parse("v 0 0 0 # origin\nv 1 0 0\nv 0 1 0\nf 1 \\\n  2 \\\n 3\nf 1 2 3\n");
    REQUIRE(cont.mesh);
    CHECK(cont.mesh->face_lines == std::vector<uint32_t>{4, 7});
    const auto comment = parse("# C:\\models\\\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    REQUIRE(comment.mesh);
    CHECK(comment.mesh->face_lines == std::vector<uint32_t>{5});
    CHECK(parse("v 0 0 0\nf 1 \\\n x 3\n").error ==
          "t.obj:2: bad face vertex 'x' (expected v, v/vt, v/vt/vn or v//vn)");
}

TEST_CASE("numbers", "[obj]") {
    const auto r =
        parse("v +1.5 -2 3e-2\nv 1e-400 .5 5.\nv 0 0 1 1\nv 0 0 0 0.5 0.5 0.5\nvt 0.5\nf 1 2 3 4\n");
    REQUIRE(r.mesh);
    CHECK(r.mesh->vertices[0] == glm::vec3(1.5f, -2.0f, 0.03f));
    CHECK(r.mesh->vertices[1] == glm::vec3(0.0f, 0.5f, 5.0f));
    CHECK(parse("v 1e400 0 0\n").error ==
          "t.obj:1: number '1e400' is not finite (NaN, infinite or too large)");
    CHECK(parse("v 0 -123.5e307 0\n").error ==
          "t.obj:1: number '-123.5e307' is not finite (NaN, infinite or too large)");
    CHECK(parse("v 0 0 0.00001e-320\nv 1 0 -12e-330\nv 0 1 0\nf 1 2 3\n").mesh);
    CHECK(parse("v inf 0 0\n").error == "t.obj:1: number 'inf' is not finite (NaN, infinite or too large)");
    CHECK(parse("v 0x10 0 0\n").error == "t.obj:1: bad number '0x10'");
    CHECK(parse("v 1 2 3 4 5 6 7 8\n").error == "t.obj:1: too many numbers in 'v' (at most 7)");
    CHECK(parse("vn 1 2\n").error == "t.obj:1: 'vn' needs 3 numbers, found 2");
    CHECK(parse("vt\n").error == "t.obj:1: 'vt' needs at least 1 number, found 0");
    CHECK(parse("v 1 2\n").error == "t.obj:1: 'v' needs at least 3 numbers, found 2");
    CHECK(parse("v 0 0 0\nf 1.0 1 1\n").error ==
          "t.obj:2: bad face vertex '1.0' (expected v, v/vt, v/vt/vn or v//vn)");
    CHECK(parse("v 0 0 0\nf 1/ 1 1\n").error ==
          "t.obj:2: bad face vertex '1/' (expected v, v/vt, v/vt/vn or v//vn)");
    CHECK(parse("v 0 0 0\nf /1 1 1\n").error ==
          "t.obj:2: bad face vertex '/1' (expected v, v/vt, v/vt/vn or v//vn)");
}

TEST_CASE("skipped statements give one note per file that sums them up", "[obj]") {
    std::string text = "o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nusemtl b\nfoo 1\nf 1 2 3\nfoo 2\ns 1\n";
    const auto r = parse(text);
    REQUIRE(r.mesh);
    CHECK(r.notes ==
          std::vector<std::string>{
              "t.obj:1: ignored 6 statements that wsd does not use: 'o' (line 1), 'usemtl' (2, from line "
              "5), 'foo' (unknown OBJ statement, 2, from line 7), 's' (line 10)"});
    // A flood of distinct unknown statements still gives one note, of bounded length.
    std::string flood = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    for (int i = 0; i < 100; ++i) flood += "kind" + std::to_string(i) + " 1\n";
    const auto capped = parse(flood);
    REQUIRE(capped.mesh);
    REQUIRE(capped.notes.size() == 1);
    CHECK(capped.notes[0].find("ignored 100 statements") != std::string::npos);
    CHECK(capped.notes[0].find(", and 84 of other kinds") != std::string::npos);
    CHECK(capped.notes[0].size() < 1200);
}

TEST_CASE("zero-area triangles of a mesh file are skipped with one note that counts them", "[obj]") {
    // A cap like a UV sphere's pole: quads whose last two corners are the pole, so each fans into
    // one good triangle and one of zero area; and a face of three collinear points.
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nv 2 0 0\n"
        "f 1 2 5 5\n"
        "f 2 3 5 5\n"
        "f 1 2 6\n"
        "f 3 4 5\n";
    auto r = parse(text);
    REQUIRE(r.mesh);
    CHECK(r.mesh->faces.size() == 3);
    CHECK(r.mesh->face_lines == std::vector<uint32_t>{7, 8, 10});
    CHECK(r.notes ==
          std::vector<std::string>{
              "t.obj:7: skipped 3 degenerate triangles (zero area), the first from this line's face"});
    // The same with uvs and normals (the unwelding path).
    r = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 2/1/1\nf 1/1/1 2/1/1 3/1/1\n");
    REQUIRE(r.mesh);
    CHECK(r.mesh->faces.size() == 1);
    CHECK(r.mesh->vertices.size() == 3);
    CHECK(r.notes ==
          std::vector<std::string>{
              "t.obj:6: skipped 1 degenerate triangle (zero area), the first from this line's face"});
    // Nothing left to draw is an error.
    r = parse("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    CHECK_FALSE(r.mesh);
    CHECK(r.error == "t.obj:4: every face is degenerate (zero area): the mesh has no triangle to draw");
}

TEST_CASE("files without faces, binary input and unreadable files", "[obj]") {
    CHECK(parse("").error == "t.obj:1: no faces: an OBJ mesh needs at least one 'f' statement");
    CHECK(parse("v 0 0 0\n\n\n").error == "t.obj:3: no faces: an OBJ mesh needs at least one 'f' statement");
    CHECK(parse(std::string_view("v 0 0 0\nv 1\0 0 0\n", 17)).error ==
          "t.obj:2: NUL byte: this is not a text OBJ file");
    CHECK(parse("v 0 0 0\nf 1 2 3\x01\xff\n")
              .error.rfind("t.obj:2: bad face vertex '3?"
                           "?'",
                           0) == 0);

    const std::string missing = (fs::temp_directory_path() / "wsd_no_such_mesh.obj").string();
    const auto r = load_obj(missing);
    CHECK_FALSE(r.mesh);
    CHECK(r.error.find(missing) != std::string::npos);
    CHECK(r.error.find("No such file") != std::string::npos);
    CHECK(load_obj(fs::temp_directory_path().string()).error.find("it is a directory") != std::string::npos);
}

TEST_CASE("R62: mutated OBJ text never crashes and never yields a broken mesh", "[obj]") {
    const std::string base =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1 4/1/1\nf -1//1 -2//1 -3//1\ng x\nf 1 2 4\n";
    const char alphabet[] = "0123456789-+./ \n\r\t#efvtnx\\\0";
    std::mt19937 rng(1234);
    int meshes = 0, errors = 0;
    for (int i = 0; i < 3000; ++i) {
        std::string text = base;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const size_t at = rng() % text.size();
            const char c = alphabet[rng() % (sizeof alphabet - 1)];
            switch (rng() % 3) {
                case 0:
                    text[at] = c;
                    break;
                case 1:
                    text.insert(at, 1, c);
                    break;
                default:
                    text.erase(at, 1);
                    break;
            }
        }
        const auto r = parse(text);
        if (r.mesh) {
            ++meshes;
            check_mesh_invariants(*r.mesh);
        } else {
            ++errors;
            REQUIRE(r.error.rfind("t.obj:", 0) == 0);
            REQUIRE(std::isdigit(static_cast<unsigned char>(r.error[6])));
        }
    }
    CHECK(meshes > 100);
    CHECK(errors > 100);
}
