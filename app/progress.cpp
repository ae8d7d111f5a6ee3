// The progress reporter: rate-limited, so a render that reports every tile does not spend its
// time printing; the bar is redrawn in place with '\r' and cleared by finish().
#include "app/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>

namespace wsd::app {

namespace {

constexpr double bar_interval = 0.1;   // seconds between redraws on a terminal
constexpr double line_interval = 5.0;  // seconds between lines otherwise
constexpr int bar_width = 30;

std::string format_rate(double per_second) {
    char buf[32];
    if (per_second >= 1e6)
        std::snprintf(buf, sizeof buf, "%.2f Mrays/s", per_second / 1e6);
    else if (per_second >= 1e3)
        std::snprintf(buf, sizeof buf, "%.1f krays/s", per_second / 1e3);
    else
        std::snprintf(buf, sizeof buf, "%.0f rays/s", per_second);
    return buf;
}

}  // namespace

ProgressMode progress_mode(bool quiet) {
    if (quiet) return ProgressMode::None;
    return ::isatty(STDERR_FILENO) ? ProgressMode::Bar : ProgressMode::Lines;
}

std::string format_duration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    const long total = std::lround(seconds);
    char buf[32];
    if (total >= 3600)
        std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
    else
        std::snprintf(buf, sizeof buf, "%ld:%02ld", total / 60, total % 60);
    return buf;
}

ProgressReporter::ProgressReporter(ProgressMode mode, std::string label,
                                   std::chrono::steady_clock::time_point run_start)
    : mode_(mode),
      label_(std::move(label)),
      start_(run_start),
      rate_start_(std::chrono::steady_clock::now()),
      last_print_(run_start) {}  // a run of short frames still prints a line every few seconds

void ProgressReporter::update(double fraction, const render::RayStats& so_far) {
    if (mode_ == ProgressMode::None) return;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_) return;
    last_fraction_ = fraction;
    last_rays_ = so_far.ray_queries();
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last_print_).count();
    if (since < (mode_ == ProgressMode::Bar ? bar_interval : line_interval)) return;
    last_print_ = now;
    print(fraction, last_rays_, false);
}

void ProgressReporter::finish(bool completed) {
    if (mode_ == ProgressMode::None) return;
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
    if (mode_ == ProgressMode::Bar && printed_) {
        print(completed ? 1.0 : last_fraction_, last_rays_, completed);
        std::cerr << '\n' << std::flush;
    }
}

void ProgressReporter::print(double fraction, uint64_t rays, bool final_update) {
    fraction = std::fmin(std::fmax(fraction, 0.0), 1.0);
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : -1;
    const double rendering = std::chrono::duration<double>(now - rate_start_).count();
    const double rate = rendering > 0 ? static_cast<double>(rays) / rendering : 0;
    char percent[16];
    std::snprintf(percent, sizeof percent, "%3.0f%%", 100 * fraction);
    if (mode_ == ProgressMode::Bar) {
        const int filled = static_cast<int>(fraction * bar_width);
        std::string bar(static_cast<size_t>(filled), '#');
        bar.resize(bar_width, '.');
        std::cerr << '\r' << label_ << " [" << bar << "] " << percent << "  elapsed "
                  << format_duration(elapsed) << "  ETA "
                  << (final_update ? std::string("0:00") : format_duration(eta)) << "  " << format_rate(rate)
                  << "   " << std::flush;
    } else {
        std::cerr << label_ << ": " << percent << " done, elapsed " << format_duration(elapsed) << ", ETA "
                  << format_duration(eta) << ", " << format_rate(rate) << '\n'
                  << std::flush;
    }
    printed_ = true;
}

}  // namespace wsd::app
