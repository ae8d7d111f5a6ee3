// The signal guard: async-signal-safe handlers that store into a lock-free atomic and a
// sig_atomic_t, nothing else.
#include "app/signals.h"

#include <csignal>

#include "app/exit_codes.h"

namespace wsd::app {

namespace {

std::atomic<bool> cancel_flag{false};
volatile std::sig_atomic_t received_signal = 0;
struct sigaction previous_int, previous_term;

extern "C" void on_signal(int signal_number) {
    received_signal = signal_number;
    cancel_flag.store(true);
}

}  // namespace

CancelOnSignal::CancelOnSignal() {
    static_assert(std::atomic<bool>::is_always_lock_free);
    cancel_flag.store(false);
    received_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;
    sigaction(SIGINT, &action, &previous_int);
    sigaction(SIGTERM, &action, &previous_term);
}

CancelOnSignal::~CancelOnSignal() {
    sigaction(SIGINT, &previous_int, nullptr);
    sigaction(SIGTERM, &previous_term, nullptr);
}

const std::atomic<bool>* CancelOnSignal::flag() const {
    return &cancel_flag;
}

bool CancelOnSignal::cancelled() const {
    return cancel_flag.load();
}

int CancelOnSignal::exit_status() const {
    if (received_signal == SIGINT) return exit_code::sigint;
    if (received_signal == SIGTERM) return exit_code::sigterm;
    return 0;
}

}  // namespace wsd::app
