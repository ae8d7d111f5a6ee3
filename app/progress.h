// Render progress on stderr: a redrawn bar (percent, elapsed, ETA, rays/s) when stderr is a
// terminal, one plain line every few seconds otherwise, nothing when quiet. Safe to call from
// any render thread; updates that arrive while another is being printed are dropped.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

#include "render/stats.h"

namespace wsd::app {

enum class ProgressMode { None, Bar, Lines };

// Bar when stderr is a terminal, Lines otherwise, None when quiet.
ProgressMode progress_mode(bool quiet);

// "1:05" / "1:02:03" for a duration in seconds.
std::string format_duration(double seconds);

class ProgressReporter {
public:
    // `run_start`: when the run began (earlier than now for a frame of an animation); the elapsed
    // time and the ETA are the run's, and update() takes the run's fraction. Rays/s count from now.
    ProgressReporter(ProgressMode mode, std::string label,
                     std::chrono::steady_clock::time_point run_start = std::chrono::steady_clock::now());
    void update(double fraction, const render::RayStats& so_far);
    void finish(bool completed = true);  // ends the bar's line (at 100% if completed); idempotent

private:
    void print(double fraction, uint64_t rays, bool final_update);

    ProgressMode mode_;
    std::string label_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point rate_start_;
    std::chrono::steady_clock::time_point last_print_;
    std::mutex mutex_;
    bool printed_ = false;
    bool finished_ = false;
    double last_fraction_ = 0;
    uint64_t last_rays_ = 0;
};

}  // namespace wsd::app
