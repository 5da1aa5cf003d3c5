// Interrupted runs remove their temporaries (formats/interrupt.h). A signal handler may call only
// async-signal-safe functions, and removing a folder tree is not one; so the signals are blocked
// in every thread and one thread takes them with sigwait(), in an ordinary context, where it may
// lock the record and remove folders. It holds the lock until the process ends: no temporary is
// created or published after the sweep.
#include "formats/interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

namespace hlod {
namespace {

struct Record {
    std::recursive_mutex mutex;  // recursive: an uninterrupted step forgets its temporary
    std::set<std::string> paths;
};

Record& record() {
    static Record* r = new Record;  // never destroyed: the signal thread may use it during exit
    return *r;
}

// The three signals, less those the parent ignores (`nohup`; a background job's SIGINT): a blocked
// signal is queued even when ignored, so sigwait took them and ended the run (until stop 49).
sigset_t interruptSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction current {};
        if (sigaction(s, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;
        sigaddset(&set, s);
    }
    return set;
}

// deferInterrupts(): whether the first signal is kept, and which it was (0: none yet).
std::atomic<bool>& deferring() {
    static std::atomic<bool> on{false};
    return on;
}

std::atomic<int>& deferred() {
    static std::atomic<int> signal{0};
    return signal;
}

// Removes every recorded temporary; a folder that a worker thread writes into at the same time may
// need another pass.
void sweep(const std::set<std::string>& paths) {
    for (const std::string& path : paths)
        for (int pass = 0; pass < 5; ++pass) {
            std::error_code ec;
            std::filesystem::remove_all(path, ec);
            if (!ec) break;
        }
}

}  // namespace

int createTemporary(std::string& pattern, bool folder) {
    std::lock_guard lock(record().mutex);
    int result = 0;
    if (folder) result = ::mkdtemp(pattern.data()) ? 0 : -1;
    else result = ::mkstemp(pattern.data());
    if (result >= 0) record().paths.insert(pattern);
    return result;
}

void uninterrupted(const std::function<void()>& step) {
    std::lock_guard lock(record().mutex);
    step();
}

void forgetTemporary(const std::string& path) {
    std::lock_guard lock(record().mutex);
    record().paths.erase(path);
}

void removeTemporariesOnInterrupt() {
    const sigset_t set = interruptSignals();
    if (sigisemptyset(&set)) return;  // all three ignored: nothing to wait for
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    std::thread([set] {
        int signal = 0;
        do
            if (sigwait(&set, &signal) != 0) return;
        while (deferring() && deferred().exchange(signal) == 0);  // the first one deferred, a second (or after resume: -1) ends it
        endByInterrupt(signal);
    }).detach();
}

void deferInterrupts() { deferring() = true; }

int interruptedBy() { return std::max(deferred().load(), 0); }

void resumeInterrupts() {
    deferring() = false;
    // -1 marks the resume: a signal the waiting thread took as deferring is seen here or there.
    if (const int signal = deferred().exchange(-1); signal > 0) endByInterrupt(signal);
}

void endByInterrupt(int signal) {
    record().mutex.lock();  // after a publish in progress; kept until the end
    sweep(record().paths);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, signal);
    ::signal(signal, SIG_DFL);
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
    ::raise(signal);  // ends the process as the signal would have
    ::_exit(128 + signal);
}

}  // namespace hlod
