// TBB tasks as ThreadSanitizer sees them: libtbb is not instrumented, so TSan misses the
// synchronisation of a task's start with the thread that spawned it and of its end with the
// thread that waits for it, and reports the data they share as races. Under -fsanitize=thread
// (HLOD_TSAN) a task body calls taskBegin() first and taskEnd() last, and the thread that
// spawns tasks calls taskEnd() once their functors exist and taskBegin() after the wait: a
// release and an acquire on one address (one for all tasks, reachable without a capture: a
// task that starts after another ended is ordered after it; tasks that overlap are not, so
// races between them are still reported). scripts/tsan.supp covers TBB's own internals.
// Without TSan these are no-ops.
#pragma once

#include <tbb/parallel_for.h>

#include <cstddef>

#if defined(__SANITIZE_THREAD__)
extern "C" void __tsan_acquire(void* address);
extern "C" void __tsan_release(void* address);
#endif

namespace hlod {

inline char tbbTasks = 0;  // the address TSan synchronises on
inline void taskBegin() {
#if defined(__SANITIZE_THREAD__)
    __tsan_acquire(&tbbTasks);
#endif
}
inline void taskEnd() {
#if defined(__SANITIZE_THREAD__)
    __tsan_release(&tbbTasks);
#endif
}

// tbb::parallel_for over [0, n), one index per task, its tasks ordered (for TSan) after the call
// and before its return.
template <class Body>
void parallelFor(size_t n, const Body& body) {
    const auto task = [&body](size_t i) {
        taskBegin();
        body(i);
        taskEnd();
    };
    taskEnd();
    tbb::parallel_for(size_t{0}, n, size_t{1}, task);
    taskBegin();
}

}  // namespace hlod
