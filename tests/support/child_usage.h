// Test support for the benchmarks: runs a piece of work in a forked child process so that its
// peak RSS (ru_maxrss) is its own, not the larger of parent and child, and reports the child's
// wall time, CPU time (user + system) and peak RSS.
#pragma once

#include <cstdint>
#include <functional>

namespace hlod::test {

struct ChildUsage {
    double wall = 0, cpu = 0;  // seconds
    uint64_t peakRss = 0;      // bytes
    bool ok = false;           // `work` returned; an exception is printed ("failed: ...") and is not ok
};

ChildUsage runInChild(const std::function<void()>& work);

}  // namespace hlod::test
