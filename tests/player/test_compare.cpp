// The common benefit (player/benefit.h), the `hlod compare` reduction (player/compare.h) and
// the fixed-step replay: values checked against hand computations.
#include "player/benefit.h"
#include "player/compare.h"
#include "player/cost_model_renderer.h"
#include "player/replay.h"
#include "tests/support/memory_source.h"
#include "tests/support/synthetic.h"
#include "tests/support/temp_dir.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

using namespace hlod;

TEST(Benefit, ProjectedAreaTimesAccuracyFromTheGeometricError) {
    Skeleton s;
    // 10 x 10 m, 200 triangles: staticBenefit = sqrt(200 x 100), surface area 100 m^2.
    uint32_t id = test::addNode(s, kNone, {{-5, -5, -100}, {5, 5, -100}}, 200);
    test::linkSkeleton(s);
    Node& n = s.nodes[id];
    Camera cam;  // at the origin looking down -Z, 60 degree vertical field of view
    Projection p = makeProjection(cam, 720);
    double f = 360 / std::tan(M_PI / 6);
    EXPECT_NEAR(p.focalPx, f, 1e-9);
    EXPECT_NEAR(projectedAreaPx(n, p), 100 * f * f / (100 * 100), 1e-3);  // staticBenefit is a float
    n.geometricError = float(100 / f);  // exactly one pixel at 100 m
    EXPECT_NEAR(projectedErrorPx(n, p), 1, 1e-6);
    EXPECT_NEAR(nodeBenefit(s, n, p), 0.5 * projectedAreaPx(n, p), 1e-3);  // accuracy 1/2 at one pixel
    n.geometricError = 0;
    EXPECT_NEAR(nodeBenefit(s, n, p), projectedAreaPx(n, p), 1e-9);  // exact: accuracy 1
    cam.position[2] = -99.5;  // closer than the box: the thresholds' area is capped at the viewport,
    Projection near = makeProjection(cam, 720);  // the benefit's is not (it must add up over children)
    EXPECT_NEAR(projectedAreaPx(n, near), near.viewportPx, 1e-6);
    EXPECT_GT(nodeBenefit(s, n, near), near.viewportPx);
    std::vector<DrawItem> drawn = {{id, 0}};
    EXPECT_EQ(frontBenefit(s, drawn, p, [](uint32_t) { return false; }), 0);  // invisible nodes add nothing
    EXPECT_NEAR(frontBenefit(s, drawn, p, [](uint32_t) { return true; }), nodeBenefit(s, n, p), 1e-9);
}

namespace {

// Every node with children, from `views` random eyes around the skeleton's bounds: the sum of
// its children's benefit is at least its own (refining never lowers the benefit). Returns the
// number of (node, view) pairs checked.
size_t expectRefiningNeverLowersBenefit(const Skeleton& s, uint32_t views, uint32_t seed) {
    Box3f all = s.nodes[0].bounds;
    for (const Node& n : s.nodes) all = {{std::min(all.min.x, n.bounds.min.x), std::min(all.min.y, n.bounds.min.y),
                                          std::min(all.min.z, n.bounds.min.z)},
                                         {std::max(all.max.x, n.bounds.max.x), std::max(all.max.y, n.bounds.max.y),
                                          std::max(all.max.z, n.bounds.max.z)}};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.5, 1.5);
    size_t checked = 0;
    for (uint32_t v = 0; v < views; ++v) {
        Camera cam;
        cam.position[0] = all.min.x + u(rng) * (all.max.x - all.min.x);
        cam.position[1] = all.min.y + u(rng) * (all.max.y - all.min.y);
        cam.position[2] = all.min.z + u(rng) * (all.max.z - all.min.z + 50);
        Projection p = makeProjection(cam, 720);
        for (const Node& n : s.nodes) {
            if (n.firstChild == kNone) continue;
            double children = 0;
            for (uint32_t c = n.firstChild; c != kNone; c = s.nodes[c].nextSibling)
                children += nodeBenefit(s, s.nodes[c], p);
            double own = nodeBenefit(s, n, p);
            EXPECT_GE(children, own * (1 - 1e-6)) << "node " << n.id << " view " << v;
            ++checked;
        }
    }
    return checked;
}

}  // namespace

TEST(Benefit, RefiningNeverLowersTheBenefitOnFixtureTrees) {
    // Quadtrees whose children's areas add up to the parent's, errors falling (at random) with depth.
    std::mt19937 rng(7);
    for (uint32_t levels : {2u, 3u, 4u}) {
        Skeleton s = test::gridSkeleton(3, 2, levels, 512, 40);
        for (Node& n : s.nodes) {
            float parentError = n.parent == kNone ? 2.f : s.nodes[n.parent].geometricError;
            float share = std::uniform_real_distribution<float>(0, 1)(rng);
            n.geometricError = n.firstChild == kNone ? 0.f : parentError * share;
        }
        EXPECT_GT(expectRefiningNeverLowersBenefit(s, 200, levels), 0u);
    }
}

TEST(Benefit, RefiningNeverLowersTheBenefitOnAFixtureDatabase) {
    // The procedural database (tests/support/synthetic.h): real meshes, measured errors and areas.
    test::TempDir dir;
    std::string db = (dir.path / "db.hlod").string();
    SyntheticOptions o;
    o.blocksX = 3, o.levels = 4;
    writeSyntheticDatabase(db, o);
    const Database database = Database::open(db);
    const Skeleton& s = database.skeleton();
    for (const Node& n : s.nodes)
        if (n.parent != kNone) {
            ASSERT_LE(n.geometricError, s.nodes[n.parent].geometricError);  // the premise
        }
    EXPECT_GT(expectRefiningNeverLowersBenefit(s, 300, 11), 0u);
}

