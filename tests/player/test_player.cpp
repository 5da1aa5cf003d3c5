// End to end with the cost-model renderer (thesis Chapter 6 conditions): frame time held near
// c_targetTime after warm-up, memory within budget, few toggles per frame (§6.5), exact
// repeatability with the synchronous loader; and the engine on a real database (Draco + JPEG).
#include "player/camera_path.h"
#include "player/cost_model_renderer.h"
#include "player/player.h"
#include "player/replay.h"
#include "player/stats.h"
#include "tests/support/memory_source.h"
#include "tests/support/synthetic.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

using namespace hlod;

namespace {

struct PlayRun {
    std::vector<FrameStats> frames;
    StatsSummary summary;
    uint64_t budget = 0;
};

struct PlaySetup {
    PathKind kind = PathKind::Walk;
    uint64_t frames = 3000;
    uint64_t warmup = 300;
    bool threaded = false;  // threaded: the cost model sleeps for each modelled frame
    uint64_t seed = 1;
    double nodeError = 0;
};

// 16 blocks of 50 m, 4 levels (1,360 nodes of 512 triangles, 0.5 ms each in the model), a
// budget of 200 nodes, c_targetTime 30 ms, 4 loads per frame with the synchronous loader.
PlayRun play(const PlaySetup& setup) {
    Skeleton s = test::gridSkeleton(4, 4, 4, 512, 50);
    auto src = memorySource(s);
    CostModel model;
    model.msPerTexturedTriangle = 1e-3;
    model.nodeError = setup.nodeError;
    model.seed = setup.seed;
    model.realTime = setup.threaded;
    CostModelRenderer renderer(model);
    PlayerOptions po;
    po.threadedLoader = setup.threaded;
    po.memoryBudget = src->expectedBytes(0) * 200;
    Constants c;
    Player player(src, c, renderer, po);
    PathOptions pathOptions;
    pathOptions.kind = setup.kind;
    CameraPath path = generatePath(s, pathOptions);
    ReplayOptions ro;
    ro.maxFrames = setup.frames;
    PlayRun r;
    r.budget = po.memoryBudget;
    r.frames = replayPath(player, path, ro);
    r.summary = summarize(r.frames, setup.warmup);
    printSummary(std::cout, r.summary);
    return r;
}

}  // namespace

// Thesis §6.4/§6.5 on the test city. Measured (this engine, sync loader, seed 1): mean 29.6 ms,
// p99 36.0 ms, 0.054 toggles per frame (105 up, 40 down in 2,700 frames). The thesis reports
// 0.008 for its walk (3 toggles in 400 frames); the frame here holds ~50 nodes of 6-25 m and a
// 1.5 m/s walk crosses node boundaries ~6x as often per frame (player/SELECTION.md). The mean
// bound also fails an engine that draws hlod0 only (~10 ms).
TEST(PlayerEndToEnd, WalkHoldsTargetWithFewToggles) {
    PlayRun r = play({});
    const StatsSummary& s = r.summary;
    EXPECT_NEAR(s.frameMs.mean, 30.0, 30.0 * 0.10);  // mean within 10% of the target
    EXPECT_LT(s.frameMs.p99, 30.0 * 1.25);           // no frame far over
    EXPECT_LT(s.togglesPerFrame, 0.065);             // thesis: 0.008
    // Flicker (a toggle undoing the same node's toggle within 35 frames) is rare: measured 11 of
    // 145 toggles in 3,000 frames, 0.0037 a frame, below the thesis's rate of all toggles.
    EXPECT_LT(double(s.reversals) / r.frames.size(), 0.005);
    EXPECT_LT(double(s.reversals), 0.1 * double(s.upToggles + s.downToggles));
    for (const FrameStats& f : r.frames) ASSERT_LE(f.residentBytes, r.budget);
}

// At 15 m/s (10x the walk, as in §6.5) the loader and the hysteresis counters still fill the
// frame. Measured: mean 29.3 ms, p99 34.1 ms, 0.296 toggles per frame (192 up, 17 down in 707
// frames: a lap of the route); the thesis reports 0.09 (one toggle every 11 frames).
TEST(PlayerEndToEnd, DriveHoldsTargetAndTogglesMore) {
    PlaySetup setup;
    setup.kind = PathKind::Drive;
    PlayRun r = play(setup);
    const StatsSummary& s = r.summary;
    EXPECT_NEAR(s.frameMs.mean, 30.0, 30.0 * 0.10);
    EXPECT_LT(s.frameMs.p99, 30.0 * 1.25);
    EXPECT_LT(s.togglesPerFrame, 0.33);  // thesis: 0.09
    EXPECT_LT(double(s.reversals) / r.frames.size(), 0.015);  // measured 11 reversals of 209 toggles in 1,007 frames
    EXPECT_LT(double(s.reversals), 0.1 * double(s.upToggles + s.downToggles));
    for (const FrameStats& f : r.frames) ASSERT_LE(f.residentBytes, r.budget);
}

