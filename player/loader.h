// The loading thread of thesis §4.3: incremental, preemptible pre-fetching of the
// highest-priority unloaded node from the priority queue, decoding off the render thread, and
// the memory budget (eviction of the lowest-priority resident nodes, done by the render thread
// so that it never evicts the front's path). Also steppable synchronously for exact tests.
#pragma once

#include "player/node_source.h"
#include "player/priority_queue.h"

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

namespace hlod {

enum class Residency : uint8_t { Unloaded, Loading, Ready, Resident, Failed };

struct LoaderOptions {
    uint64_t memoryBudget = 0;      // bytes; 0 = no limit
    uint64_t chunkBytes = 64 << 10; // read unit; preemption is checked between chunks
    uint32_t maxReady = 64;         // decoded nodes waiting for upload before the loader pauses
    uint32_t maxSuspended = 8;      // preempted partial loads kept for resumption
    uint32_t roomNodes = 4;         // eviction makes room for this many of the most urgent unloaded nodes
};

struct PriorityUpdate {
    uint32_t id;
    double priority;
};

struct LoaderCounters {
    uint64_t loads = 0;        // nodes decoded
    uint64_t bytesRead = 0;    // stored bytes read
    uint64_t bytesDecoded = 0; // DecodedNode::bytes() produced
    uint64_t preemptions = 0;
    uint64_t residentBytes = 0;  // uploaded + ready + reserved for the node being loaded
};

class Loader {
public:
    Loader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options);
    ~Loader();
    Loader(const Loader&) = delete;
    Loader& operator=(const Loader&) = delete;

    // Reads and decodes a node now (hlod0 at start-up) and counts it resident; it never enters
    // the queue and is never evicted. Throws FormatError.
    DecodedNode loadPinned(uint32_t id);

    void start();  // the loading thread, at a low OS priority
    void stop();
    // Synchronous mode: loads up to `count` nodes, highest priority first (preemptible: a more
    // urgent node appearing between chunks suspends the current one, as the thread does).
    uint32_t step(uint32_t count, bool preemptible = false);

    // --- render thread ---
    // Decoded nodes to upload now (bounded); they count as resident from here on.
    std::vector<DecodedNode> takeReady(uint32_t maxCount, uint64_t maxBytes);
    // This frame's priorities; `forget` were visited last frame but not now (they sink to
    // priority 0, or leave the queue when unloaded). Then evicts resident nodes, lowest
    // priority first and never `pinned` ones, until the budget holds and the roomNodes most
    // urgent unloaded nodes fit (each only in place of nodes of lower priority than its own). Returns the evicted nodes (the caller evicts them from the renderer).
    std::vector<uint32_t> updateAndEvict(std::span<const PriorityUpdate> updates, std::span<const uint32_t> forget,
                                         const std::function<bool(uint32_t)>& pinned);
    LoaderCounters counters();
    double takeLongestWaitMs();  // longest render-thread wait for the lock since the last call
    // Nodes whose read or decode failed since the last call, in order; each is reported once,
    // stays Failed (out of the queue, never picked, never evicted) and keeps no bytes.
    std::vector<LoadFailure> takeFailures();
    Residency residency(uint32_t id);

    // Test access: the queue (only while no thread runs).
    const LinkedPriorityQueue& queue() const { return queue_; }

private:
    struct Partial {
        std::vector<uint8_t> data;
        uint64_t done = 0;
    };
    std::shared_ptr<const NodeSource> source_;
    LoaderOptions options_;
    std::mutex mutex_;
    std::condition_variable wake_;
    // guarded by mutex_
    LinkedPriorityQueue queue_;
    std::vector<Residency> state_;
    std::vector<uint64_t> nodeBytes_;
    std::vector<DecodedNode> ready_;
    LoaderCounters counters_;
    std::vector<LoadFailure> failures_;
    bool stop_ = false, dirty_ = false;
    // loader thread only
    std::unordered_map<uint32_t, Partial> suspended_;
    std::vector<uint32_t> suspendedOrder_;
    // render thread only
    double longestWaitMs_ = 0;
    std::thread thread_;

    std::unique_lock<std::mutex> lockTimed();
    uint32_t pickLocked() const;
    bool shouldPreemptLocked(uint32_t id) const;
    bool loadOne(bool preemptible);
    Partial takeSuspended(uint32_t id);
    void suspend(uint32_t id, Partial&& partial);
    void failLocked(uint32_t id, const std::string& what);
    uint32_t nextUnloadedLocked(uint32_t id) const;
    void evictLocked(const std::function<bool(uint32_t)>& pinned, std::vector<uint32_t>& evicted);
    void run();
};

}  // namespace hlod
