// The scene's memory while it loads: however it grows (objects made one by one in a loop, lists,
// strings), the interpreter checks, every 16,384 loop iterations and calls once the process has
// grown by 16 MiB, that the machine can still give more, and stops the scene with an error
// before the kernel's OOM killer would stop the process. The build's own need is estimated once
// the scene is complete (render/memory_budget.h).
#include "lang/interpreter.h"
#include "render/memory_budget.h"

namespace wsd::lang {

namespace {

// Memory a check keeps free to the system when the figure is the machine's (MemAvailable or a
// cgroup's limit): others need some, and a scene that has come this close is stopped in time.
constexpr size_t kMemoryMargin = size_t{256} << 20;
// How many of the last interval's growth must still fit: the interval is a count of steps, and
// steps may take more memory as the scene grows.
constexpr size_t kIntervalsAhead = 2;
// And a share of what the scene has taken: the containers that hold what it made grow by
// doubling, and a doubling holds the old copy and the new at once (on a loop of spheres, the
// resident memory rose by a third in one step).
constexpr size_t kGrowthShare = 2;  // grown / kGrowthShare
constexpr size_t kCheckGrowth = size_t{16} << 20;

}  // namespace

bool Interpreter::memory_left(Span at) {
    // The resident memory is cheap to read; what the machine can give is read once the scene
    // has grown by kCheckGrowth since it was last read.
    const size_t now = render::resident_bytes();
    if (now < resident_at_check_ + kCheckGrowth) return true;
    const size_t grown = now > resident_at_start_ ? now - resident_at_start_ : 0;
    const size_t interval = now - resident_at_check_;
    resident_at_check_ = now;
    const render::MemoryAvailable available = render::available_memory();
    // A malformed WSD_MAX_MEMORY is reported by the load's own check, once the scene is complete.
    if (!available.error.empty() || !available.bytes) return true;
    // WSD_MAX_MEMORY counts from the start of the load; the machine's figures fall by themselves.
    size_t left = *available.bytes;
    if (available.fixed) left = left > grown ? left - grown : 0;
    const size_t need =
        (available.fixed ? 0 : kMemoryMargin) + kIntervalsAhead * interval + grown / kGrowthShare;
    if (left >= need) return true;
    Diagnostic& d =
        diags_.error(at, "out of memory while loading: the scene has taken " + render::memory_text(grown) +
                             " so far, and the " + render::memory_text(left) + " left of " +
                             available.source + " would not hold much more");
    d.help.push_back(
        "the loop or call here makes what takes the memory; a mesh, or `object` instances of one "
        "group, hold many shapes in far less");
    abort();
    return false;
}

}  // namespace wsd::lang
