// The loader policies of player/LOADERS.md: Varadhan & Manocha 2002's bins (Fig. 5), angle
// priority and prefetch frustum (§4.2.2), LRU replacement (§4.3, Fig. 7), a demand preempting a
// prefetch within one chunk, valid fronts (player/front.h checkCut) from the vm and thesis loaders with both miss
// rules and both selectors, and the disk model turning each wait into exactly its modelled time.
#include "player/camera_path.h"
#include "player/cost_model_renderer.h"
#include "player/front.h"
#include "player/loader_vm.h"
#include "player/player.h"
#include "player/priority_queue.h"
#include "player/replay.h"
#include "tests/support/memory_source.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

using namespace hlod;

namespace {

// A memory source that logs every chunk read and can act before one.
class ChunkLogSource final : public NodeSource {
public:
    explicit ChunkLogSource(Skeleton s) : inner_(memorySource(std::move(s))) {}
    const Skeleton& skeleton() const override { return inner_->skeleton(); }
    std::string name() const override { return "test.hlod"; }
    uint64_t nodeSize(uint32_t id) const override { return inner_->nodeSize(id); }
    void readChunk(uint32_t id, uint64_t offset, std::span<uint8_t> out) const override {
        if (onChunk) onChunk(id, offset);
        log.push_back({id, offset});
        inner_->readChunk(id, offset, out);
    }
    DecodedNode decode(uint32_t id, std::span<const uint8_t> data) const override { return inner_->decode(id, data); }
    uint64_t expectedBytes(uint32_t id) const override { return inner_->expectedBytes(id); }

    mutable std::vector<std::pair<uint32_t, uint64_t>> log;
    std::function<void(uint32_t, uint64_t)> onChunk;

private:
    std::shared_ptr<const NodeSource> inner_;
};

// A vm frame classifying `errors` with the whole sphere as prefetch frustum.
std::shared_ptr<const VmFrame> vmFrame(std::map<uint32_t, double> errors, bool moved = true) {
    auto f = std::make_shared<VmFrame>();
    f->errors.insert(errors.begin(), errors.end());
    f->theta0 = M_PI;
    f->theta1 = M_PI;
    f->moved = moved;
    return f;
}

}  // namespace

// Fig. 5: epsilon = 10, delta = 12, 13 bins B_i = [i, i + 1): B10, B9, B11, B8, B12, B7, B6, ..., B0.
TEST(VmBins, Figure5OrderAndFifoWithinABin) {
    VmBins bins(10, 12, 1);
    EXPECT_EQ(bins.order(), (std::vector<int>{10, 9, 11, 8, 12, 7, 6, 5, 4, 3, 2, 1, 0}));
    EXPECT_EQ(bins.binOf(10.0), 10);
    EXPECT_EQ(bins.binOf(9.99), 9);
    EXPECT_EQ(bins.binOf(12.99), 12);
    EXPECT_EQ(bins.binOf(13.0), -1);  // beyond delta's bin: not prefetched
    EXPECT_TRUE(bins.push(1, 9.5));
    EXPECT_TRUE(bins.push(2, 10.2));
    EXPECT_TRUE(bins.push(3, 11.7));
    EXPECT_TRUE(bins.push(4, 10.9));
    EXPECT_TRUE(bins.push(5, 9.1));
    EXPECT_TRUE(bins.push(6, 0.5));
    EXPECT_TRUE(bins.push(8, 12.5));
    EXPECT_FALSE(bins.push(7, 13.5));
    std::vector<uint32_t> popped;
    for (uint32_t id; (id = bins.pop()) != kNoNode;) popped.push_back(id);
    // B10 in arrival order (2 before 4, not sorted), then B9 (1, 5), B11, B12, then B0.
    EXPECT_EQ(popped, (std::vector<uint32_t>{2, 4, 1, 5, 3, 8, 6}));
    EXPECT_TRUE(bins.empty());
}