namespace {

// Frame 0 is warm-up.
PolicyRun run(const std::string& name, std::vector<double> actual, std::vector<double> benefit) {
    std::vector<FrameStats> frames;
    for (size_t i = 0; i < actual.size(); ++i) {
        FrameStats f;
        f.frame = i;
        f.targetMs = 10;
        f.actualMs = actual[i];
        f.benefit = benefit[i];
        f.selectionMs = 0.5 * i;
        f.trianglesPerLevel = {100, uint64_t(i)};
        f.distance = 2.0 * i;
        f.upToggles = i == 3;
        frames.push_back(f);
    }
    return policyRun(name, frames, 1);
}

}  // namespace

TEST(Compare, RowsAndGapsToTheOracle) {
    std::vector<PolicyRun> runs = {run("a", {99, 9, 11, 12}, {1, 50, 60, 80}), run("oracle", {99, 10, 10, 10}, {1, 100, 0, 80})};
    std::vector<double> gaps = benefitGaps(runs[0], runs[1]);
    EXPECT_NEAR(gaps[1], 0.5, 1e-12);
    EXPECT_TRUE(std::isnan(gaps[2]));  // the oracle's benefit is 0: no gap
    EXPECT_NEAR(gaps[3], 0, 1e-12);
    std::vector<CompareRow> rows = compareRows(runs, &runs[1]);
    ASSERT_EQ(rows.size(), 2u);
    const CompareRow& a = rows[0];
    EXPECT_EQ(a.counted, 3u);
    EXPECT_NEAR(a.frameMs.mean, 32.0 / 3, 1e-12);
    EXPECT_EQ(a.frameMs.max, 12);
    EXPECT_NEAR(a.relErrorP99, 0.2, 1e-12);  // |12 - 10| / 10
    EXPECT_NEAR(a.relErrorMean, 0.4 / 3, 1e-12);
    EXPECT_NEAR(a.benefitMean, 190.0 / 3, 1e-12);
    EXPECT_NEAR(a.gapMean, 0.25, 1e-12);  // frames 1 and 3
    EXPECT_NEAR(a.togglesPerFrame, 1.0 / 3, 1e-12);
    EXPECT_NEAR(a.togglesPerMetre, 1.0 / 4, 1e-12);  // 4 m from frame 1 to frame 3
    EXPECT_NEAR(a.selectionMs.max, 1.5, 1e-12);
    EXPECT_NEAR(a.trianglesMean, 102, 1e-12);
    EXPECT_NEAR(rows[1].gapMean, 0, 1e-12);
    std::vector<CompareRow> noOracle = compareRows(runs, nullptr);
    EXPECT_TRUE(std::isnan(noOracle[0].gapMean));
    std::ostringstream csv, text;
    writeCompareCsv(csv, noOracle);
    EXPECT_NE(csv.str().find("\na,4,3,"), std::string::npos) << csv.str();
    EXPECT_NE(csv.str().find(",,"), std::string::npos);  // the empty gap field
    writeCompareText(text, noOracle);
    EXPECT_NE(text.str().find("oracle"), std::string::npos);
    EXPECT_NE(compareJson(noOracle, {}).find("\"gap_mean\": null"), std::string::npos);
    // A camera that only turns has no toggles per metre: "-", empty, null (0 until stop 50).
    std::vector<PolicyRun> turning = {run("t", {99, 9, 11, 12}, {1, 50, 60, 80})};
    turning[0].summary.togglesPerDistance = std::nan("");  // summarize's rate of a camera that did not move
    std::vector<CompareRow> turned = compareRows(turning, nullptr);
    std::ostringstream turnedText, turnedCsv;
    writeCompareText(turnedText, turned);
    writeCompareCsv(turnedCsv, turned);
    EXPECT_NE(turnedText.str().find(" 0.3333         - "), std::string::npos) << turnedText.str();  // tog/frame, then tog/m
    EXPECT_NE(turnedCsv.str().find(",0.33333,,"), std::string::npos) << turnedCsv.str();
    EXPECT_NE(compareJson(turned, {}).find("\"toggles_per_metre\": null"), std::string::npos);
}

// Fixed step: frame i is sampled at i x step whatever the frames took; preload: every node
// resident before the first frame.
TEST(Compare, FixedStepReplayAndPreload) {
    Skeleton s = test::gridSkeleton(2, 2, 3, 512, 50);
    auto src = memorySource(s);
    CostModelRenderer renderer;
    PlayerOptions po;
    po.threadedLoader = false;
    po.preload = true;
    Player player(src, Constants{}, renderer, po);
    for (uint32_t id = 0; id < s.nodes.size(); ++id) EXPECT_TRUE(player.resident(id));
    CameraPath path;
    path.keys.resize(2);
    path.keys[1].time = 1;
    path.keys[1].position[0] = 10;
    ReplayOptions ro;
    ro.fixedStepMs = 40;
    auto frames = replayPath(player, path, ro);
    ASSERT_EQ(frames.size(), 26u);  // 0, 0.04, ..., 1.00 s
    for (size_t i = 0; i < frames.size(); ++i) EXPECT_NEAR(frames[i].timeSeconds, 0.04 * i, 1e-12);
    EXPECT_EQ(renderer.uploads(), s.nodes.size());  // nothing loaded twice, nothing evicted

    // Without a frame count the replay keeps at most frameCap frames (a day-long path at short
    // frames grew without bound before stop 36); a frame count given goes past it.
    path.keys[1].time = 86399;
    ro.frameCap = 30;
    EXPECT_EQ(replayPath(player, path, ro).size(), 30u);
    ro.maxFrames = 40;
    EXPECT_EQ(replayPath(player, path, ro).size(), 40u);
}
