// The evaluator recurses over statements, expressions and user-function calls. Each is bounded
// (Limits::eval_depth levels per call, Limits::call_depth calls), but their product is far past a
// default thread stack, so evaluation runs on a thread of its own with a large stack. The stack
// is virtual memory: only the pages a deep recursion touches are ever committed.
#pragma once

#include <cstddef>
#include <functional>

namespace wsd::lang {

inline constexpr size_t kEvaluatorStackBytes = size_t(1) << 30;

// Runs `task` on a thread with a stack of kEvaluatorStackBytes (less if the system refuses that
// much, down to 256 MiB; on the calling thread if it refuses even that) and waits for it. An
// exception thrown by `task` is rethrown here.
void run_on_large_stack(const std::function<void()>& task);

}  // namespace wsd::lang
