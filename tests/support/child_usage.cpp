// Test support (child_usage.h): fork, run, wait4 for the child's rusage.
#include "tests/support/child_usage.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>

namespace hlod::test {

ChildUsage runInChild(const std::function<void()>& work) {
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        try {
            work();
            _exit(0);  // no destructor of the parent's objects runs in the child
        } catch (const std::exception& e) {
            std::fprintf(stderr, "failed: %s\n", e.what());
            _exit(1);
        }
    }
    ChildUsage c;
    if (pid < 0) return c;
    int status = 0;
    rusage usage{};
    wait4(pid, &status, 0, &usage);
    c.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    c.cpu = usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
    c.peakRss = static_cast<uint64_t>(usage.ru_maxrss) * 1024;
    c.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    return c;
}

}  // namespace hlod::test
