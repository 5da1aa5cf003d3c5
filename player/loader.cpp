// What every loader shares (player/loader.h): the loading thread at a low OS priority (thesis
// §4.3), the ready list the render thread uploads from, pinned loads, failures reported once
// and never retried, the demand/prefetch byte counts, and the on-demand fetch of `--on-miss
// wait` (Varadhan & Manocha 2002 §4.1 Stage II: the renderer waits for the front's missing nodes).
#include "player/loader.h"

#include "formats/db.h"
#include "player/loader_thesis.h"
#include "player/loader_vm.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <unordered_set>
#include <utility>

namespace hlod {
namespace {

// The problem of a failure without the file and node the error names: "NAME (node N, blob B):
// problem" -> "blob B: problem", "NAME: problem" -> "problem"; anything else as it is.
std::string problemOf(const std::string& what, const std::string& name, uint32_t id) {
    const std::string nodePrefix = name + " (node " + std::to_string(id) + ", ";
    if (what.starts_with(nodePrefix)) {
        std::string rest = what.substr(nodePrefix.size());
        if (size_t close = rest.find("): "); close != std::string::npos) rest.erase(close, 1);
        return rest;
    }
    if (what.starts_with(name + ": ")) return what.substr(name.size() + 2);
    return what;
}

constexpr const char* kKindNames[] = {"thesis", "vm", "demand", "incore"};
constexpr const char* kOnMissNames[] = {"parent", "wait"};

}  // namespace

LoaderKind loaderKindByName(const std::string& name) {
    for (size_t i = 0; i < std::size(kKindNames); ++i)
        if (name == kKindNames[i]) return LoaderKind(i);
    throw std::invalid_argument("unknown loader '" + name + "' (thesis, vm, demand, incore)");
}
const char* loaderKindName(LoaderKind kind) { return kKindNames[size_t(kind)]; }
OnMiss onMissByName(const std::string& name) {
    for (size_t i = 0; i < std::size(kOnMissNames); ++i)
        if (name == kOnMissNames[i]) return OnMiss(i);
    throw std::invalid_argument("unknown --on-miss '" + name + "' (parent, wait)");
}
const char* onMissName(OnMiss onMiss) { return kOnMissNames[size_t(onMiss)]; }

Loader::Loader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options)
    : source_(std::move(source)),
      options_(options),
      state_(source_->skeleton().nodes.size(), Residency::Unloaded),
      nodeBytes_(source_->skeleton().nodes.size(), 0),
      wanted_(source_->skeleton().nodes.size(), 0) {
    options_.chunkBytes = std::max<uint64_t>(options_.chunkBytes, 1);
}

Loader::~Loader() { joinThread(); }

std::unique_lock<std::mutex> Loader::lockTimed() {
    auto t0 = std::chrono::steady_clock::now();
    std::unique_lock lock(mutex_);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    longestWaitMs_ = std::max(longestWaitMs_, ms);
    return lock;
}

void Loader::countLoadLocked(uint32_t id, uint64_t stored, uint64_t decoded) {
    counters_.bytesRead += stored;
    counters_.bytesDecoded += decoded;
    (wanted_[id] ? counters_.demandBytes : counters_.prefetchBytes) += stored;
    ++counters_.loads;
    nodeBytes_[id] = decoded;
}

DecodedNode Loader::loadPinned(uint32_t id) {
    std::vector<uint8_t> data(source_->nodeSize(id));
    source_->readChunk(id, 0, data);
    DecodedNode node = source_->decode(id, data);
    std::lock_guard lock(mutex_);
    counters_.residentBytes += node.bytes();
    counters_.bytesRead += data.size();
    counters_.bytesDecoded += node.bytes();
    ++counters_.loads;
    nodeBytes_[id] = node.bytes();
    state_[id] = Residency::Resident;
    return node;
}

std::optional<DecodedNode> Loader::tryLoadPinned(uint32_t id) {
    try {
        return loadPinned(id);
    } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        failLocked(id, e.what());
        return std::nullopt;
    }
}

void Loader::failLocked(uint32_t id, const std::string& what) {
    state_[id] = Residency::Failed;  // never picked again
    onFailedLocked(id);
    failures_.push_back({id, what, problemOf(what, source_->name(), id)});
}

void Loader::evictLocked(uint32_t id) {
    counters_.residentBytes -= nodeBytes_[id];
    evicted_.push_back(id);
    state_[id] = Residency::Unloaded;
}

