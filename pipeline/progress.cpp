// Live progress of a build: on a terminal a line redrawn four times a
// second with stage, percent, items/s, ETA, current and peak RSS; otherwise one summary line
// per stage. Figures per stage are kept for the final summary and the build report (formats/build_report.h).
#include "pipeline/pipeline.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <ostream>
#include <thread>

namespace hlod {

uint64_t currentRss() {
    std::ifstream statm("/proc/self/statm");
    uint64_t size = 0, resident = 0;
    statm >> size >> resident;
    return resident * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
}

uint64_t peakRss() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<uint64_t>(usage.ru_maxrss) * 1024;
}

std::string formatBytes(uint64_t bytes) {
    char text[32];
    if (bytes >= (1ull << 30)) std::snprintf(text, sizeof text, "%.2f GiB", bytes / double(1ull << 30));
    else std::snprintf(text, sizeof text, "%.1f MiB", bytes / double(1ull << 20));
    return text;
}

struct Progress::Impl {
    using Clock = std::chrono::steady_clock;
    Impl(std::ostream& o, bool l) : out(o), live(l) {}
    std::ostream& out;
    bool live;
    mutable std::mutex mutex;
    std::condition_variable wake;
    bool stop = false;
    std::string stage, unit;
    uint64_t total = 0;
    std::atomic<uint64_t> done{0};
    Clock::time_point start;
    bool active = false;
    std::vector<BuildStage> figures;
    std::thread ticker;

    std::string line() const {  // caller holds mutex
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        const uint64_t d = done.load();
        const double rate = seconds > 0 ? d / seconds : 0;
        char text[256];
        const double percent = total ? std::min(100.0, 100.0 * d / total) : 0.0;
        const double eta = rate > 0 && total > d ? (total - d) / rate : 0;
        if (total)
            std::snprintf(text, sizeof text, "%-8s %5.1f%%  %8.0f k%s/s  ETA %5.0f s  RSS %s (peak %s)", stage.c_str(), percent,
                          rate / 1000, unit.c_str(), eta, formatBytes(currentRss()).c_str(), formatBytes(std::max(peakRss(), currentRss())).c_str());
        else
            std::snprintf(text, sizeof text, "%-8s %12llu %s  %8.0f k%s/s  RSS %s (peak %s)", stage.c_str(),
                          static_cast<unsigned long long>(d), unit.c_str(), rate / 1000, unit.c_str(),
                          formatBytes(currentRss()).c_str(), formatBytes(std::max(peakRss(), currentRss())).c_str());
        return text;
    }

    void tick() {
        std::unique_lock lock(mutex);
        while (!stop) {
            if (active) out << "\r" << line() << "\x1b[K" << std::flush;
            wake.wait_for(lock, std::chrono::milliseconds(250));
        }
    }
};

Progress::Progress(std::ostream& out, bool live) : impl_(new Impl{out, live}) {
    if (live) impl_->ticker = std::thread([this] { impl_->tick(); });
}

Progress::~Progress() {
    {
        std::lock_guard lock(impl_->mutex);
        impl_->stop = true;
    }
    impl_->wake.notify_all();
    if (impl_->ticker.joinable()) impl_->ticker.join();
}

void Progress::beginStage(const std::string& name, uint64_t totalItems, const std::string& unit) {
    std::lock_guard lock(impl_->mutex);
    impl_->stage = name, impl_->unit = unit, impl_->total = totalItems;
    impl_->done = 0;
    impl_->start = Impl::Clock::now();
    impl_->active = true;
}

void Progress::advance(uint64_t items) {
    impl_->done += items;
}

void Progress::endStage() {
    std::lock_guard lock(impl_->mutex);
    const double seconds = std::chrono::duration<double>(Impl::Clock::now() - impl_->start).count();
    impl_->figures.push_back({impl_->stage, seconds, impl_->done.load()});
    impl_->active = false;
    char text[256];
    std::snprintf(text, sizeof text, "%-8s %8.2f s  %12llu %s  %8.0f k%s/s  peak RSS %s", impl_->stage.c_str(), seconds,
                  static_cast<unsigned long long>(impl_->done.load()), impl_->unit.c_str(),
                  seconds > 0 ? impl_->done.load() / seconds / 1000 : 0.0, impl_->unit.c_str(),
                  formatBytes(peakRss()).c_str());
    impl_->out << (impl_->live ? "\r" : "") << text << (impl_->live ? "\x1b[K\n" : "\n") << std::flush;
}

void Progress::message(const std::string& line) {
    std::lock_guard lock(impl_->mutex);
    impl_->out << (impl_->live ? "\r\x1b[K" : "") << line << "\n" << std::flush;
}

std::vector<BuildStage> Progress::stages() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->figures;
}

}  // namespace hlod
