// The process's resident memory, for benchmarks that report what a phase needed at its peak:
// reset the peak, note what is resident, run the phase, then read the peak
// (wsd::app::peak_memory_bytes). Linux /proc; elsewhere the figures are unknown.
#pragma once

#include <cstdlib>
#include <fstream>
#include <string>

namespace wsd::bench {

// VmRSS (resident memory now) in bytes, or -1 when /proc is unavailable.
inline long long resident_bytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::atoll(line.c_str() + 6) * 1024;
    return -1;
}

// Resets VmHWM (the peak) to the current resident memory (Linux ≥ 4.0), so that a phase's peak
// is its own; false where it cannot.
inline bool reset_peak_memory() {
    std::ofstream clear("/proc/self/clear_refs");
    return static_cast<bool>(clear << "5" << std::flush);
}

}  // namespace wsd::bench
