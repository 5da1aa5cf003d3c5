// The rendering engine of thesis Chapter 4: a Player owns the per-node selection state
// (§4.2), the loading thread and its priority queue (§4.3) and drives a Renderer one frame
// at a time. `hlod play` replays a camera path through it; `hlod view` calls frame() from
// its window loop.
#pragma once

#include "formats/constants.h"
#include "formats/db.h"
#include "player/feedback.h"
#include "player/loader.h"
#include "player/node_source.h"
#include "player/policy.h"
#include "player/renderer.h"
#include "player/vm_bins.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace hlod {

struct PlayerOptions {
    uint64_t memoryBudget = 0;          // --memory BYTES (§4.3 maxMemory); 0 = no limit
    bool requireLoadedChildren = false; // §5.2 option: switch to children only when all are loaded
    bool threadedLoader = true;         // false: the loader is stepped synchronously in frame()
    uint32_t syncLoadsPerFrame = 4;     // synchronous mode: nodes loaded at the start of each frame
    uint32_t maxUploadsPerFrame = 16;   // GPU uploads per frame are bounded by count ...
    uint64_t maxUploadBytesPerFrame = 32ull << 20;  // ... and by bytes (at least one per frame)
    uint64_t chunkBytes = 64ull << 10;  // incremental load unit; preemption is checked between chunks
    double lookaheadSeconds = 0.5;      // distance is also measured from position + velocity * this
    double teleportSpeed = 100;         // m/s; faster camera moves are clamped to this (teleports)
    double metresPerUnit = 1;           // what one database unit is (play's --units): teleportSpeed / this in units/s
    double vTimeGain = 0.2;             // first feedback loop: v_time moves this fraction per frame
    ShareLoop shareLoop;                // second feedback loop: band and step (player/feedback.h)
    double initialHystSwitches = -1;    // hysteresis_n of a node evaluated first = this * c_hystSwitch
    double initialVTime = 0;            // ms per unit of cost; 0: measured at start (all hlod0 drawn)
    double overheadMs = -1;             // fixed overhead; < 0: measured at start with drawing off
    FrameOptions frameOptions;          // passed to Renderer::drawFrame
    std::string policy = "thesis";      // selection policy by name (player/policy.h, player/POLICIES.md)
    PolicyOptions policyOptions;        // its settings ("policy.setting" -> value)
    double viewportHeight = 720;
    // Every node decoded and uploaded at start and never evicted (Funkhouser & Séquin 1993 §7 ran
    // from memory): `hlod compare --preload`. A node below hlod0 that cannot load is skipped as in
    // any run (strictLoads: it ends the start-up).
    bool preload = false;        // pixels: the common benefit and pixel thresholds (player/benefit.h)
    // A node below hlod0 that cannot be read or decoded: false (default) skips it for good (its
    // parent stays drawn, onLoadFailure is told once); true (`--strict`) makes frame() throw.
    bool strictLoads = false;
    std::function<void(const LoadFailure&)> onLoadFailure;  // called from frame(), render thread
    // The loader policy (player/LOADERS.md): thesis (§4.3), vm and demand (Varadhan & Manocha
    // 2002 §4, with and without prefetching), incore (every node loaded at start; a budget below
    // the database's decoded size is then an error).
    LoaderKind loader = LoaderKind::Thesis;
    // A wanted node that is not loaded: draw the loaded parent (thesis) or wait for its fetch (vm).
    OnMiss onMiss = OnMiss::Parent;
    DiskModel disk;      // modelled fetch time of `--on-miss wait` with the synchronous loader
    VmOptions vm;        // vm loader: bins, tolerance, prefetch frustum
};

