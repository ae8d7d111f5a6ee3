// A scene that does not fit in memory is refused before its build, with both figures and at the
// shape that needs the most; the estimate counts a mesh's triangles, and a prototype once however
// many instances use it.
#include "render/memory_budget.h"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app_test_util.h"

using namespace wsd::test;
using namespace wsd::render;

namespace {

ShapeSpec mesh_shape(size_t triangles) {
    auto mesh = std::make_shared<MeshData>();
    mesh->vertices.assign(triangles + 2, glm::vec3(0));
    mesh->faces.assign(triangles, glm::uvec3(0, 1, 2));
    ShapeSpec s;
    s.kind = ShapeKind::Mesh;
    s.mesh = mesh;
    return s;
}

// 2^24 instances through groups of groups, made while the scene is evaluated (the object
// statement is line 6).
const char* const kNestedInstances =
    "camera { position <0, 0, -3>  look_at <0, 0, 0> }\nlight point { position <2, 3, -4> }\n"
    "let t = mesh { vertices [<0, 0, 0>, <1, 0, 0>, <0, 1, 0>]  faces [<0, 1, 2>]  material { } }\n"
    "let a = group { for i in 0 .. 4096 { object t { translate <i, 0, 0> } } }\n"
    "let b = group { for j in 0 .. 4096 { object a { translate <0, j, 0> } } }\n"
    "object b { }\n";

}  // namespace

TEST_CASE("the memory estimate grows with triangles and counts a prototype once", "[memory]") {
    SceneSpec small, large;
    small.shapes.push_back(mesh_shape(1000));
    large.shapes.push_back(mesh_shape(1000000));
    const MemoryEstimate a = estimate_memory(small), b = estimate_memory(large);
    CHECK(a.primitives == 1000);
    CHECK(b.primitives == 1000000);
    CHECK(b.bytes - a.bytes > 999000u * 100u);  // at least 100 bytes a triangle
    CHECK(b.bytes - a.bytes < 999000u * 400u);

    SceneSpec instanced;
    instanced.prototypes.push_back(PrototypeSpec{{mesh_shape(1000000)}, 0});
    for (int i = 0; i < 1000; ++i) {
        ShapeSpec inst;
        inst.kind = ShapeKind::Instance;
        inst.prototype = 0;
        instanced.shapes.push_back(inst);
    }
    const MemoryEstimate c = estimate_memory(instanced);
    CHECK(c.instances == 1000);
    CHECK(c.primitives == 1000000);
    CHECK(c.bytes < b.bytes + 1000u * 1024u);
    CHECK(c.largest_shape == 0);
}

TEST_CASE("a scene bigger than the memory it may use is refused before it is built", "[memory][e2e]") {
    TempDir dir;
    fs::copy_file(fs::path(WSD_SOURCE_DIR) / "examples/models/torus.obj", dir.path() / "torus.obj");
    write_file(dir / "s.wsd",
               "settings { width 40  height 30 }\ncamera { position <0, 2, -4>  look_at <0, 0, 0> }\n"
               "light point { position <3, 8, -5> }\nlet default_material = material { }\nsphere { center "
               "<0, 0, 0>  radius 0.1 }\n"
               "mesh { file \"torus.obj\" }\n");
    const RunResult refused = run_wsd(dir, "render s.wsd -o s.png", "WSD_MAX_MEMORY=100K");
    CHECK(refused.status != 0);
    CHECK(refused.err.find("s.wsd:6:13: error: the scene needs about ") != std::string::npos);
    CHECK(refused.err.find("more than the 100 KiB of WSD_MAX_MEMORY") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.path() / "s.png"));

    const RunResult bad = run_wsd(dir, "render s.wsd -o s.png", "WSD_MAX_MEMORY=lots");
    CHECK(bad.status != 0);
    CHECK(bad.err.find("WSD_MAX_MEMORY='lots' is not a size") != std::string::npos);

    const RunResult fits = run_wsd(dir, "render s.wsd -o s.png", "WSD_MAX_MEMORY=2G");
    INFO(fits.err);
    CHECK(fits.status == 0);
    CHECK(fs::exists(dir.path() / "s.png"));
}

TEST_CASE("running out of memory while the scene is evaluated is a scene error, not a crash",
          "[memory][e2e]") {
    // 2^24 instances through nested groups: expanded while the scene is evaluated, before the
    // memory estimate can count them. Under a 1.5 GB address-space limit the expansion fails.
    if (const char* s = std::getenv("WSD_SANITIZED"); s && std::string(s) == "1") {
        WARN("skipped: WSD_SANITIZED=1 (the sanitizers reserve more address space than the limit)");
        return;
    }
    TempDir dir;
    write_file(dir / "nest.wsd", kNestedInstances);
    const RunResult r = run_wsd(dir, "check nest.wsd", "ulimit -v 1500000;");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(r.err.find("nest.wsd: out of memory while loading the scene") != std::string::npos);
}

