// Progress of a build: on a terminal a line redrawn four times a second with stage, percent,
// items/s, textures loaded, ETA, current and peak RSS; otherwise (a pipe, a log) the same line
// printed once when a stage begins and then every ProgressOptions::interval (5 s), or one JSON
// object per line (--progress-json), so a long build is never silent. The ETA is the remaining
// items over the stage's mean rate so far, and is shown only once the stage has a rate (at
// least one item done): a stage that has done nothing yet (the first block decoding its
// textures) says "ETA --" instead of a made-up 0 s, and the textures it decodes are counted on
// the line. Each stage ends with one summary line. Figures per stage are kept for the final
// summary and the build report (formats/build_report.h).
#include "pipeline/pipeline.h"

#include "formats/json_text.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cctype>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <ostream>
#include <stdexcept>
#include <string>
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

// As it is when it needs no quoting, else in single quotes (`hlod build my scan.ply` in META
// command read as two arguments until stop 47).
std::string shellWord(const std::string& path) {
    const auto safe = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("/._-+,:@%=", c) != nullptr; };
    if (!path.empty() && std::all_of(path.begin(), path.end(), safe)) return path;
    std::string quoted = "'";
    for (const char c : path) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

namespace {

// A JSON string literal (stage names, units and messages: file names may hold any bytes).
std::string jsonQuoted(const std::string& text) { return jsonText(nlohmann::json(text)); }

}  // namespace

struct Progress::Impl {
    Impl(std::ostream& o, ProgressOptions p) : out(o), options(std::move(p)) {
        if (!options.clock) {
            const auto origin = std::chrono::steady_clock::now();
            options.clock = [origin] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - origin).count(); };
        }
    }
    std::ostream& out;
    ProgressOptions options;
    mutable std::mutex mutex;
    std::condition_variable wake;
    bool stop = false;
    std::string stage, unit;
    uint64_t total = 0;
    std::atomic<uint64_t> done{0}, textures{0}, texels{0};
    double start = 0, lastLine = 0;
    bool active = false;
    std::vector<BuildStage> figures;
    std::thread ticker;

    // Seconds left, or < 0 while the stage has no rate (nothing done yet) or no known total.
    double eta(double elapsed, uint64_t d) const {
        if (!total || d == 0 || elapsed <= 0) return -1;
        return d >= total ? 0 : (total - d) / (d / elapsed);
    }

    // A stage's total is an estimate (`build`: the §3.2 recursion's visits): work past it raises it
    // to what is done, so `done` never exceeds `total` (117 % on the bunny until stop 46).
    uint64_t shownTotal(uint64_t d) const { return total && d > total ? d : total; }

    std::string line(double now) const {  // caller holds mutex
        const double elapsed = now - start;
        const uint64_t d = done.load(), n = textures.load(), t = texels.load(), whole = shownTotal(d);
        const double left = eta(elapsed, d);
        char text[384];
        if (options.json) {
            std::snprintf(text, sizeof text,
                          "{\"stage\": %s, \"done\": %llu, \"total\": %llu, \"unit\": %s, \"textures\": %llu, \"texels\": %llu, "
                          "\"elapsed_s\": %.1f, \"eta_s\": %s}",
                          jsonQuoted(stage).c_str(), static_cast<unsigned long long>(d), static_cast<unsigned long long>(whole),
                          jsonQuoted(unit).c_str(), static_cast<unsigned long long>(n), static_cast<unsigned long long>(t), elapsed,
                          left < 0 ? "null" : std::to_string(static_cast<long long>(std::lround(left))).c_str());
            return text;
        }
        const double rate = elapsed > 0 ? d / elapsed : 0;
        char amount[64], textureText[64] = "", etaText[32] = "ETA --";
        if (whole) std::snprintf(amount, sizeof amount, "%5.1f%%", std::min(100.0, 100.0 * d / whole));
        else std::snprintf(amount, sizeof amount, "%llu %s", static_cast<unsigned long long>(d), unit.c_str());
        if (n) std::snprintf(textureText, sizeof textureText, "  textures %llu (%.1f Mtexel)", static_cast<unsigned long long>(n), t / 1e6);
        if (left >= 0) std::snprintf(etaText, sizeof etaText, "ETA %.0f s", left);
        std::snprintf(text, sizeof text, "%-8s %s  %8.0f k%s/s%s  %s  RSS %s (peak %s)", stage.c_str(), amount, rate / 1000,
                      unit.c_str(), textureText, whole ? etaText : "", formatBytes(currentRss()).c_str(),
                      formatBytes(std::max(peakRss(), currentRss())).c_str());
        return text;
    }

    void print(double now) {  // caller holds mutex
        if (options.live) out << "\r" << line(now) << "\x1b[K" << std::flush;
        else out << line(now) << "\n" << std::flush;
        lastLine = now;
    }

    void poll() {  // caller holds mutex
        if (!active) return;
        const double now = options.clock();
        if (options.live || now - lastLine >= options.interval) print(now);
    }

    void tick() {
        const auto period = std::chrono::duration<double>(options.live ? 0.25 : std::min(0.25, options.interval));
        std::unique_lock lock(mutex);
        while (!stop) {
            poll();
            wake.wait_for(lock, period);
        }
    }
};

