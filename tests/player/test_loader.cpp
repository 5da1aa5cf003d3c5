// The loading thread (thesis §4.3): priority order, incremental preemptible loads, the memory
// budget with eviction of the lowest-priority unpinned nodes, failures reported once, not retried,
// and (threaded) the budget held under an erratic path with no data race (run under TSan).
#include "player/camera_path.h"
#include "player/cost_model_renderer.h"
#include "player/loader_thesis.h"
#include "player/player.h"
#include "player/replay.h"
#include "tests/support/memory_source.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

using namespace hlod;

namespace {

// A memory source with hooks: counts chunk reads and can act in the middle of a load.
class HookSource final : public NodeSource {
public:
    explicit HookSource(Skeleton s) : inner_(memorySource(std::move(s))) {}
    const Skeleton& skeleton() const override { return inner_->skeleton(); }
    std::string name() const override { return "test.hlod"; }
    uint64_t nodeSize(uint32_t id) const override { return inner_->nodeSize(id); }
    void readChunk(uint32_t id, uint64_t offset, std::span<uint8_t> out) const override {
        ++chunks;
        if (onChunk) onChunk(id, offset);
        inner_->readChunk(id, offset, out);
    }
    DecodedNode decode(uint32_t id, std::span<const uint8_t> data) const override {
        if (id == corrupt) throw FormatError("test.hlod (node " + std::to_string(id) + ", blob 7): corrupt geometry");
        return inner_->decode(id, data);
    }
    uint64_t expectedBytes(uint32_t id) const override { return inner_->expectedBytes(id); }

    mutable std::atomic<uint64_t> chunks{0};
    std::function<void(uint32_t, uint64_t)> onChunk;
    uint32_t corrupt = kNoNode;

private:
    std::shared_ptr<const NodeSource> inner_;
};

std::vector<uint32_t> readyIds(ThesisLoader& l) {
    std::vector<uint32_t> ids;
    for (const DecodedNode& d : l.takeReady(100, ~0ull)) ids.push_back(d.id);
    return ids;
}

const auto kNothingPinned = [](uint32_t) { return false; };

// Cost-model renderer that checks, at each draw, that no node evicted during this frame lies on
// the front's path: drawn, or an ancestor of a drawn node (refined this frame).
class FrontPathRenderer final : public Renderer {
public:
    FrontPathRenderer(const Skeleton& s, const CostModel& m) : skeleton_(s), inner_(m) {}
    std::string name() const override { return "front-path"; }
    void upload(DecodedNode&& node) override { inner_.upload(std::move(node)); }
    void evict(uint32_t node) override {
        inner_.evict(node);
        evicted_.push_back(node);
        ++evictions;
    }
    double drawFrame(const Camera& camera, std::span<const DrawItem> items, const FrameOptions& options) override {
        std::vector<uint8_t> onPath(skeleton_.nodes.size(), 0);
        for (const DrawItem& d : items)
            for (uint32_t id = d.node; id != kNone; id = skeleton_.nodes[id].parent) onPath[id] = 1;
        for (uint32_t id : evicted_) frontEvictions += onPath[id];
        evicted_.clear();
        return inner_.drawFrame(camera, items, options);
    }
    uint64_t evictions = 0, frontEvictions = 0;

private:
    const Skeleton& skeleton_;
    CostModelRenderer inner_;
    std::vector<uint32_t> evicted_;
};

}  // namespace

TEST(Loader, LoadsHighestPriorityFirst) {
    auto src = std::make_shared<HookSource>(test::gridSkeleton(1, 1, 3));
    ThesisLoader loader(src, {});
    std::vector<PriorityUpdate> u{{5, 3.0}, {6, 9.0}, {7, 1.0}};
    loader.updateAndEvict(u, {}, kNothingPinned);
    EXPECT_EQ(loader.step(1), 1u);
    EXPECT_EQ(readyIds(loader), std::vector<uint32_t>{6});
    EXPECT_EQ(loader.step(5), 2u);
    EXPECT_EQ(readyIds(loader), (std::vector<uint32_t>{5, 7}));
    EXPECT_EQ(loader.residency(5), Residency::Resident);
}

