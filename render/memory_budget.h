// Memory before a build: what a scene will need once built (its geometry, tree and frame buffer,
// with the build's temporaries), estimated from its spec before anything is allocated, and what
// the machine can still give. A scene that does not fit is refused with both numbers instead of
// meeting the kernel's OOM killer halfway through its build or render.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "render/scene_spec.h"

namespace wsd::render {

struct MemoryEstimate {
    size_t bytes = 0;       // the peak the build and render add to what the spec already holds
    size_t primitives = 0;  // stored primitives (a mesh's triangles one by one, prototypes once)
    size_t instances = 0;
    size_t pixels = 0;
    size_t largest_shape = 0;        // index into spec.shapes of the shape that needs the most
    size_t largest_shape_bytes = 0;  // (a prototype's share is counted at its first instance)
};

MemoryEstimate estimate_memory(const SceneSpec& spec);

// Bytes this process may still allocate: /proc/meminfo's MemAvailable, capped by the limits of
// its cgroups (cgroup_memory_left), and by WSD_MAX_MEMORY (bytes, or with a K, M or G suffix)
// when set. `bytes` is nullopt when none of them can be read; `source` names the one that decided
// ("available memory", "the cgroup's memory limit", "WSD_MAX_MEMORY"); `error` is set when
// WSD_MAX_MEMORY is malformed.
struct MemoryAvailable {
    std::optional<size_t> bytes;
    std::string source;
    std::string error;
    // WSD_MAX_MEMORY decided: a fixed figure, which does not fall as this process allocates (the
    // others do).
    bool fixed = false;
};
MemoryAvailable available_memory();

// What the memory limits of a process's cgroups still allow, the tightest of them, or nullopt
// where none is set: its own cgroup's and every ancestor's up to the mount's root (a Slurm job's
// limit sits above the step and task cgroups its processes are in), memory.max less
// memory.current under cgroup v2, memory.limit_in_bytes less memory.usage_in_bytes under v1.
// self_cgroup: the text of /proc/self/cgroup; root: where the hierarchies are mounted
// (/sys/fs/cgroup, with v1's memory controller in root/memory).
std::optional<size_t> cgroup_memory_left(const std::string& self_cgroup, const std::filesystem::path& root);

// This process's resident memory in bytes (/proc/self/statm), or 0 where it cannot be read.
size_t resident_bytes();

// "1.5 GiB", "312 MiB": a byte count for messages.
std::string memory_text(size_t bytes);

}  // namespace wsd::render
