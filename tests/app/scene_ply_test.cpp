// PLY meshes in scenes, loaded and rendered by the real `wsd`: the example torus written as ASCII
// and binary PLY (with its normals) renders byte for byte like the OBJ it came from, and a broken
// PLY file is an error at the `file` property naming the file's own line.
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>

#include "app_test_util.h"
#include "render/obj.h"

using namespace wsd::test;

namespace {

// `m` as a PLY file: positions and normals as float, faces as uchar-counted int lists.
std::string to_ply(const wsd::render::MeshData& m, bool binary) {
    std::string out = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                      " 1.0\nelement vertex " + std::to_string(m.vertices.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\n"
                      "property float nx\nproperty float ny\nproperty float nz\nelement face " +
                      std::to_string(m.faces.size()) +
                      "\nproperty list uchar int vertex_indices\nend_header\n";
    const auto put = [&](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
    char buf[64];
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const float v[6] = {m.vertices[i].x, m.vertices[i].y, m.vertices[i].z,
                            m.normals[i].x,  m.normals[i].y,  m.normals[i].z};
        if (binary) {
            put(v, sizeof v);
            continue;
        }
        for (float x : v) {
            std::snprintf(buf, sizeof buf, "%.9g ", static_cast<double>(x));
            out += buf;
        }
        out += "\n";
    }
    for (const auto& f : m.faces) {
        const int idx[3] = {static_cast<int>(f.x), static_cast<int>(f.y), static_cast<int>(f.z)};
        if (binary) {
            out.push_back(3);
            put(idx, sizeof idx);
        } else {
            out += "3 " + std::to_string(idx[0]) + " " + std::to_string(idx[1]) + " " +
                   std::to_string(idx[2]) + "\n";
        }
    }
    return out;
}

const char* const kHead =
    "settings { width 40  height 30 }\n"
    "camera { position <0, 2, -4>  look_at <0, 0, 0> }\n"
    "light point { position <3, 8, -5> }\n";

}  // namespace

TEST_CASE("a PLY mesh renders byte for byte like the OBJ it was written from", "[ply][e2e]") {
    TempDir dir;
    const auto obj = wsd::render::load_obj((fs::path(WSD_SOURCE_DIR) / "examples/models/torus.obj").string());
    REQUIRE(obj.mesh);
    REQUIRE(obj.mesh->normals.size() == obj.mesh->vertices.size());
    fs::copy_file(fs::path(WSD_SOURCE_DIR) / "examples/models/torus.obj", dir.path() / "torus.obj");
    write_file(dir / "ascii.ply", to_ply(*obj.mesh, false));
    write_file(dir / "binary.ply", to_ply(*obj.mesh, true));
    std::string images[3];
    const char* files[3] = {"torus.obj", "ascii.ply", "binary.ply"};
    for (int i = 0; i < 3; ++i) {
        write_file(dir / "s.wsd",
                   std::string(kHead) + "mesh { file \"" + files[i] +
                       "\"  rotate <30, 20, 0>  material { color <0.9, 0.5, 0.2>  specular 0.4 } }\n");
        const RunResult r = run_wsd(dir, "render s.wsd -o s.pfm --quiet");
        INFO(files[i] << ": " << r.err);
        REQUIRE(r.status == 0);
        images[i] = read_file(dir / "s.pfm");
    }
    CHECK(images[1] == images[0]);
    CHECK(images[2] == images[0]);
}

TEST_CASE("a broken PLY file is an error at the scene's file property", "[ply][e2e]") {
    TempDir dir;
    write_file(
        dir / "bad.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n");
    write_file(dir / "s.wsd", std::string(kHead) + "mesh { file \"bad.ply\" }\n");
    const RunResult r = run_wsd(dir, "render s.wsd -o s.png --quiet");
    CHECK(r.status != 0);
    CHECK(
        r.err.find("s.wsd:4:13: error: bad.ply:13: vertex index 5 out of range (the file has 3 vertices)") !=
        std::string::npos);
    CHECK_FALSE(fs::exists(dir.path() / "s.png"));
}

TEST_CASE("a file named .ply that is not PLY is an error, not read as OBJ", "[ply][e2e]") {
    TempDir dir;
    const std::string rest =
        "format ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    write_file(dir / "upper.PLY", "PLY\n" + rest);
    write_file(dir / "s.wsd", std::string(kHead) + "mesh { file \"upper.PLY\" }\n");
    RunResult r = run_wsd(dir, "check s.wsd");
    CHECK(r.status == 1);
    CHECK(r.err.find("s.wsd:4:13: error: upper.PLY:1: not a PLY file: its first line is not 'ply'") !=
          std::string::npos);
    CHECK(r.err.find("OBJ") == std::string::npos);
    // Blanks after "ply" are allowed, as after any header keyword.
    write_file(dir / "blank.ply", "ply \n" + rest);
    write_file(dir / "t.wsd",
               std::string(kHead) + "mesh { file \"blank.ply\"  material { color <1, 1, 1> } }\n");
    r = run_wsd(dir, "check t.wsd");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(r.out.find("1 triangle") != std::string::npos);
}
