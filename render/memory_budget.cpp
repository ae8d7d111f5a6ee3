#include "render/memory_budget.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "render/geometry_impl.h"
#include "render/instance_prims.h"

namespace wsd::render {

namespace {

// Peak bytes per stored primitive for its tree: the build's bounds, references and binary nodes
// (temporaries), then the wide nodes and the leaf order that stay (a mesh's order is dropped
// after the build, so its peak still holds it). With the triangle's own record
// and vertices this makes about 154 bytes a triangle, against 106 measured (`--stats` peak memory
// of a 10^6-triangle mesh less a 9·10^4-triangle one, less the mesh data and file read before
// the build): a margin, so that a scene refused would not have fitted.
constexpr size_t kTreeBytes = 128;
// A triangle as stored, beside its share of the tree; a mesh vertex in world space.
constexpr size_t kTriangleBytes = sizeof(TriPrim) + sizeof(uint32_t);
constexpr size_t kVertexBytes = sizeof(Vec3f);
// Any other primitive (spheres, boxes, quadrics, CSG solids): the largest of their records.
constexpr size_t kOtherBytes = 256;
constexpr size_t kInstanceBytes = sizeof(InstancePrim) + sizeof(Transform);
// A pixel: the float frame buffer, the adaptive prepass and the encoded output.
constexpr size_t kPixelBytes = 64;

size_t shape_bytes(const ShapeSpec& s, MemoryEstimate& e) {
    switch (s.kind) {
        case ShapeKind::Mesh: {
            if (!s.mesh) return 0;
            e.primitives += s.mesh->faces.size();
            return s.mesh->faces.size() * (kTriangleBytes + kTreeBytes) +
                   s.mesh->vertices.size() * kVertexBytes;
        }
        case ShapeKind::Csg: {
            size_t bytes = kOtherBytes + kTreeBytes;
            ++e.primitives;
            if (s.csg)
                for (const ShapeSpec& m : s.csg->members) bytes += shape_bytes(m, e);
            return bytes;
        }
        case ShapeKind::Instance:
            ++e.instances;
            return kInstanceBytes + kTreeBytes;
        default:
            ++e.primitives;
            return kOtherBytes + kTreeBytes;
    }
}

std::optional<size_t> read_number_file(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::string word;
    if (!(in >> word) || word == "max") return std::nullopt;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(word.c_str(), &end, 10);
    if (end == word.c_str() || *end) return std::nullopt;
    return static_cast<size_t>(v);
}

std::optional<size_t> mem_available() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    unsigned long long kb = 0;
    std::string unit;
    while (in >> key >> kb >> unit)
        if (key == "MemAvailable:") return static_cast<size_t>(kb) * 1024;
    return std::nullopt;
}

// "4G", "512M", "1000000": bytes; nullopt when malformed.
std::optional<size_t> parse_size(const char* text) {
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text || !(v >= 0)) return std::nullopt;
    double scale = 1;
    if (*end == 'K' || *end == 'k')
        scale = 1024.0, ++end;
    else if (*end == 'M' || *end == 'm')
        scale = 1024.0 * 1024, ++end;
    else if (*end == 'G' || *end == 'g')
        scale = 1024.0 * 1024 * 1024, ++end;
    if (*end) return std::nullopt;
    const double bytes = v * scale;
    if (!(bytes < 1.8e19)) return std::nullopt;
    return static_cast<size_t>(bytes);
}

}  // namespace

MemoryEstimate estimate_memory(const SceneSpec& spec) {
    MemoryEstimate e;
    std::vector<bool> counted(spec.prototypes.size(), false);
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const ShapeSpec& s = spec.shapes[i];
        size_t bytes = shape_bytes(s, e);
        if (s.kind == ShapeKind::Instance && s.prototype < counted.size() && !counted[s.prototype]) {
            counted[s.prototype] = true;
            for (const ShapeSpec& member : spec.prototypes[s.prototype].shapes)
                bytes += shape_bytes(member, e);
        }
        e.bytes += bytes;
        if (bytes > e.largest_shape_bytes) {
            e.largest_shape_bytes = bytes;
            e.largest_shape = i;
        }
    }
    e.pixels = static_cast<size_t>(std::max(spec.settings.width, 0)) *
               static_cast<size_t>(std::max(spec.settings.height, 0));
    e.bytes += e.pixels * kPixelBytes;
    return e;
}