TEST(Loader, BudgetEvictsLowestPriorityUnpinnedNodes) {
    auto src = std::make_shared<HookSource>(test::gridSkeleton(1, 1, 3, 512));
    uint64_t one = src->expectedBytes(1);
    LoaderOptions o;
    o.memoryBudget = 2 * one + one / 2;  // room for two nodes
    ThesisLoader loader(src, o);
    std::vector<PriorityUpdate> u{{1, 5.0}, {2, 4.0}, {3, 3.0}};
    loader.updateAndEvict(u, {}, kNothingPinned);
    EXPECT_EQ(loader.step(5), 2u);  // the third does not fit
    EXPECT_EQ(readyIds(loader), (std::vector<uint32_t>{1, 2}));
    EXPECT_LE(loader.counters().residentBytes, o.memoryBudget);
    // A more urgent node appears: the lowest-priority unpinned resident node (2) makes room.
    std::vector<PriorityUpdate> u2{{1, 5.0}, {2, 4.0}, {3, 3.0}, {4, 8.0}};
    auto evicted = loader.updateAndEvict(u2, {}, kNothingPinned);
    EXPECT_EQ(evicted, std::vector<uint32_t>{2});
    EXPECT_EQ(loader.step(5), 1u);
    EXPECT_EQ(readyIds(loader), std::vector<uint32_t>{4});
    // Pinned nodes (drawn this frame) are never evicted, even for a more urgent node.
    std::vector<PriorityUpdate> u3{{1, 5.0}, {4, 8.0}, {5, 9.0}};
    evicted = loader.updateAndEvict(u3, {}, [](uint32_t id) { return id == 1 || id == 4; });
    EXPECT_TRUE(evicted.empty());
    EXPECT_EQ(loader.step(5), 0u);
    EXPECT_LE(loader.counters().residentBytes, o.memoryBudget);
}

// Issue 12: with the budget full, eviction made room for the most urgent unloaded node only, so
// the loader took one node a frame whatever its rate. It now makes room for roomNodes of them,
// each only in place of resident nodes of lower priority than its own (§4.3's order).
TEST(Loader, FullBudgetMakesRoomForSeveralMoreUrgentNodes) {
    auto src = std::make_shared<HookSource>(test::gridSkeleton(1, 1, 3, 512));
    uint64_t one = src->expectedBytes(1);
    for (uint32_t roomNodes : {1u, 4u}) {
        LoaderOptions o;
        o.memoryBudget = 4 * one + one / 2;  // room for four nodes
        o.roomNodes = roomNodes;
        ThesisLoader loader(src, o);
        std::vector<PriorityUpdate> u{{1, 1.0}, {2, 2.0}, {3, 3.0}, {4, 4.0}};
        loader.updateAndEvict(u, {}, kNothingPinned);
        EXPECT_EQ(loader.step(8), 4u);
        readyIds(loader);
        // Four more urgent nodes and one less urgent than every resident node (0.5).
        std::vector<PriorityUpdate> u2{{1, 1.0}, {2, 2.0}, {3, 3.0}, {4, 4.0}, {5, 13.0}, {6, 12.0}, {7, 11.0}, {8, 10.0}, {9, 0.5}};
        auto evicted = loader.updateAndEvict(u2, {}, kNothingPinned);
        if (roomNodes == 1) {  // the rule before the fix: one victim, one load a frame
            EXPECT_EQ(evicted, std::vector<uint32_t>{1});
            EXPECT_EQ(loader.step(8), 1u);
            continue;
        }
        EXPECT_EQ(evicted, (std::vector<uint32_t>{1, 2, 3, 4}));
        EXPECT_EQ(loader.step(8), 4u);
        EXPECT_EQ(readyIds(loader), (std::vector<uint32_t>{5, 6, 7, 8}));
        EXPECT_LE(loader.counters().residentBytes, o.memoryBudget);
        // Two urgent nodes and two between the resident ones (10..13): only the two lowest-priority
        // resident nodes make way; a node never displaces a more urgent one.
        std::vector<PriorityUpdate> u3{{5, 13.0}, {6, 12.0}, {7, 11.0}, {8, 10.0}, {1, 20.0}, {2, 19.0}, {3, 11.5}, {4, 10.5}};
        evicted = loader.updateAndEvict(u3, {}, kNothingPinned);
        EXPECT_EQ(evicted, (std::vector<uint32_t>{8, 7}));
        EXPECT_EQ(loader.step(8), 2u);
        EXPECT_EQ(readyIds(loader), (std::vector<uint32_t>{1, 2}));
    }
}

