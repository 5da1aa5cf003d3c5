// Thesis §4.3 "Incremental Pre-fetching": the loading thread takes the highest-priority
// unloaded node from the queue (the cached pointer), reads it a chunk at a time and, between
// chunks, gives way to a more urgent node (the partial read is suspended, resumed later).
// Draco/JPEG decoding happens here; the render thread only uploads. Memory: a node is loaded
// only when resident bytes + its expected decoded size fit maxMemory; the render thread
// evicts the lowest-priority resident nodes to make room (never hlod0, never a node on the
// current front's path: drawn or refined). A node whose read or decode fails is reported once
// (takeFailures) and never requested again; the player decides whether that ends the run.
#include "player/loader_thesis.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace hlod {

ThesisLoader::ThesisLoader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options)
    : Loader(std::move(source), options), queue_(uint32_t(source_->skeleton().nodes.size())) {}

ThesisLoader::~ThesisLoader() { joinThread(); }

uint32_t ThesisLoader::pickLocked() const {
    if (stop_ || ready_.size() >= options_.maxReady) return kNoNode;
    uint32_t id = queue_.highestUnloaded();
    if (id == kNoNode) return kNoNode;
    uint64_t budget = options_.memoryBudget;
    if (budget > 0 && counters_.residentBytes + source_->expectedBytes(id) > budget) return kNoNode;
    return id;
}

bool ThesisLoader::shouldPreemptLocked(uint32_t id) const {
    if (stop_ || !queue_.contains(id)) return true;
    uint32_t other = queue_.highestUnloaded();
    return other != kNoNode && queue_.priority(other) > queue_.priority(id);
}

ThesisLoader::Partial ThesisLoader::takeSuspended(uint32_t id) {
    auto it = suspended_.find(id);
    if (it == suspended_.end()) return {};
    Partial p = std::move(it->second);
    suspended_.erase(it);
    std::erase(suspendedOrder_, id);
    return p;
}

void ThesisLoader::suspend(uint32_t id, Partial&& partial) {
    if (suspendedOrder_.size() >= options_.maxSuspended && !suspendedOrder_.empty()) {
        suspended_.erase(suspendedOrder_.front());
        suspendedOrder_.erase(suspendedOrder_.begin());
    }
    suspended_[id] = std::move(partial);
    suspendedOrder_.push_back(id);
}

bool ThesisLoader::loadOne(bool preemptible) {
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
        countLoadLocked(id, size, bytes);
        state_[id] = Residency::Ready;
        ready_.push_back(std::move(node));
    } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        counters_.residentBytes -= reserved;
        failLocked(id, e.what());
    }
    return true;
}

void ThesisLoader::update(const LoadRequest& request) {
    std::vector<uint32_t> evicted = updateAndEvict(request.updates, request.forget, request.pinned);
    std::lock_guard lock(mutex_);
    markWantedLocked(request.wanted);
    evicted_.insert(evicted_.end(), evicted.begin(), evicted.end());
}

uint32_t ThesisLoader::nextUnloadedLocked(uint32_t id) const {
    do id = queue_.next(id);
    while (id != kNoNode && queue_.loaded(id));
    return id;
}

// §4.3: "unloading the nodes in the set mem with the smallest priority until the above condition
// is satisfied". First the budget itself; then room for the roomNodes most urgent unloaded
// nodes (what the loader can take before the next pass), each only at the expense of resident
// nodes of lower priority than its own. Room for just the most urgent one held a full budget to
// one load a frame while most of it was nodes no longer visited (player/LOADER_RUNS.md, issue 12).
void ThesisLoader::evictForLoadsLocked(const std::function<bool(uint32_t)>& pinned, std::vector<uint32_t>& evicted) {
    uint32_t victim = queue_.tail();
    auto evictableBelow = [&](double priority) {  // the next victim of priority below `priority`
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
    while (counters_.residentBytes > budget && evictableBelow(std::numeric_limits<double>::infinity())) evictVictim();
    uint64_t need = 0;
    uint32_t want = queue_.highestUnloaded();
    for (uint32_t n = 0; n < options_.roomNodes && want != kNoNode; ++n, want = nextUnloadedLocked(want)) {
        need += source_->expectedBytes(want);
        while (counters_.residentBytes + need > budget && evictableBelow(queue_.priority(want))) evictVictim();
        if (counters_.residentBytes + need > budget) break;
    }
}

std::vector<uint32_t> ThesisLoader::updateAndEvict(std::span<const PriorityUpdate> updates,
                                                   std::span<const uint32_t> forget,
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
        if (options_.memoryBudget > 0) evictForLoadsLocked(pinned, evicted);
        dirty_ = true;
    }
    wake_.notify_one();
    return evicted;
}

// --on-miss wait: the lowest-priority resident nodes make room, as in updateAndEvict.
bool ThesisLoader::makeRoomLocked(uint64_t bytes, const std::function<bool(uint32_t)>& keep) {
    for (uint32_t c = queue_.tail(); c != kNoNode && counters_.residentBytes + bytes > options_.memoryBudget;) {
        uint32_t above = queue_.prev(c);
        if (state_[c] == Residency::Resident && !keep(c)) {
            evictLocked(c);
            queue_.setLoaded(c, false);
        }
        c = above;
    }
    return counters_.residentBytes + bytes <= options_.memoryBudget;
}

}  // namespace hlod