// Everything logged for one frame (columns of the CSV, player/STATS.md).
struct FrameStats {
    uint64_t frame = 0;
    double timeSeconds = 0;          // simulated time the camera was sampled at
    double distance = 0;             // path length travelled by the camera since frame 0 (teleports excluded)
    double targetMs = 0;             // c_targetTime
    double estimateNoFeedbackMs = 0; // overhead + initial v_time * sum(cost drawn) (Fig. 6.4a)
    double estimateMs = 0;           // overhead + v_time * sum(cost drawn) (Fig. 6.4b)
    double actualMs = 0;             // Renderer::drawFrame
    double vTime = 0;                // v_time after this frame's update, ms per unit cost
    double hlod0ShareMs = 0;         // shareTime of the hlod0 nodes used this frame
    std::vector<uint32_t> nodesPerLevel;
    std::vector<uint64_t> trianglesPerLevel;
    uint32_t upToggles = 0;          // §6.5: a node drawn last frame whose children are drawn now
    uint32_t downToggles = 0;        // §6.5: siblings drawn last frame replaced by their parent
    uint32_t reversals = 0;          // toggles undoing the same node's toggle of <= 35 frames before
    uint32_t residentNodes = 0;      // uploaded to the renderer
    uint64_t residentBytes = 0;      // real bytes: uploaded + decoded waiting + being loaded
    double memoryEstimateBytes = 0;  // §4.3: c_memory * sum(cost) of resident nodes
    double memoryEstimatePct = 0;    // 100 * memoryEstimateBytes / maxMemory (Fig. 6.1); NaN without a budget
    uint32_t loads = 0;              // nodes uploaded this frame
    uint32_t evictions = 0;          // nodes evicted this frame
    uint32_t failedLoads = 0;        // nodes whose load failed (reported this frame, never retried)
    uint32_t misses = 0;             // visible nodes wanted (cumHyst >= 0) but not loaded
    uint32_t refused = 0;            // sibling sets, all loaded, refused because cumHyst < 0
    double stallMs = 0;              // longest render-thread wait on the loader's lock
    double selectionMs = 0;          // CPU time of the traversal (§5.2 running time)
    // Columns shared by every selection policy (player/POLICIES.md), appended after the per-level ones.
    const char* policy = "";         // the policy's registry name
    double benefit = 0;              // common benefit of the front (player/benefit.h)
    double optimisationMs = 0;       // the policy's optimisation proper (= selectionMs unless it says)
    uint32_t iterations = 0;         // the policy's unit of work (thesis: nodes considered)
    uint64_t visibleTriangles = 0;   // triangles full detail would draw for the drawn visible nodes
    double leftoverMs = 0;           // target_ms - est_ms: budget the front left unused by the estimate
    // Loader columns (player/LOADERS.md), appended after the policy ones.
    uint64_t demandBytes = 0;        // stored bytes of nodes a frame wanted, fetched during this frame
    uint64_t prefetchBytes = 0;      // stored bytes of the other loads during this frame
    uint64_t frontBytes = 0;         // decoded bytes of the drawn nodes
    uint32_t wantedMissing = 0;      // nodes the selector wanted to draw that were not loaded
    double waitMs = 0;               // --on-miss wait: fetch time added to actual_ms (modelled or measured)
};

class Player {
public:
    // Loads the skeleton's hlod0 nodes (decode + upload) before returning, measures the
    // fixed overhead and v_time unless given, then starts the loading thread.
    // Throws FormatError when an hlod0 node cannot be read or decoded (hlod0 is never skipped).
    Player(const Database& db, const Constants& constants, Renderer& renderer, const PlayerOptions& options);
    Player(std::shared_ptr<const NodeSource> source, const Constants& constants, Renderer& renderer,
           const PlayerOptions& options);
    ~Player();
    Player(const Player&) = delete;
    Player& operator=(const Player&) = delete;

    // One frame: uploads (bounded), selection, eviction, draw, feedback loops, loader priorities.
    // With strictLoads, throws FormatError when a node failed to load (either loader mode).
    FrameStats frame(const Camera& camera, double timeSeconds);

    const Skeleton& skeleton() const;
    const Camera& camera() const;             // the last frame's camera, its clip planes fitted to the model (fitClipPlanes)
    std::span<const DrawItem> front() const;  // the nodes drawn by the last frame
    uint32_t levelCount() const;
    double vTime() const;
    double overheadMs() const;
    double hlod0ShareMs() const;
    bool resident(uint32_t node) const;
    bool frontSkipsBlocks() const;            // the last front left visible blocks out on purpose

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hlod
