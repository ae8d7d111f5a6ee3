// SIGINT/SIGTERM during a render: the handler only sets the render's cancel flag and remembers
// the signal, so the render stops cleanly and the command removes its partial output and exits
// with 130 or 143. The previous handlers come back when the guard is destroyed.
#pragma once

#include <atomic>

namespace wsd::app {

class CancelOnSignal {
public:
    CancelOnSignal();
    ~CancelOnSignal();
    CancelOnSignal(const CancelOnSignal&) = delete;
    CancelOnSignal& operator=(const CancelOnSignal&) = delete;

    const std::atomic<bool>* flag() const;
    bool cancelled() const;
    int exit_status() const;  // 130 for SIGINT, 143 for SIGTERM, 0 if no signal came
};

}  // namespace wsd::app