TEST(VmBins, AngularAndIntegratedPriority) {
    EXPECT_EQ(angularPriority(0.3, 0.5, 0.8), 1.0);                  // inside F_R
    EXPECT_DOUBLE_EQ(angularPriority(0.5 + 0.8, 0.5, 0.8), 0.5);      // (theta - theta0) = theta1
    EXPECT_DOUBLE_EQ(integratedPriority(8, 10, 0.5), 4);             // eps_O < eps: eps_O x AngPr
    EXPECT_DOUBLE_EQ(integratedPriority(11, 10, 0.5), 22);           // eps_O > eps: eps_O / AngPr
    EXPECT_DOUBLE_EQ(integratedPriority(10, 10, 0.5), 10);
}

// Fig. 7: after StartTail the accessed nodes lie in the reverse of their access order; the front
// (accessed first, §4.1 Stage II) beyond the prefetched ones (accessed in decreasing priority),
// these in increasing priority; the nodes not accessed stay at the head, the first victims.
TEST(VmLru, Figure7OrderAfterAScriptedFrame) {
    InMemoryList list(10);
    list.markStartTail();
    for (uint32_t id : {0u, 1u, 2u, 3u, 4u}) list.access(id);  // an earlier frame: 4 3 2 1 0
    EXPECT_EQ(list.order(), (std::vector<uint32_t>{4, 3, 2, 1, 0}));
    list.markStartTail();  // StartTail = 0
    list.access(1);        // front, in memory
    list.access(5);        // front, fetched (L_O)
    list.access(2);        // prefetched, highest priority (in memory)
    list.access(6);        // prefetched, loaded
    list.access(7);        // prefetched, lowest priority
    EXPECT_EQ(list.startTail(), 0u);
    EXPECT_EQ(list.order(), (std::vector<uint32_t>{4, 3, 0, 7, 6, 2, 5, 1}));
    // The node at StartTail accessed: StartTail moves to its predecessor, the node stays.
    list.access(0);
    EXPECT_EQ(list.startTail(), 3u);
    EXPECT_EQ(list.order(), (std::vector<uint32_t>{4, 3, 0, 7, 6, 2, 5, 1}));
    list.remove(4);
    EXPECT_EQ(list.head(), 3u);
}

// The vm loader's victims come from the head of the InMemoryList, skipping drawn nodes; hlod0 is
// never in the list.
TEST(VmLoader, EvictsFromTheHeadNeverADrawnNodeNorHlod0) {
    auto src = std::make_shared<ChunkLogSource>(test::gridSkeleton(1, 1, 3, 512));
    uint64_t one = src->expectedBytes(1);
    LoaderOptions o;
    o.memoryBudget = src->expectedBytes(0) + 3 * one;
    VmLoader loader(src, o, false);
    loader.loadPinned(0);
    std::vector<uint32_t> front{0}, wanted{1, 2, 3};
    loader.update({{}, {}, front, wanted, {}, nullptr});
    EXPECT_EQ(loader.step(10), 3u);
    loader.takeReady(10, ~0ull);
    EXPECT_EQ(loader.inMemoryList().order(), (std::vector<uint32_t>{3, 2, 1}));  // reverse access order
    // Node 3 is drawn (accessed: it moves after StartTail = 1), 4 is wanted: the head, 2, goes.
    std::vector<uint32_t> front2{0, 3}, wanted2{4};
    loader.update({{}, {}, front2, wanted2, {}, nullptr});
    EXPECT_EQ(loader.step(10), 1u);
    EXPECT_EQ(loader.takeEvicted(), std::vector<uint32_t>{2});
    EXPECT_EQ(loader.inMemoryList().order(), (std::vector<uint32_t>{1, 4, 3}));
    loader.takeReady(10, ~0ull);
    std::vector<uint32_t> wanted3{5};
    loader.update({{}, {}, front2, wanted3, {}, nullptr});
    EXPECT_EQ(loader.step(10), 1u);
    EXPECT_EQ(loader.takeEvicted(), std::vector<uint32_t>{1});  // the head again; 3 is drawn
    EXPECT_EQ(loader.residency(0), Residency::Resident);
    EXPECT_EQ(loader.residency(3), Residency::Resident);
    EXPECT_LE(loader.counters().residentBytes, o.memoryBudget);
}