TEST(PlayerEndToEnd, FeedbackCorrectsABiasedCostModel) {
    // Per-node errors of +-40%: the v_time loop keeps the estimate close (Fig. 6.4b).
    PlaySetup setup;
    setup.frames = 2000;
    setup.seed = 3;
    setup.nodeError = 0.4;
    PlayRun r = play(setup);
    EXPECT_LT(std::abs(r.summary.estimateErrorPct.mean), 5.0);
    EXPECT_NEAR(r.summary.frameMs.mean, 30.0, 30.0 * 0.15);
}

TEST(PlayerEndToEnd, SynchronousRunsAreExactlyRepeatable) {
    PlaySetup setup;
    setup.kind = PathKind::Erratic;
    setup.frames = 600;
    setup.seed = 5;
    PlayRun a = play(setup);
    PlayRun b = play(setup);
    ASSERT_EQ(a.frames.size(), b.frames.size());
    for (size_t i = 0; i < a.frames.size(); ++i) {
        ASSERT_EQ(a.frames[i].actualMs, b.frames[i].actualMs) << i;
        ASSERT_EQ(a.frames[i].nodesPerLevel, b.frames[i].nodesPerLevel) << i;
    }
}

// The loading thread with frames that take their modelled time (the cost model sleeps), as in
// `hlod play` without --sync-loader: 400 frames, about 12 s. The thread loads a node of this
// source in well under a millisecond, so it keeps up whatever the machine's load; the frame
// time depends on it only through what is resident. Measured: mean 30.3 ms, p99 37.6 ms.
TEST(PlayerEndToEnd, ThreadedLoaderHoldsTarget) {
    PlaySetup setup;
    setup.threaded = true;
    setup.frames = 400;
    setup.warmup = 100;
    PlayRun r = play(setup);
    uint64_t detail = 0;
    for (const FrameStats& f : r.frames) detail += f.nodesPerLevel[2] + f.nodesPerLevel[3];
    EXPECT_GT(detail, 0u);  // loaded nodes were drawn
    EXPECT_NEAR(r.summary.frameMs.mean, 30.0, 30.0 * 0.10);
    EXPECT_LT(r.summary.frameMs.p99, 30.0 * 1.4);
    for (const FrameStats& f : r.frames) ASSERT_LE(f.residentBytes, r.budget);
}

TEST(PlayerDatabase, PlaysASyntheticDatabase) {
    auto dir = std::filesystem::temp_directory_path() / ("hlod_player_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::string file = (dir / "synthetic.hlod").string();
    SyntheticOptions so;
    so.levels = 3;
    writeSyntheticDatabase(file, so);
    Database db = Database::open(file);
    CostModel model;
    model.msPerTexturedTriangle = 1e-2;
    CostModelRenderer renderer(model);
    PlayerOptions po;
    po.threadedLoader = false;
    Constants c;
    Player player(db, c, renderer, po);
    for (uint32_t r : db.skeleton().roots()) EXPECT_TRUE(player.resident(r));
    EXPECT_EQ(player.levelCount(), 3u);
    PathOptions pathOptions;
    pathOptions.kind = PathKind::Walk;
    CameraPath path = generatePath(db.skeleton(), pathOptions);
    ReplayOptions ro;
    ro.maxFrames = 400;
    auto frames = replayPath(player, path, ro);
    uint64_t deeper = 0, loads = 0;
    for (const FrameStats& f : frames) {
        loads += f.loads;
        for (size_t l = 1; l < f.nodesPerLevel.size(); ++l) deeper += f.nodesPerLevel[l];
    }
    EXPECT_GT(loads, 0u);
    EXPECT_GT(deeper, 0u);  // more detail than hlod0 was drawn
    // Real bytes: decoded Draco meshes and JPEG texels.
    EXPECT_GT(frames.back().residentBytes, 0u);
    std::filesystem::remove_all(dir);
}