std::optional<size_t> cgroup_memory_left(const std::string& self_cgroup, const std::filesystem::path& root) {
    namespace fs = std::filesystem;
    // cgroup v1 writes "no limit" as the largest page count it can hold (about 2^63 bytes).
    constexpr size_t kNoLimit = size_t{1} << 62;
    std::optional<size_t> left;
    std::istringstream lines(self_cgroup);
    for (std::string line; std::getline(lines, line);) {
        // hierarchy-id:controllers:path
        const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string id = line.substr(0, a), controllers = line.substr(a + 1, b - a - 1);
        fs::path base;
        const char *max_file = nullptr, *current_file = nullptr;
        if (id == "0" && controllers.empty()) {  // v2: one unified hierarchy
            base = root, max_file = "memory.max", current_file = "memory.current";
        } else if (("," + controllers + ",").find(",memory,") != std::string::npos) {  // v1
            base = root / "memory", max_file = "memory.limit_in_bytes",
            current_file = "memory.usage_in_bytes";
        } else {
            continue;
        }
        const fs::path rel = fs::path(line.substr(b + 1)).relative_path();
        std::error_code ec;
        // A container may mount its own cgroup as the root, where the path names no directory.
        fs::path dir = rel.empty() || !fs::is_directory(base / rel, ec) ? base : base / rel;
        for (;;) {
            if (auto max = read_number_file(dir / max_file); max && *max < kNoLimit) {
                const size_t current = read_number_file(dir / current_file).value_or(0);
                const size_t l = *max > current ? *max - current : 0;
                if (!left || l < *left) left = l;
            }
            if (dir == base) break;
            dir = dir.parent_path();
        }
    }
    return left;
}

MemoryAvailable available_memory() {
    MemoryAvailable a;
    a.bytes = mem_available();
    if (a.bytes) a.source = "available memory";
    const auto cap = [&](size_t limit, const char* source) {
        if (!a.bytes || limit < *a.bytes) {
            a.bytes = limit;
            a.source = source;
        }
    };
    {
        std::ifstream in("/proc/self/cgroup");
        const std::string self((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (auto left = cgroup_memory_left(self, "/sys/fs/cgroup")) cap(*left, "the cgroup's memory limit");
    }
    if (const char* env = std::getenv("WSD_MAX_MEMORY"); env && *env) {
        if (auto limit = parse_size(env)) {
            cap(*limit, "WSD_MAX_MEMORY");
            a.fixed = a.source == "WSD_MAX_MEMORY";
        } else
            a.error =
                std::string("WSD_MAX_MEMORY='") + env + "' is not a size (bytes, or a number with K, M or G)";
    }
    return a;
}

size_t resident_bytes() {
    // read(2) rather than a stream: the interpreter asks often while a scene loads.
    const int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0;
    char buf[128];
    const ssize_t n = read(fd, buf, sizeof buf - 1);
    close(fd);
    if (n <= 0) return 0;
    buf[n] = '\0';
    unsigned long long size = 0, resident = 0;
    if (std::sscanf(buf, "%llu %llu", &size, &resident) != 2) return 0;
    const long page = sysconf(_SC_PAGESIZE);
    return static_cast<size_t>(resident) * static_cast<size_t>(page > 0 ? page : 4096);
}

std::string memory_text(size_t bytes) {
    char buf[32];
    const double mib = static_cast<double>(bytes) / (1024.0 * 1024.0);
    if (mib >= 1024)
        std::snprintf(buf, sizeof buf, "%.1f GiB", mib / 1024);
    else if (mib >= 1)
        std::snprintf(buf, sizeof buf, "%.0f MiB", mib);
    else
        std::snprintf(buf, sizeof buf, "%.0f KiB", static_cast<double>(bytes) / 1024.0);
    return buf;
}

}  // namespace wsd::render
