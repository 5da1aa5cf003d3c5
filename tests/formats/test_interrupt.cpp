// Deferred interrupts (formats/interrupt.h), each run in a forked child: the child takes the
// signals as hlod's main does, defers them as `hlod view` does, and ends by the signal or exits 0.
#include "formats/interrupt.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace hlod {
namespace {

// The child's end: the signal that ended it, or -(exit status) when it exited.
int childEnd(bool signalBeforeResume) {
    const pid_t pid = fork();
    if (pid == 0) {
        removeTemporariesOnInterrupt();
        deferInterrupts();
        if (signalBeforeResume) {
            kill(getpid(), SIGTERM);
            for (int i = 0; i < 5000 && !interruptedBy(); ++i) usleep(1000);
            if (interruptedBy() != SIGTERM) _exit(3);  // not kept
        }
        resumeInterrupts();
        if (!signalBeforeResume) kill(getpid(), SIGTERM);
        for (int i = 0; i < 5000; ++i) usleep(1000);  // 5 s for the signal to end it
        _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFSIGNALED(status) ? WTERMSIG(status) : -WEXITSTATUS(status);
}

// A signal kept while deferring ends the process at resumeInterrupts(); one after it ends it at
// once (until stop 51 `hlod view` dropped a signal after its loop's last check and exited 0).
TEST(Interrupts, ResumeEndsByAKeptSignalAndByLaterOnes) {
    EXPECT_EQ(childEnd(true), SIGTERM);
    EXPECT_EQ(childEnd(false), SIGTERM);
}

}  // namespace
}  // namespace hlod
