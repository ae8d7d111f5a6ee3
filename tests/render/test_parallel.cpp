// parallel_for: every index runs exactly once whatever the thread count, a body's exception
// reaches the caller, cancellation stops it early, and progress polling happens while it runs.
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "render/parallel.h"

using wsd::render::parallel_for;
using wsd::render::ParallelOptions;

namespace {

ParallelOptions with_threads(int n) {
    ParallelOptions o;
    o.threads = n;
    return o;
}

// A value that depends only on the index.
uint64_t mix(size_t i) {
    uint64_t x = i * 0x9e3779b97f4a7c15ull;
    x ^= x >> 31;
    return x * 0xbf58476d1ce4e5b9ull;
}

}  // namespace

TEST_CASE("parallel_for runs every index exactly once on any number of threads", "[parallel]") {
    for (const int threads : {1, 2, 3, 8}) {
        CAPTURE(threads);
        const size_t count = 1000;
        std::vector<std::atomic<int>> runs(count);
        const int most = wsd::render::thread_count(threads);
        std::vector<std::atomic<int>> busy(size_t(most) + 1);
        std::atomic<bool> overlap{false}, bad_worker{false};
        const bool complete = parallel_for(count, with_threads(threads), [&](size_t i, int worker) {
            if (worker < 0 || worker >= most) {
                bad_worker = true;
                return;
            }
            if (busy[size_t(worker)].fetch_add(1) != 0) overlap = true;  // one body per worker at a time
            runs[i].fetch_add(1);
            busy[size_t(worker)].fetch_sub(1);
        });
        CHECK(complete);
        CHECK_FALSE(bad_worker);
        CHECK_FALSE(overlap);
        size_t once = 0;
        for (const auto& r : runs) once += r.load() == 1;
        CHECK(once == count);
    }
}

TEST_CASE("parallel_for's results depend on the index alone, not on the thread count", "[parallel]") {
    auto run = [](int threads) {
        std::vector<uint64_t> out(777);
        parallel_for(out.size(), with_threads(threads), [&](size_t i, int) { out[i] = mix(i); });
        return out;
    };
    const auto one = run(1);
    CHECK(run(2) == one);
    CHECK(run(5) == one);
    CHECK(one[776] == mix(776));
}

TEST_CASE("parallel_for over nothing runs no body and is complete", "[parallel]") {
    int calls = 0;
    CHECK(parallel_for(0, with_threads(4), [&](size_t, int) { ++calls; }));
    CHECK(calls == 0);
}

TEST_CASE("an exception thrown by a body reaches the caller, and the loop stops early", "[parallel]") {
    // Indices after the failing one wait until it has started, so no scheduling order lets the
    // other threads run through the range first; with ten million indices, a loop that did not
    // stop would run them all.
    constexpr size_t count = 10'000'000;
    for (const int threads : {1, 3}) {
        CAPTURE(threads);
        std::atomic<size_t> ran{0};
        std::atomic<bool> reached{false};
        auto throwing = [&](size_t i, int) {
            ran.fetch_add(1);
            if (i == 5) {
                reached = true;
                throw std::runtime_error("tile 5 failed");
            }
            if (i > 5)
                while (!reached.load()) std::this_thread::yield();
        };
        CHECK_THROWS_WITH(parallel_for(count, with_threads(threads), throwing), "tile 5 failed");
        CHECK(ran.load() >= 6);
        CHECK(ran.load() < count);
    }
}

TEST_CASE("cancellation stops parallel_for early and is reported", "[parallel]") {
    SECTION("set before the start: no index runs") {
        std::atomic<bool> cancel{true};
        ParallelOptions o = with_threads(2);
        o.cancel = &cancel;
        int calls = 0;
        CHECK_FALSE(parallel_for(100, o, [&](size_t, int) { ++calls; }));
        CHECK(calls == 0);
    }
    SECTION("set by a body: the others stop after their current index") {
        for (const int threads : {1, 2, 4}) {
            CAPTURE(threads);
            std::atomic<bool> cancel{false};
            ParallelOptions o = with_threads(threads);
            o.cancel = &cancel;
            std::atomic<size_t> ran{0};
            // Indices after 10 wait for the flag, so each thread holds at most one of them when
            // it is set, whatever the scheduling.
            const bool complete = parallel_for(100000, o, [&](size_t i, int) {
                ran.fetch_add(1);
                if (i == 10) cancel = true;
                if (i > 10)
                    while (!cancel.load()) std::this_thread::yield();
            });
            CHECK_FALSE(complete);
            CHECK(ran.load() <= 11 + size_t(threads));
        }
    }
    SECTION("set after the last index: complete") {
        std::atomic<bool> cancel{false};
        ParallelOptions o = with_threads(2);
        o.cancel = &cancel;
        // Index 2 is taken after 0 and 1, so every index has started when the flag is set.
        CHECK(parallel_for(3, o, [&](size_t i, int) {
            if (i == 2) cancel = true;
        }));
    }
}

TEST_CASE("parallel_for polls progress on the calling thread while bodies run", "[parallel]") {
    std::atomic<int> polls{0};
    ParallelOptions o = with_threads(2);
    o.poll_interval = std::chrono::milliseconds(1);
    o.poll = [&] { polls.fetch_add(1); };
    // The first body waits for a poll, so the test hangs (ctest's timeout) if none comes.
    parallel_for(4, o, [&](size_t i, int) {
        if (i == 0)
            while (polls.load() == 0) std::this_thread::yield();
    });
    CHECK(polls.load() >= 1);
}

TEST_CASE("parallel_chunks cuts [0, count) into the same fixed chunks on any number of threads",
          "[parallel]") {
    for (size_t count : {size_t(0), size_t(1), size_t(7), size_t(8), size_t(9), size_t(100)}) {
        for (int threads : {1, 2, 3}) {
            INFO("count " << count << " threads " << threads);
            std::vector<std::atomic<int>> seen(count);
            const size_t chunks = (count + 7) / 8;
            std::vector<std::pair<size_t, size_t>> ranges(chunks);
            std::atomic<int> calls{0};
            wsd::render::parallel_chunks(count, 8, threads,
                                         [&](size_t c, size_t begin, size_t end, int worker) {
                                             CHECK(worker >= 0);
                                             CHECK(worker < threads);
                                             ranges[c] = {begin, end};
                                             for (size_t i = begin; i < end; ++i) seen[i].fetch_add(1);
                                             calls.fetch_add(1);
                                         });
            CHECK(size_t(calls.load()) == chunks);
            for (size_t c = 0; c < chunks; ++c) {
                CHECK(ranges[c].first == c * 8);
                CHECK(ranges[c].second == std::min(count, c * 8 + 8));
            }
            for (size_t i = 0; i < count; ++i) CHECK(seen[i].load() == 1);
        }
    }
}
