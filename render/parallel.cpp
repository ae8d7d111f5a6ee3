// parallel_for: `threads` std::threads (never more than there are indices) take indices from an
// atomic counter; the calling thread waits on a condition variable, waking to poll progress, and
// joins them.
#include "render/parallel.h"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace wsd::render {

int thread_count(int requested) {
    const int n = requested > 0 ? requested : int(std::thread::hardware_concurrency());
    return std::max(n, 1);
}

bool parallel_for(size_t count, const ParallelOptions& options,
                  const std::function<void(size_t index, int worker)>& body) {
    const int threads = int(std::min(size_t(thread_count(options.threads)), std::max(count, size_t(1))));
    std::atomic<size_t> next{0}, done{0};
    std::atomic<bool> stop{false};  // a body threw
    std::mutex mutex;
    std::condition_variable finished;
    int running = threads;
    std::exception_ptr failure;
    auto cancelled = [&] { return options.cancel && options.cancel->load(std::memory_order_relaxed); };

    auto worker = [&](int id) {
        try {
            while (!stop.load(std::memory_order_relaxed) && !cancelled()) {
                const size_t i = next.fetch_add(1, std::memory_order_relaxed);
                if (i >= count) break;
                body(i, id);
                done.fetch_add(1, std::memory_order_relaxed);
            }
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!failure) failure = std::current_exception();
            stop = true;
        }
        std::lock_guard lock(mutex);
        --running;
        finished.notify_all();
    };

    std::vector<std::thread> pool;
    pool.reserve(size_t(threads));
    for (int i = 0; i < threads; ++i) pool.emplace_back(worker, i);
    {
        std::unique_lock lock(mutex);
        while (running > 0) {
            if (finished.wait_for(lock, options.poll_interval, [&] { return running == 0; })) break;
            if (options.poll) {
                lock.unlock();
                options.poll();
                lock.lock();
            }
        }
    }
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    return done.load() == count;
}

void parallel_chunks(size_t count, size_t size, int threads,
                     const std::function<void(size_t chunk, size_t begin, size_t end, int worker)>& body) {
    const size_t chunks = (count + size - 1) / size;
    auto run = [&](size_t c, int worker) { body(c, c * size, std::min(count, (c + 1) * size), worker); };
    if (chunks <= 1) {
        if (chunks == 1) run(0, 0);
        return;
    }
    ParallelOptions options;
    options.threads = threads;
    parallel_for(chunks, options, run);
}

}  // namespace wsd::render