// LOADERS.md choice 13: a decoded node not yet uploaded (Ready) is no victim, as in the thesis
// loader: a new demand waits until the render thread has taken it. Until stop 50 the vm loader
// evicted it (at a budget just above hlod0 threaded runs uploaded 0 or 1 node in 1,500 frames).
TEST(VmLoader, AReadyNodeIsNoVictimBeforeItsUpload) {
    auto src = std::make_shared<ChunkLogSource>(test::gridSkeleton(1, 1, 3, 512));
    LoaderOptions o;
    o.memoryBudget = src->expectedBytes(0) + 3 * src->expectedBytes(1);
    VmLoader loader(src, o, false);
    loader.loadPinned(0);
    std::vector<uint32_t> front{0}, wanted{1, 2, 3};
    loader.update({{}, {}, front, wanted, {}, nullptr});
    EXPECT_EQ(loader.step(10), 3u);  // decoded, none taken (uploaded) yet: the budget is full
    std::vector<uint32_t> front2{0, 3}, wanted2{4};
    loader.update({{}, {}, front2, wanted2, {}, nullptr});
    EXPECT_EQ(loader.step(10), 0u);  // no room but in Ready nodes: 4 waits
    EXPECT_EQ(loader.residency(4), Residency::Unloaded);
    std::vector<uint32_t> ready;
    for (const DecodedNode& d : loader.takeReady(10, ~0ull)) ready.push_back(d.id);
    EXPECT_EQ(ready, (std::vector<uint32_t>{1, 2, 3}));
    loader.update({{}, {}, front2, wanted2, {}, nullptr});  // the next frame asks again
    EXPECT_EQ(loader.step(10), 1u);  // uploaded, the head of the list makes room
    EXPECT_EQ(loader.takeEvicted().size(), 1u);
    EXPECT_EQ(loader.residency(4), Residency::Ready);
    EXPECT_LE(loader.counters().residentBytes, o.memoryBudget);
}

// PREFETCH (§4.2.3): the popped node's parent and children are loaded, highest bin first; a
// demand arriving while a prefetch is read preempts it after the chunk in progress.
TEST(VmLoader, PrefetchesChildrenOfThePoppedNodeAndADemandPreemptsWithinOneChunk) {
    auto src = std::make_shared<ChunkLogSource>(test::gridSkeleton(1, 1, 3, 4096));
    LoaderOptions o;
    o.chunkBytes = 4096;  // 16 chunks per node (4096 triangles x 16 bytes)
    VmLoader loader(src, o, true);
    loader.loadPinned(0);
    std::vector<uint32_t> front{0};
    loader.update({{}, {}, front, {}, {}, vmFrame({{0, 10.5}})});  // hlod0 close to its switch: bin 10
    bool raised = false;
    src->onChunk = [&](uint32_t id, uint64_t offset) {
        if (id == 1 && offset == 4 * 4096 && !raised) {
            raised = true;
            std::vector<uint32_t> wanted{7};  // a grandchild the next frame wants now
            loader.update({{}, {}, front, wanted, {}, vmFrame({{0, 10.5}}, false)});
        }
    };
    src->log.clear();
    EXPECT_EQ(loader.step(1, true), 1u);  // the prefetch of node 1 (CHD(0)) is abandoned ...
    EXPECT_EQ(loader.counters().preemptions, 1u);
    EXPECT_EQ(loader.residency(1), Residency::Unloaded);
    ASSERT_EQ(src->log.size(), 5u);  // ... after the chunk in progress when the demand came
    EXPECT_EQ(src->log.back(), (std::pair<uint32_t, uint64_t>{1, 4 * 4096}));
    EXPECT_EQ(loader.step(1, true), 1u);
    EXPECT_EQ(src->log[5], (std::pair<uint32_t, uint64_t>{7, 0}));  // the next chunk is the demand's
    EXPECT_EQ(loader.residency(7), Residency::Ready);
    loader.step(10, true);  // then the prefetch resumes: CHD(0) = 1..4, in order
    std::vector<uint32_t> ready;
    for (const DecodedNode& d : loader.takeReady(100, ~0ull)) ready.push_back(d.id);
    ASSERT_GE(ready.size(), 5u);
    EXPECT_EQ(std::vector<uint32_t>(ready.begin(), ready.begin() + 5), (std::vector<uint32_t>{7, 1, 2, 3, 4}));
    LoaderCounters k = loader.counters();
    EXPECT_EQ(k.demandBytes, src->nodeSize(7));
    EXPECT_EQ(k.prefetchBytes, k.bytesRead - k.demandBytes - src->nodeSize(0));  // hlod0 is neither
}

