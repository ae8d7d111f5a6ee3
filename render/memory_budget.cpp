#include "render/memory_budget.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
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

std::optional<size_t> read_number_file(const char* path) {
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
    if (auto max = read_number_file("/sys/fs/cgroup/memory.max")) {
        const size_t current = read_number_file("/sys/fs/cgroup/memory.current").value_or(0);
        cap(*max > current ? *max - current : 0, "the cgroup's memory limit");
    }
    if (const char* env = std::getenv("WSD_MAX_MEMORY"); env && *env) {
        if (auto limit = parse_size(env))
            cap(*limit, "WSD_MAX_MEMORY");
        else
            a.error =
                std::string("WSD_MAX_MEMORY='") + env + "' is not a size (bytes, or a number with K, M or G)";
    }
    return a;
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