// The same on a replay: once the budget binds, a frame that follows evictions loads the
// synchronous loader's 4 nodes (before the fix: the eviction made room for one, so such a frame
// loaded at most one node: all nodes here have the same size).
TEST(Loader, FullBudgetKeepsTheSynchronousLoadRate) {
    Skeleton s = test::gridSkeleton(4, 4, 4, 512, 50);
    auto src = memorySource(s);
    CostModel model;
    model.msPerTexturedTriangle = 1e-3;
    CostModelRenderer renderer(model);
    PlayerOptions po;
    po.threadedLoader = false;
    po.syncLoadsPerFrame = 4;
    uint64_t one = src->expectedBytes(0);
    for (const Node& n : s.nodes) ASSERT_EQ(src->expectedBytes(n.id), one);
    po.memoryBudget = one * (16 + 160);  // hlod0 and 160 more nodes
    Constants c;
    Player player(src, c, renderer, po);
    PathOptions pathOptions;
    pathOptions.kind = PathKind::Drive;
    CameraPath path = generatePath(s, pathOptions);
    ReplayOptions ro;
    ro.maxFrames = 1000;
    bool evictedBefore = false;
    uint64_t framesAfterEvictions = 0, maxLoadsAfterEvictions = 0, misses = 0;
    replayPath(player, path, ro, [&](const FrameStats& f) {
        ASSERT_LE(f.residentBytes, po.memoryBudget);
        if (evictedBefore) {
            ++framesAfterEvictions;
            maxLoadsAfterEvictions = std::max<uint64_t>(maxLoadsAfterEvictions, f.loads);
        }
        evictedBefore = f.evictions > 0;
        misses += f.misses;
    });
    std::cout << "frames after evictions " << framesAfterEvictions << ", misses " << misses << "\n";
    EXPECT_GT(framesAfterEvictions, 100u);  // the budget binds
    EXPECT_EQ(maxLoadsAfterEvictions, 4u);
}

TEST(Loader, PreemptsForMoreUrgentNodeAndResumes) {
    auto src = std::make_shared<HookSource>(test::gridSkeleton(1, 1, 3, 4096));
    LoaderOptions o;
    o.chunkBytes = 4096;  // 16 chunks per node (4096 triangles * 16 bytes)
    ThesisLoader loader(src, o);
    std::vector<PriorityUpdate> u{{1, 2.0}};
    loader.updateAndEvict(u, {}, kNothingPinned);
    bool raised = false;
    src->onChunk = [&](uint32_t id, uint64_t offset) {
        if (id == 1 && offset == 4 * 4096 && !raised) {
            raised = true;
            std::vector<PriorityUpdate> v{{1, 2.0}, {2, 7.0}};
            loader.updateAndEvict(v, {}, kNothingPinned);
        }
    };
    loader.step(1, true);  // node 1 is suspended after its 5th chunk
    EXPECT_EQ(loader.counters().preemptions, 1u);
    EXPECT_EQ(loader.residency(1), Residency::Unloaded);
    EXPECT_TRUE(readyIds(loader).empty());
    loader.step(2, true);
    EXPECT_EQ(readyIds(loader), (std::vector<uint32_t>{2, 1}));
    EXPECT_EQ(src->chunks.load(), 16u + 16u);  // node 1 resumed, not re-read
}

TEST(Loader, CorruptNodeIsReportedOnceAndNotRetried) {
    auto src = std::make_shared<HookSource>(test::gridSkeleton(1, 1, 3));
    src->corrupt = 2;
    ThesisLoader loader(src, {});
    std::vector<PriorityUpdate> u{{2, 9.0}, {3, 1.0}};
    loader.updateAndEvict(u, {}, kNothingPinned);
    loader.step(5);
    std::vector<LoadFailure> failures = loader.takeFailures();
    ASSERT_EQ(failures.size(), 1u);
    EXPECT_EQ(failures[0].node, 2u);
    EXPECT_EQ(failures[0].what, "test.hlod (node 2, blob 7): corrupt geometry");
    EXPECT_EQ(failures[0].problem, "blob 7: corrupt geometry");
    EXPECT_EQ(loader.residency(2), Residency::Failed);
    EXPECT_EQ(readyIds(loader), std::vector<uint32_t>{3});
    EXPECT_EQ(loader.counters().residentBytes, src->expectedBytes(3));  // node 2's reservation released
    // Asked for again (still visible, most urgent): never re-read, never reported again.
    uint64_t chunks = src->chunks.load();
    loader.updateAndEvict(u, {}, kNothingPinned);
    EXPECT_EQ(loader.step(5), 0u);
    EXPECT_EQ(src->chunks.load(), chunks);
    EXPECT_TRUE(loader.takeFailures().empty());
    EXPECT_EQ(loader.residency(2), Residency::Failed);
}

