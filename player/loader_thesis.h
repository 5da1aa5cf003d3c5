// The loading thread of thesis §4.3: incremental, preemptible pre-fetching of the
// highest-priority unloaded node from the priority queue, decoding off the render thread, and
// the memory budget (eviction of the lowest-priority resident nodes, done by the render thread
// so that it never evicts the front's path). `hlod play --loader thesis` (player/LOADERS.md).
#pragma once

#include "player/loader.h"
#include "player/priority_queue.h"

#include <unordered_map>

namespace hlod {

class ThesisLoader final : public Loader {
public:
    ThesisLoader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options);
    ~ThesisLoader() override;

    // update(): updateAndEvict with the request's priorities, forget list and pinned predicate.
    void update(const LoadRequest& request) override;
    // This frame's priorities; `forget` were visited last frame but not now (they sink to
    // priority 0, or leave the queue when unloaded). Then evicts resident nodes, lowest
    // priority first and never `pinned` ones, until the budget holds and the roomNodes most
    // urgent unloaded nodes fit (each only in place of nodes of lower priority than its own). Returns the evicted nodes (the caller evicts them from the renderer).
    std::vector<uint32_t> updateAndEvict(std::span<const PriorityUpdate> updates, std::span<const uint32_t> forget,
                                         const std::function<bool(uint32_t)>& pinned);

private:
    struct Partial {
        std::vector<uint8_t> data;
        uint64_t done = 0;
    };
    LinkedPriorityQueue queue_;  // guarded by mutex_
    // loader thread only
    std::unordered_map<uint32_t, Partial> suspended_;
    std::vector<uint32_t> suspendedOrder_;

    bool loadOne(bool preemptible) override;
    bool makeRoomLocked(uint64_t bytes, const std::function<bool(uint32_t)>& keep) override;
    void onFailedLocked(uint32_t id) override { queue_.remove(id); }
    void onFetchedLocked(uint32_t id) override {
        if (queue_.contains(id)) queue_.setLoaded(id, true);
    }
    uint32_t pickLocked() const;
    uint32_t nextUnloadedLocked(uint32_t id) const;
    void evictForLoadsLocked(const std::function<bool(uint32_t)>& pinned, std::vector<uint32_t>& evicted);
    bool shouldPreemptLocked(uint32_t id) const;
    Partial takeSuspended(uint32_t id);
    void suspend(uint32_t id, Partial&& partial);
};

}  // namespace hlod
