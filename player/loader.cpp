// Thesis §4.3 "Incremental Pre-fetching": the loading thread takes the highest-priority
// unloaded node from the queue (the cached pointer), reads it a chunk at a time and, between
// chunks, gives way to a more urgent node (the partial read is suspended, resumed later).
// Draco/JPEG decoding happens here; the render thread only uploads. Memory: a node is loaded
// only when resident bytes + its expected decoded size fit maxMemory; the render thread
// evicts the lowest-priority resident nodes to make room (never hlod0, never a node on the
// current front's path: drawn or refined). A node whose read or decode fails is reported once
// (takeFailures) and never requested again; the player decides whether that ends the run.
#include "player/loader.h"

#include "formats/db.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <limits>
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

}  // namespace

Loader::Loader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options)
    : source_(std::move(source)),
      options_(options),
      queue_(uint32_t(source_->skeleton().nodes.size())),
      state_(source_->skeleton().nodes.size(), Residency::Unloaded),
      nodeBytes_(source_->skeleton().nodes.size(), 0) {
    options_.chunkBytes = std::max<uint64_t>(options_.chunkBytes, 1);
}

Loader::~Loader() { stop(); }

std::unique_lock<std::mutex> Loader::lockTimed() {
    auto t0 = std::chrono::steady_clock::now();
    std::unique_lock lock(mutex_);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    longestWaitMs_ = std::max(longestWaitMs_, ms);
    return lock;
}

DecodedNode Loader::loadPinned(uint32_t id) {
    std::vector<uint8_t> data(source_->nodeSize(id));
    source_->readChunk(id, 0, data);
    DecodedNode node = source_->decode(id, data);
    std::lock_guard lock(mutex_);
    nodeBytes_[id] = node.bytes();
    counters_.residentBytes += nodeBytes_[id];
    counters_.bytesRead += data.size();
    counters_.bytesDecoded += nodeBytes_[id];
    ++counters_.loads;
    state_[id] = Residency::Resident;
    return node;
}

uint32_t Loader::pickLocked() const {
    if (stop_ || ready_.size() >= options_.maxReady) return kNoNode;
    uint32_t id = queue_.highestUnloaded();
    if (id == kNoNode) return kNoNode;
    uint64_t budget = options_.memoryBudget;
    if (budget > 0 && counters_.residentBytes + source_->expectedBytes(id) > budget) return kNoNode;
    return id;
}

bool Loader::shouldPreemptLocked(uint32_t id) const {
    if (stop_ || !queue_.contains(id)) return true;
    uint32_t other = queue_.highestUnloaded();
    return other != kNoNode && queue_.priority(other) > queue_.priority(id);
}

Loader::Partial Loader::takeSuspended(uint32_t id) {
    auto it = suspended_.find(id);
    if (it == suspended_.end()) return {};
    Partial p = std::move(it->second);
    suspended_.erase(it);
    std::erase(suspendedOrder_, id);
    return p;
}

void Loader::suspend(uint32_t id, Partial&& partial) {
    if (suspendedOrder_.size() >= options_.maxSuspended && !suspendedOrder_.empty()) {
        suspended_.erase(suspendedOrder_.front());
        suspendedOrder_.erase(suspendedOrder_.begin());
    }
    suspended_[id] = std::move(partial);
    suspendedOrder_.push_back(id);
}

void Loader::failLocked(uint32_t id, const std::string& what) {
    state_[id] = Residency::Failed;  // out of the queue; priority updates skip it: never picked again
    queue_.remove(id);
    failures_.push_back({id, what, problemOf(what, source_->name(), id)});
}

