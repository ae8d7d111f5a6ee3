// parallel_for: runs a body once for every index of [0, count) on a pool of threads that it
// starts and joins, and owns what every parallel loop needs besides the work itself:
// - indices are taken in increasing order from a shared counter, so any index may run on any
//   thread; results that must not depend on the thread count may depend only on the index;
// - `worker` (in [0, threads)) names the thread running the body, for per-thread state that the
//   caller keeps (never two bodies with the same worker at once);
// - the first exception a body throws is rethrown on the calling thread once every thread has
//   stopped; no index starts after it;
// - cancellation: no index starts once `*cancel` is seen set (running bodies finish);
// - progress: while the threads run, the calling thread calls `poll` every `poll_interval`.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>

namespace wsd::render {

struct ParallelOptions {
    int threads = 0;                            // 0 = all cores
    const std::atomic<bool>* cancel = nullptr;  // may be null
    std::function<void()> poll;                 // may be empty
    std::chrono::milliseconds poll_interval{250};
};

// The number of threads `requested` means (0 = all cores), at least 1: an upper bound of the
// `worker` values any parallel_for with that request passes.
int thread_count(int requested);

// Runs body(index, worker) for every index in [0, count). Returns true when every index ran,
// false when cancellation stopped it early. Rethrows a body's exception.
bool parallel_for(size_t count, const ParallelOptions& options,
                  const std::function<void(size_t index, int worker)>& body);

// Runs body(chunk, begin, end, worker) for the fixed chunks [k·size, min(count, (k + 1)·size))
// of [0, count), on `threads` threads (0 = all cores); a single chunk runs on the calling
// thread. The chunks do not depend on the thread count, so neither do results kept per chunk
// and merged in chunk order.
void parallel_chunks(size_t count, size_t size, int threads,
                     const std::function<void(size_t chunk, size_t begin, size_t end, int worker)>& body);

}  // namespace wsd::render
