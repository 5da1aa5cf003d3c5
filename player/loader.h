// The loader interface (player/LOADERS.md): which nodes to bring from disk, when, and which to
// drop for the memory budget. One base class holds what every loader shares (the loading thread,
// chunked reads and decode off the render thread, the ready list the render thread uploads from,
// failures, counters, the on-demand fetch of `--on-miss wait`); a policy supplies the choice of the
// next node (loadOne), its reaction to a frame (update) and its victims (makeRoomLocked):
//   thesis  thesis §4.3 (player/loader_thesis.h): sorted list + hash + cached pointer,
//           incremental preemptible loads, lowest-priority eviction;
//   vm      Varadhan & Manocha 2002 §4 (player/loader_vm.h): demand fetch of the front, then
//           prioritized prefetching by error bins and angle, LRU replacement of §4.3;
//   demand  the same without prefetching (their OOCNoPre);
//   incore  every node loaded before the first frame (their Incore): the thesis loader, idle.
// Also steppable synchronously (step) for exact, repeatable runs and tests.
#pragma once

#include "player/node_source.h"

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace hlod {

enum class Residency : uint8_t { Unloaded, Loading, Ready, Resident, Failed };

enum class LoaderKind : uint8_t { Thesis, Vm, Demand, Incore };
// `--on-miss`: parent = draw the loaded parent and never wait (thesis §4.2); wait = the frame
// waits until the wanted nodes are fetched (Varadhan & Manocha §4.1 Stage II).
enum class OnMiss : uint8_t { Parent, Wait };

LoaderKind loaderKindByName(const std::string& name);  // std::invalid_argument naming the known ones
const char* loaderKindName(LoaderKind kind);
OnMiss onMissByName(const std::string& name);
const char* onMissName(OnMiss onMiss);

// Modelled time of reading and decoding one node (synchronous runs: a wait becomes frame time,
// exactly and repeatably). Figures measured by tests/bench/bench_loader.cpp (player/LOADERS.md).
struct DiskModel {
    // Defaults: bench_loader on this machine, page-cached reads (player/LOADERS.md "Disk model").
    double seekMs = 0.0005;           // fixed cost of one node's read
    double bandwidthMBs = 32000;      // stored bytes, MB/s (1 MB = 1e6 bytes)
    double decodeNsPerByte = 15;      // per decoded byte (DecodedNode::bytes): Draco + JPEG
    double fetchMs(uint64_t storedBytes, uint64_t decodedBytes) const {
        return seekMs + double(storedBytes) / (bandwidthMBs * 1e3) + double(decodedBytes) * decodeNsPerByte * 1e-6;
    }
};

struct LoaderOptions {
    uint64_t memoryBudget = 0;      // bytes; 0 = no limit
    uint64_t chunkBytes = 64 << 10; // read unit; preemption is checked between chunks
    uint32_t maxReady = 64;         // decoded nodes waiting for upload before the loader pauses
    uint32_t maxSuspended = 8;      // preempted partial loads kept for resumption
    uint32_t roomNodes = 4;         // thesis: eviction makes room for this many of the most urgent unloaded nodes
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
    uint64_t demandBytes = 0;    // stored bytes of nodes wanted by a frame when their load began
    uint64_t prefetchBytes = 0;  // stored bytes of the other loads (prefetches)
};

// The vm loader's classification data of one frame (player/loader_vm.h).
struct VmFrame;

// What the render thread tells the loader once a frame, after the selection.
struct LoadRequest {
    std::span<const PriorityUpdate> updates;  // thesis §4.3: visited nodes (level > 0) and priorities
    std::span<const uint32_t> forget;         // visited last frame, not this one
    std::span<const uint32_t> front;          // the drawn nodes (never evicted while drawn)
    std::span<const uint32_t> wanted;         // wanted-but-missing nodes: demand fetches
    std::function<bool(uint32_t)> pinned;     // thesis: the front's path, never evicted
    std::shared_ptr<const VmFrame> vm;        // vm: classification of this frame (null otherwise)
};

// Nodes fetched on the calling thread (`--on-miss wait`).
struct FetchResult {
    std::vector<DecodedNode> nodes;  // count as resident already: upload them now
    uint64_t storedBytes = 0, decodedBytes = 0;
    double modelledMs = 0;  // DiskModel::fetchMs summed over the fetched nodes
};

class Loader {
public:
    Loader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options);
    virtual ~Loader();  // a derived loader stops the thread in its own destructor
    Loader(const Loader&) = delete;
    Loader& operator=(const Loader&) = delete;

    // Reads and decodes a node now (hlod0 at start-up) and counts it resident; it never enters
    // the queue and is never evicted. Throws FormatError.
    DecodedNode loadPinned(uint32_t id);
    // loadPinned for a node that may fail (every node for incore and preload): a node that cannot
    // be read or decoded is a failure (takeFailures) as in the queue, and nothing is returned.
    std::optional<DecodedNode> tryLoadPinned(uint32_t id);

    void start();  // the loading thread, at a low OS priority
    void stop();
    // Synchronous mode: loads up to `count` nodes (preemptible: a more urgent node appearing
    // between chunks suspends the current one, as the thread does).
    uint32_t step(uint32_t count, bool preemptible = false);

    // --- render thread ---
    // Decoded nodes to upload now (bounded); they count as resident from here on.
    std::vector<DecodedNode> takeReady(uint32_t maxCount, uint64_t maxBytes);
    // This frame's request; evictions it makes are returned by takeEvicted.
    virtual void update(const LoadRequest& request) = 0;
    // Uploaded nodes the loader evicted since the last call (the caller evicts them from the renderer).
    std::vector<uint32_t> takeEvicted();
    // Reads and decodes `ids` now, on this thread, making room by the policy's eviction but never
    // evicting a node of `keep` (a node that still does not fit is left out; failed nodes are
    // skipped and reported by takeFailures). Counted as demand bytes.
    FetchResult fetchNow(std::span<const uint32_t> ids, std::span<const uint32_t> keep, const DiskModel& disk);
    LoaderCounters counters();
    double takeLongestWaitMs();  // longest render-thread wait for the lock since the last call
    // Nodes whose read or decode failed since the last call, in order; each is reported once,
    // stays Failed (never picked, never evicted) and keeps no bytes.
    std::vector<LoadFailure> takeFailures();
    Residency residency(uint32_t id);

protected:
    std::shared_ptr<const NodeSource> source_;
    LoaderOptions options_;
    std::mutex mutex_;
    std::condition_variable wake_;
    // guarded by mutex_
    std::vector<Residency> state_;
    std::vector<uint64_t> nodeBytes_;
    std::vector<uint8_t> wanted_;  // wanted by the last request (demand) or not (prefetch)
    std::vector<DecodedNode> ready_;
    std::vector<uint32_t> evicted_;
    LoaderCounters counters_;
    std::vector<LoadFailure> failures_;
    bool stop_ = false, dirty_ = false;

    std::unique_lock<std::mutex> lockTimed();
    // One node: returns false when nothing can be loaded now.
    virtual bool loadOne(bool preemptible) = 0;
    // Evicts (policy order) until `bytes` more fit the budget, never a node `keep` says; false
    // when they cannot fit.
    virtual bool makeRoomLocked(uint64_t bytes, const std::function<bool(uint32_t)>& keep) = 0;
    virtual void onFailedLocked(uint32_t /*id*/) {}
    virtual void onFetchedLocked(uint32_t /*id*/) {}  // fetchNow made the node resident
    void failLocked(uint32_t id, const std::string& what);
    void evictLocked(uint32_t id);  // drops a Resident (uploaded) node's bytes; the renderer is told (takeEvicted)
    void markWantedLocked(std::span<const uint32_t> wanted);
    void countLoadLocked(uint32_t id, uint64_t stored, uint64_t decoded);
    void joinThread();

private:
    double longestWaitMs_ = 0;  // render thread only
    std::thread thread_;
    void run();
};

// The loader of `kind` (incore: the thesis loader; the Player loads every node first).
std::unique_ptr<Loader> makeLoader(LoaderKind kind, std::shared_ptr<const NodeSource> source, const LoaderOptions& options);

}  // namespace hlod