// One node: returns false when nothing can be loaded now.
bool Loader::loadOne(bool preemptible) {
    uint32_t id;
    uint64_t reserved;
    {
        std::lock_guard lock(mutex_);
        id = pickLocked();
        if (id == kNoNode) return false;
        reserved = source_->expectedBytes(id);
        state_[id] = Residency::Loading;
        queue_.setLoaded(id, true);
        counters_.residentBytes += reserved;
    }
    Partial part = takeSuspended(id);
    uint64_t size = source_->nodeSize(id);
    part.data.resize(size);
    try {
        while (part.done < size) {
            uint64_t n = std::min(options_.chunkBytes, size - part.done);
            source_->readChunk(id, part.done, std::span(part.data).subspan(part.done, n));
            part.done += n;
            if (!preemptible || part.done == size) continue;
            std::lock_guard lock(mutex_);
            if (!shouldPreemptLocked(id)) continue;
            state_[id] = Residency::Unloaded;
            queue_.setLoaded(id, false);
            counters_.residentBytes -= reserved;
            ++counters_.preemptions;
            suspend(id, std::move(part));
            return true;
        }
        DecodedNode node = source_->decode(id, part.data);
        std::lock_guard lock(mutex_);
        uint64_t bytes = node.bytes();
        counters_.residentBytes = counters_.residentBytes - reserved + bytes;
        counters_.bytesRead += size;
        counters_.bytesDecoded += bytes;
        ++counters_.loads;
        nodeBytes_[id] = bytes;
        state_[id] = Residency::Ready;
        ready_.push_back(std::move(node));
    } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        counters_.residentBytes -= reserved;
        failLocked(id, e.what());
    }
    return true;
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

void Loader::stop() {
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

uint32_t Loader::nextUnloadedLocked(uint32_t id) const {
    do id = queue_.next(id);
    while (id != kNoNode && queue_.loaded(id));
    return id;
}

// §4.3: "unloading the nodes in the set mem with the smallest priority until the above condition
// is satisfied". First the budget itself; then room for the roomNodes most urgent unloaded
// nodes (what the loader can take before the next pass), each only at the expense of resident
// nodes of lower priority than its own. Room for just the most urgent one held a full budget to
// one load a frame while most of it was nodes no longer visited (player/LOADER_RUNS.md, issue 12).
void Loader::evictLocked(const std::function<bool(uint32_t)>& pinned, std::vector<uint32_t>& evicted) {
    uint32_t victim = queue_.tail();
    auto evictableAbove = [&](double priority) {  // the next victim of priority below `priority`
        for (; victim != kNoNode && queue_.priority(victim) < priority; victim = queue_.prev(victim))
            if (state_[victim] == Residency::Resident && !pinned(victim)) return true;
        return false;
    };
    auto evictVictim = [&] {
        uint32_t c = victim;
        victim = queue_.prev(c);
        counters_.residentBytes -= nodeBytes_[c];
        state_[c] = Residency::Unloaded;
        queue_.setLoaded(c, false);
        evicted.push_back(c);
    };
    const uint64_t budget = options_.memoryBudget;
    const double anyPriority = std::numeric_limits<double>::infinity();
    while (counters_.residentBytes > budget && evictableAbove(anyPriority)) evictVictim();
    uint64_t need = 0;
    uint32_t want = queue_.highestUnloaded();
    for (uint32_t n = 0; n < options_.roomNodes && want != kNoNode; ++n, want = nextUnloadedLocked(want)) {
        need += source_->expectedBytes(want);
        while (counters_.residentBytes + need > budget && evictableAbove(queue_.priority(want))) evictVictim();
        if (counters_.residentBytes + need > budget) break;
    }
}

std::vector<uint32_t> Loader::updateAndEvict(std::span<const PriorityUpdate> updates, std::span<const uint32_t> forget,
                                             const std::function<bool(uint32_t)>& pinned) {
    std::vector<uint32_t> evicted;
    {
        auto lock = lockTimed();
        for (uint32_t id : forget) {
            if (state_[id] == Residency::Unloaded)
                queue_.remove(id);
            else if (queue_.contains(id))
                queue_.update(id, 0);
        }
        for (const PriorityUpdate& u : updates) {
            if (state_[u.id] == Residency::Failed) continue;
            queue_.update(u.id, u.priority);
            queue_.setLoaded(u.id, state_[u.id] != Residency::Unloaded);
        }
        if (options_.memoryBudget > 0) evictLocked(pinned, evicted);
        dirty_ = true;
    }
    wake_.notify_one();
    return evicted;
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

}  // namespace hlod