// The player skips a node that fails to load (counted once in failed_loads, never resident)
// unless strictLoads makes it fatal.
TEST(Loader, PlayerSkipsAFailedLoadUnlessStrict) {
    auto src = std::make_shared<HookSource>(test::gridSkeleton(1, 1, 3));
    src->corrupt = 1;
    PathOptions pathOptions;
    pathOptions.kind = PathKind::Fly;
    CameraPath path = generatePath(src->skeleton(), pathOptions);
    Constants c;
    c.targetTimeMs = 1000;  // plenty of time: the player wants the children at once
    for (bool strict : {false, true}) {
        CostModelRenderer renderer;
        PlayerOptions po;
        po.threadedLoader = false;
        po.strictLoads = strict;
        std::vector<uint32_t> told;
        po.onLoadFailure = [&](const LoadFailure& f) { told.push_back(f.node); };
        Player player(src, c, renderer, po);
        auto run = [&] {
            uint32_t failed = 0;
            for (int f = 0; f < 50; ++f) failed += player.frame(sampleCameraPath(path, f * 0.03), f * 0.03).failedLoads;
            return failed;
        };
        if (strict) {
            EXPECT_THROW(run(), FormatError);
            EXPECT_TRUE(told.empty());
            continue;
        }
        EXPECT_EQ(run(), 1u);
        EXPECT_EQ(told, std::vector<uint32_t>{1});
        EXPECT_FALSE(player.resident(1));
    }
}

// A tight budget (hlod0 + 16 nodes): eviction must spare every node on the front's path, the
// refined interior nodes as well as the drawn ones; evicting a refined node makes its visible
// child unloaded next frame, and the front collapses to the parent (flicker).
TEST(Loader, TightBudgetNeverEvictsTheFrontPath) {
    Skeleton s = test::gridSkeleton(4, 4, 4, 512, 50);
    auto src = memorySource(s);
    CostModel model;
    model.msPerTexturedTriangle = 1e-3;
    FrontPathRenderer renderer(s, model);
    PlayerOptions po;
    po.threadedLoader = false;
    po.memoryBudget = src->expectedBytes(0) * (16 + 16);
    Constants c;
    Player player(src, c, renderer, po);
    PathOptions pathOptions;
    pathOptions.kind = PathKind::Walk;
    CameraPath path = generatePath(s, pathOptions);
    ReplayOptions ro;
    ro.maxFrames = 3000;
    uint64_t deeper = 0;
    replayPath(player, path, ro, [&](const FrameStats& f) {
        ASSERT_LE(f.residentBytes, po.memoryBudget);
        deeper += f.nodesPerLevel[2] + f.nodesPerLevel[3];
    });
    std::cout << "evictions " << renderer.evictions << ", of the front's path " << renderer.frontEvictions << "\n";
    EXPECT_GT(renderer.evictions, 20u);  // the budget binds
    EXPECT_GT(deeper, 0u);                // refined interior nodes existed
    EXPECT_EQ(renderer.frontEvictions, 0u);
}

// Threaded: the budget holds at every frame under an erratic path, the renderer is never asked
// to draw a node that is not uploaded (CostModelRenderer throws), hlod0 stays resident.
TEST(LoaderThread, BudgetHeldUnderErraticPath) {
    Skeleton s = test::gridSkeleton(3, 3, 4, 512, 50);
    auto src = memorySource(s);
    uint64_t hlod0Bytes = 0;
    for (const Node& n : s.nodes)
        if (n.level == 0) hlod0Bytes += src->expectedBytes(n.id);
    CostModel model;
    model.msPerTexturedTriangle = 2e-3;
    CostModelRenderer renderer(model);
    PlayerOptions po;
    po.memoryBudget = hlod0Bytes * 3;  // hlod0 + 18 more nodes
    po.chunkBytes = 1024;
    Constants c;
    Player player(src, c, renderer, po);
    PathOptions pathOptions;
    pathOptions.kind = PathKind::Erratic;
    pathOptions.duration = 40;
    pathOptions.seed = 7;
    CameraPath path = generatePath(s, pathOptions);
    ReplayOptions ro;
    ro.maxFrames = 1500;
    uint64_t evictions = 0, loads = 0;
    auto frames = replayPath(player, path, ro, [&](const FrameStats& f) {
        ASSERT_LE(f.residentBytes, po.memoryBudget) << "frame " << f.frame;
        evictions += f.evictions;
        loads += f.loads;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));  // frames take time: the loader runs
    });
    EXPECT_EQ(frames.size(), 1500u);
    EXPECT_GT(loads, 0u);
    uint64_t capacity = po.memoryBudget / src->expectedBytes(0) - 9;
    if (loads > capacity) {
        EXPECT_GE(evictions, loads - capacity);  // every load past capacity evicted one
    }
    std::cout << "loads " << loads << ", evictions " << evictions << ", capacity " << capacity << "\n";
    for (const Node& n : s.nodes)
        EXPECT_TRUE(n.level > 0 || player.resident(n.id)) << n.id;
}