TEST_CASE("instances that cannot be held while the scene loads are refused before they are made",
          "[memory][e2e]") {
    // 2^24 instances (8 GiB of shape records) against a 1 GiB budget: refused at the object
    // statement that adds them, before any is made.
    TempDir dir;
    write_file(dir / "nest.wsd", kNestedInstances);
    const RunResult r = run_wsd(dir, "check nest.wsd", "WSD_MAX_MEMORY=1G");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(r.err.find("nest.wsd:6:1: error: the scene's 16777216 instances need about") != std::string::npos);
    CHECK(r.err.find("of WSD_MAX_MEMORY") != std::string::npos);
}

TEST_CASE("a loop that makes more than the memory it may use is stopped while the scene loads",
          "[memory][e2e]") {
    // A million spheres, about 2 GB while the scene loads and never instances: the check every
    // few thousand iterations stops the loop once 64 MiB are nearly taken.
    TempDir dir;
    const std::string scene =
        "camera { position <0, 0, -3>  look_at <0, 0, 0> }\nlight point { position <2, 3, -4> }\n"
        "let n = 1000000\n"
        "for i in 0 .. n { sphere { center <i, 0, 0>  radius 0.4  material { color <1, 1, 1> } } }\n";
    write_file(dir / "many.wsd", scene);
    const RunResult r = run_wsd(dir, "render many.wsd -o many.png", "WSD_MAX_MEMORY=64M");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(r.err.find("many.wsd:4:1: error: out of memory while loading: the scene has taken ") !=
          std::string::npos);
    CHECK(r.err.find(" left of WSD_MAX_MEMORY would not hold much more") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.path() / "many.png"));

    // A thousand fit, and so does a loop of many steps that keeps nothing.
    std::string small = scene;
    small.replace(small.find("1000000"), 7, "1000");
    write_file(dir / "small.wsd", small);
    const RunResult fits = run_wsd(dir, "check small.wsd", "WSD_MAX_MEMORY=64M");
    INFO(fits.err);
    CHECK(fits.status == 0);
    // Under the sanitizers freed memory is held back (ASan's quarantine), and counts as taken.
    if (const char* s = std::getenv("WSD_SANITIZED"); s && std::string(s) == "1") return;
    write_file(dir / "steps.wsd",
               "camera { position <0, 0, -3>  look_at <0, 0, 0> }\nlight point { position <2, 3, -4> }\n"
               "for i in 0 .. 200000 { let t = [i, i + 1, i + 2] }\n"
               "sphere { center <0, 0, 0>  radius 1  material { } }\n");
    const RunResult steps = run_wsd(dir, "check steps.wsd", "WSD_MAX_MEMORY=64M");
    INFO(steps.err);
    CHECK(steps.status == 0);
}

TEST_CASE("the memory a process's cgroups still allow is the tightest of their limits", "[memory]") {
    TempDir dir;
    const fs::path root = dir.path();
    const auto put = [&](const fs::path& file, const std::string& text) {
        fs::create_directories(file.parent_path());
        write_file(file.string(), text);
    };
    // cgroup v2: a Slurm job's limit two levels above the task's cgroup, a looser one above it
    // and "max" below it.
    fs::create_directories(root / "system.slice/job_7/step_0/task_0");
    put(root / "system.slice/memory.max", "5000000\n");
    put(root / "system.slice/memory.current", "100\n");
    put(root / "system.slice/job_7/memory.max", "1000000\n");
    put(root / "system.slice/job_7/memory.current", "400000\n");
    put(root / "system.slice/job_7/step_0/memory.max", "max\n");
    put(root / "system.slice/job_7/step_0/memory.current", "399000\n");
    const std::string v2 = "0::/system.slice/job_7/step_0/task_0\n";
    CHECK(cgroup_memory_left(v2, root) == std::optional<size_t>(600000));
    // A tighter one nearer the task wins; a cgroup over its limit leaves nothing.
    put(root / "system.slice/job_7/step_0/memory.max", "399500\n");
    CHECK(cgroup_memory_left(v2, root) == std::optional<size_t>(500));
    put(root / "system.slice/job_7/step_0/memory.max", "300000\n");
    CHECK(cgroup_memory_left(v2, root) == std::optional<size_t>(0));
    // No limit anywhere, or a path that names no directory (a container that mounts its own
    // cgroup as the root): the root's files.
    CHECK_FALSE(cgroup_memory_left("0::/\n", root).has_value());
    put(root / "memory.max", "2048\n");
    put(root / "memory.current", "48\n");
    CHECK(cgroup_memory_left("0::/elsewhere/x\n", root) == std::optional<size_t>(2000));

    // cgroup v1: the memory controller's own hierarchy, whose "no limit" is a huge number.
    put(root / "memory/memory.limit_in_bytes", "9223372036854771712\n");
    put(root / "memory/slurm/uid_0/job_9/memory.limit_in_bytes", "3000\n");
    put(root / "memory/slurm/uid_0/job_9/memory.usage_in_bytes", "1000\n");
    fs::create_directories(root / "memory/slurm/uid_0/job_9/step_batch");
    const std::string v1 =
        "12:pids:/slurm\n4:cpuacct,memory:/slurm/uid_0/job_9/step_batch\n1:name=systemd:/\n";
    CHECK(cgroup_memory_left(v1, root) == std::optional<size_t>(2000));
    CHECK_FALSE(cgroup_memory_left("4:cpu:/a\n", root).has_value());
}