// Visibility events (§4.2.2): nodes outside the render frustum F_R but inside the prefetch
// frustum F_I are prefetched themselves; one outside F_I is not.
TEST(VmLoader, PrefetchesNodesOutsideTheRenderFrustumWithinThePrefetchFrustum) {
    auto src = std::make_shared<ChunkLogSource>(test::gridSkeleton(1, 1, 2, 512));  // root 0, quadrants 1-4
    const Skeleton& s = src->skeleton();
    VmLoader loader(src, {}, true);
    loader.loadPinned(0);
    std::vector<uint32_t> front{1};
    loader.update({{}, {}, front, front, {}, nullptr});  // node 1 is fetched first
    EXPECT_EQ(loader.step(10), 1u);
    auto f = std::make_shared<VmFrame>();
    const double eye[3] = {25, 25, 1000}, down[3] = {0, 0, -1};  // above node 1, looking down
    std::copy(eye, eye + 3, f->eye);
    std::copy(down, down + 3, f->forward);
    EXPECT_EQ(angleToLineOfSight(s.nodes[1], eye, down), 0.0);
    const double side = angleToLineOfSight(s.nodes[2], eye, down), corner = angleToLineOfSight(s.nodes[4], eye, down);
    EXPECT_NEAR(side, angleToLineOfSight(s.nodes[3], eye, down), 1e-12);
    ASSERT_LT(side, corner);
    f->theta0 = side / 2;                // nodes 2, 3 (beside) and 4 (diagonal) lie outside F_R ...
    f->theta1 = (side + corner) / 2;     // ... 2 and 3 inside F_I, 4 outside
    f->outside = {2, 3, 4};
    loader.update({{}, {}, front, {}, {}, f});
    loader.step(10);
    EXPECT_EQ(loader.residency(2), Residency::Ready);
    EXPECT_EQ(loader.residency(3), Residency::Ready);
    EXPECT_EQ(loader.residency(4), Residency::Unloaded);
    EXPECT_EQ(loader.counters().prefetchBytes, src->nodeSize(2) + src->nodeSize(3));
}

namespace {

struct FrontCase {
    LoaderKind loader;
    OnMiss onMiss;
    const char* policy;
    bool threaded;
};

std::string caseName(const FrontCase& c) {
    return std::string(loaderKindName(c.loader)) + "/" + onMissName(c.onMiss) + "/" + c.policy +
           (c.threaded ? "/threaded" : "/sync");
}

PlayerOptions options(const FrontCase& c, uint64_t budget) {
    PlayerOptions po;
    po.threadedLoader = c.threaded;
    po.memoryBudget = budget;
    po.chunkBytes = 4096;
    po.loader = c.loader;
    po.onMiss = c.onMiss;
    po.policy = c.policy;
    return po;
}

CameraPath erratic(const Skeleton& s, double seconds) {
    PathOptions p;
    p.kind = PathKind::Erratic;
    p.duration = seconds;
    p.seed = 5;
    return generatePath(s, p);
}

}  // namespace