namespace {
ProgressOptions liveOrNot(bool live) {
    ProgressOptions options;
    options.live = live;
    return options;
}
}  // namespace

Progress::Progress(std::ostream& out, bool live) : Progress(out, liveOrNot(live)) {}

Progress::Progress(std::ostream& out, ProgressOptions options) : impl_(new Impl{out, std::move(options)}) {
    if (!(impl_->options.interval > 0)) throw std::invalid_argument("progress interval must be positive");
    if (impl_->options.thread) impl_->ticker = std::thread([this] { impl_->tick(); });
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
    impl_->done = 0, impl_->textures = 0, impl_->texels = 0;
    impl_->start = impl_->options.clock();
    impl_->active = true;
    if (!impl_->options.live) impl_->print(impl_->start);  // a pipe sees every stage begin
}

void Progress::advance(uint64_t items) {
    impl_->done += items;
}

void Progress::textureLoaded(uint64_t texels) {
    ++impl_->textures;
    impl_->texels += texels;
}

void Progress::poll() {
    std::lock_guard lock(impl_->mutex);
    impl_->poll();
}

void Progress::endStage() {
    std::lock_guard lock(impl_->mutex);
    const double seconds = impl_->options.clock() - impl_->start;
    const uint64_t done = impl_->done.load();
    impl_->figures.push_back({impl_->stage, seconds, done});
    impl_->active = false;
    char text[384];
    if (impl_->options.json)
        std::snprintf(text, sizeof text, "{\"stage\": %s, \"done\": %llu, \"total\": %llu, \"unit\": %s, \"seconds\": %.2f, \"end\": true}",
                      jsonQuoted(impl_->stage).c_str(), static_cast<unsigned long long>(done),
                      static_cast<unsigned long long>(impl_->shownTotal(done)), jsonQuoted(impl_->unit).c_str(), seconds);
    else
        std::snprintf(text, sizeof text, "%-8s %8.2f s  %12llu %s  %8.0f k%s/s  peak RSS %s", impl_->stage.c_str(), seconds,
                      static_cast<unsigned long long>(done), impl_->unit.c_str(), seconds > 0 ? done / seconds / 1000 : 0.0,
                      impl_->unit.c_str(), formatBytes(peakRss()).c_str());
    impl_->out << (impl_->options.live ? "\r" : "") << text << (impl_->options.live ? "\x1b[K\n" : "\n") << std::flush;
}

void Progress::message(const std::string& line) {
    std::lock_guard lock(impl_->mutex);
    if (impl_->options.json) impl_->out << "{\"message\": " << jsonQuoted(line) << "}\n" << std::flush;
    else impl_->out << (impl_->options.live ? "\r\x1b[K" : "") << line << "\n" << std::flush;
}

std::vector<BuildStage> Progress::stages() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->figures;
}

}  // namespace hlod
