// run_on_large_stack: a joinable POSIX thread with an explicit stack size (std::thread has no way
// to set one).
#include "lang/large_stack.h"

#include <pthread.h>

#include <exception>

namespace wsd::lang {

namespace {

struct Job {
    const std::function<void()>* task;
    std::exception_ptr error;
};

void* run_job(void* arg) {
    auto* job = static_cast<Job*>(arg);
    try {
        (*job->task)();
    } catch (...) {
        job->error = std::current_exception();
    }
    return nullptr;
}

bool run_on_thread(Job& job, size_t stack_bytes) {
    pthread_attr_t attr;
    if (pthread_attr_init(&attr) != 0) return false;
    pthread_t thread;
    const bool started = pthread_attr_setstacksize(&attr, stack_bytes) == 0 &&
                         pthread_create(&thread, &attr, run_job, &job) == 0;
    pthread_attr_destroy(&attr);
    if (started) pthread_join(thread, nullptr);
    return started;
}

}  // namespace

void run_on_large_stack(const std::function<void()>& task) {
    Job job{&task, nullptr};
    constexpr size_t kSmallest = size_t(256) << 20;
    bool ran = false;
    for (size_t bytes = kEvaluatorStackBytes; !ran && bytes >= kSmallest; bytes /= 2)
        ran = run_on_thread(job, bytes);
    if (!ran) task();
    if (job.error) std::rethrow_exception(job.error);
}

}  // namespace wsd::lang