void Loader::markWantedLocked(std::span<const uint32_t> wanted) {
    std::fill(wanted_.begin(), wanted_.end(), 0);
    for (uint32_t id : wanted) wanted_[id] = 1;
}

void Loader::run() {
    // The thesis starts the loading thread "at a low operating system priority".
    setpriority(PRIO_PROCESS, pid_t(gettid()), 10);
    for (;;) {
        if (loadOne(true)) continue;
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || dirty_; });
        dirty_ = false;
        if (stop_) return;
    }
}

void Loader::start() {
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
}

void Loader::stop() { joinThread(); }

void Loader::joinThread() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    std::lock_guard lock(mutex_);
    stop_ = false;
}

uint32_t Loader::step(uint32_t count, bool preemptible) {
    uint32_t done = 0;
    while (done < count && loadOne(preemptible)) ++done;
    return done;
}

std::vector<DecodedNode> Loader::takeReady(uint32_t maxCount, uint64_t maxBytes) {
    std::vector<DecodedNode> out;
    {
        auto lock = lockTimed();
        uint64_t bytes = 0;
        size_t n = 0;
        while (n < ready_.size() && n < maxCount && (n == 0 || bytes + nodeBytes_[ready_[n].id] <= maxBytes)) {
            bytes += nodeBytes_[ready_[n].id];
            state_[ready_[n].id] = Residency::Resident;
            ++n;
        }
        out.assign(std::make_move_iterator(ready_.begin()), std::make_move_iterator(ready_.begin() + n));
        ready_.erase(ready_.begin(), ready_.begin() + n);
        dirty_ = dirty_ || n > 0;
    }
    if (!out.empty()) wake_.notify_one();
    return out;
}

std::vector<uint32_t> Loader::takeEvicted() {
    auto lock = lockTimed();
    return std::exchange(evicted_, {});
}

FetchResult Loader::fetchNow(std::span<const uint32_t> ids, std::span<const uint32_t> keep, const DiskModel& disk) {
    FetchResult r;
    std::unordered_set<uint32_t> kept(keep.begin(), keep.end());
    auto isKept = [&](uint32_t id) { return kept.contains(id); };
    for (uint32_t id : ids) {
        uint64_t reserved = source_->expectedBytes(id);
        {
            auto lock = lockTimed();
            if (state_[id] != Residency::Unloaded) continue;  // arrived meanwhile, being loaded, or failed
            if (options_.memoryBudget > 0 && !makeRoomLocked(reserved, isKept)) continue;
            state_[id] = Residency::Loading;
            counters_.residentBytes += reserved;
        }
        std::vector<uint8_t> data(source_->nodeSize(id));
        try {
            source_->readChunk(id, 0, data);
            DecodedNode node = source_->decode(id, data);
            auto lock = lockTimed();
            counters_.residentBytes = counters_.residentBytes - reserved + node.bytes();
            wanted_[id] = 1;
            countLoadLocked(id, data.size(), node.bytes());
            state_[id] = Residency::Resident;
            onFetchedLocked(id);
            r.storedBytes += data.size();
            r.decodedBytes += node.bytes();
            r.modelledMs += disk.fetchMs(data.size(), node.bytes());
            r.nodes.push_back(std::move(node));
        } catch (const std::exception& e) {
            auto lock = lockTimed();
            counters_.residentBytes -= reserved;
            failLocked(id, e.what());
        }
    }
    return r;
}

LoaderCounters Loader::counters() {
    auto lock = lockTimed();
    return counters_;
}

double Loader::takeLongestWaitMs() {
    double ms = longestWaitMs_;
    longestWaitMs_ = 0;
    return ms;
}

std::vector<LoadFailure> Loader::takeFailures() {
    auto lock = lockTimed();
    return std::exchange(failures_, {});
}

Residency Loader::residency(uint32_t id) {
    auto lock = lockTimed();
    return state_[id];
}

std::unique_ptr<Loader> makeLoader(LoaderKind kind, std::shared_ptr<const NodeSource> source, const LoaderOptions& options) {
    switch (kind) {
        case LoaderKind::Vm: return std::make_unique<VmLoader>(std::move(source), options, true);
        case LoaderKind::Demand: return std::make_unique<VmLoader>(std::move(source), options, false);
        case LoaderKind::Thesis:
        case LoaderKind::Incore: break;
    }
    return std::make_unique<ThesisLoader>(std::move(source), options);
}

}  // namespace hlod