// Every frame's front is a valid cut (player/front.h) with the vm and thesis loaders, both miss
// rules, the thesis and sse selectors, under a memory budget that binds.
TEST(Loaders, VmAndThesisGiveValidFronts) {
    auto source = memorySource(test::errorGridSkeleton(3, 3, 4, 50, 4));
    const Skeleton& s = source->skeleton();
    CameraPath path = erratic(s, 20);
    std::map<LoaderKind, uint64_t> evictions;
    for (LoaderKind kind : {LoaderKind::Thesis, LoaderKind::Vm, LoaderKind::Demand})
        for (OnMiss onMiss : {OnMiss::Parent, OnMiss::Wait})
            for (const char* policy : {"thesis", "sse"}) {
                FrontCase fc{kind, onMiss, policy, false};
                CostModel model;
                model.msPerTexturedTriangle = 2e-3;
                CostModelRenderer renderer(model);
                Constants c;
                Player player(source, c, renderer, options(fc, 600000));
                ReplayOptions ro;
                ro.maxFrames = 500;
                uint64_t drawnBelowRoots = 0;
                replayPath(player, path, ro, [&](const FrameStats& f) {
                    std::vector<DrawnNode> drawn;
                    for (const DrawItem& d : player.front()) {
                        drawn.push_back({d.node, DrawReason::Leaf});
                        drawnBelowRoots += d.level > 0;
                    }
                    std::vector<uint8_t> resident(s.nodes.size());
                    for (const Node& n : s.nodes) resident[n.id] = player.resident(n.id);
                    double still[3] = {0, 0, 0};
                    View view = makeView(player.camera(), still, 0);
                    auto visible = [&](uint32_t id) { return frustumVis(view, s.nodes[id].bounds) >= 1; };
                    ASSERT_EQ(checkCut(s, drawn, resident, visible, player.frontSkipsBlocks()), "")
                        << caseName(fc) << " frame " << f.frame;
                    evictions[kind] += f.evictions;
                });
                EXPECT_GT(drawnBelowRoots, 0u) << caseName(fc);  // the loaders brought detail
            }
    for (auto [kind, count] : evictions) EXPECT_GT(count, 0u) << loaderKindName(kind);  // the budget bound
}

// --on-miss wait with the synchronous loader: on the same viewpoints (fixed time step), a disk
// model with 2 ms a node makes each frame longer than with a free disk by exactly 2 ms per node
// fetched; a bandwidth of 1 MB/s by exactly demand_bytes / 1000 ms; --on-miss parent never waits.
TEST(Loaders, DiskModelMakesWaitFramesLongerByExactlyTheModelledTime) {
    auto source = memorySource(test::errorGridSkeleton(3, 3, 4, 50, 4));
    CameraPath path = erratic(source->skeleton(), 20);
    auto run = [&](OnMiss onMiss, DiskModel disk) {
        CostModel model;
        model.msPerTexturedTriangle = 2e-3;
        CostModelRenderer renderer(model);
        Constants c;
        PlayerOptions po = options({LoaderKind::Vm, onMiss, "thesis", false}, 0);
        po.disk = disk;
        Player player(source, c, renderer, po);
        ReplayOptions ro;
        ro.maxFrames = 400;
        ro.fixedStepMs = 30;
        return replayPath(player, path, ro);
    };
    const double inf = std::numeric_limits<double>::infinity();
    auto free = run(OnMiss::Wait, {0, inf, 0});
    auto seek = run(OnMiss::Wait, {2, inf, 0});
    auto slow = run(OnMiss::Wait, {0, 1, 0});
    auto parent = run(OnMiss::Parent, {2, 1, 0});
    ASSERT_EQ(free.size(), seek.size());
    ASSERT_EQ(free.size(), slow.size());
    uint64_t waits = 0;
    for (size_t i = 0; i < free.size(); ++i) {
        ASSERT_EQ(free[i].wantedMissing, seek[i].wantedMissing) << "frame " << i;
        EXPECT_EQ(free[i].waitMs, 0.0);
        EXPECT_EQ(seek[i].waitMs, 2.0 * seek[i].wantedMissing);
        EXPECT_NEAR(seek[i].actualMs - free[i].actualMs, 2.0 * seek[i].wantedMissing, 1e-9) << "frame " << i;
        EXPECT_NEAR(slow[i].actualMs - free[i].actualMs, double(slow[i].demandBytes) / 1000, 1e-9) << "frame " << i;
        EXPECT_EQ(parent[i].waitMs, 0.0);
        waits += seek[i].wantedMissing > 0;
    }
    EXPECT_GT(waits, 3u);  // the path made the frames wait
}
