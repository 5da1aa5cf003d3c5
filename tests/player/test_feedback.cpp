// The two feedback loops of thesis §4.2: v_time towards the measured rate (first loop); the
// hlod0 share raised "gradually" while loaded nodes are refused and the frame is well under
// target, lowered while frames run well over, never by more than its step, kept within
// [kMinShare, kMaxShare] x c_targetTime and not stuck at a bound (second loop), in isolation
// and through the Player.
#include "player/cost_model_renderer.h"
#include "player/feedback.h"
#include "player/player.h"
#include "tests/support/memory_source.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace hlod;

TEST(Feedback, VTimeMovesGainTowardsMeasuredRate) {
    // measured (12 - 2) / 5000 = 0.002; 0.001 + 0.2 * (0.002 - 0.001)
    EXPECT_DOUBLE_EQ(nextVTime(0.001, 12, 2, 5000, 0.2), 0.0012);
    EXPECT_DOUBLE_EQ(nextVTime(0.001, 12, 2, 0, 0.2), 0.001);  // nothing drawn: unchanged
    EXPECT_DOUBLE_EQ(nextVTime(0.001, 1, 2, 5000, 1), 1e-9);   // under the overhead: floored
}

// With the leak off, ln(share) moves by gain x the relative error, only outside the band.
TEST(Feedback, ShareMovesByGainTimesRelativeErrorOutsideTheBand) {
    ShareLoop loop;
    loop.gain = 0.05;
    loop.leak = 0;
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 15, 3, loop), 100 * (1 + 0.05 * 0.5));  // refused, e = 0.5
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 15, 0, loop), 100);                     // nothing refused
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 27.5, 3, loop), 100);                   // in the band
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 36, 0, loop), 100 * (1 - 0.05 * 0.2));  // over, whatever refused
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 36, 5, loop), 100 * (1 - 0.05 * 0.2));
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 300, 0, loop), 100 * (1 - loop.step));  // e = -9: limited to the step
    loop.gain = 1e9;  // the bang-bang loop of earlier versions: +-step whenever outside the band
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 26, 3, loop), 105);
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 34, 0, loop), 95);
}

// The default controller: the share moves in the direction of the error (or, inside the band,
// back towards the target), never by more than `step`, and stays within the bounds.
TEST(Feedback, ShareMovesTheRightWayNeverMoreThanItsStep) {
    ShareLoop loop;
    for (double share : {3.0, 10.0, 30.0, 100.0, 599.0, 600.0})
        for (double actual : {0.0, 5.0, 20.0, 26.0, 30.0, 34.0, 40.0, 90.0, 1000.0})
            for (uint32_t refused : {0u, 2u}) {
                double next = nextHlod0Share(share, 30, actual, refused, loop);
                EXPECT_LE(std::abs(next / share - 1), loop.step + 1e-12) << share << " " << actual;
                EXPECT_GE(next, kMinShare * 30);
                EXPECT_LE(next, kMaxShare * 30);
                const double e = (30 - actual) / 30;
                if (e > loop.band && refused > 0 && share <= 30) {
                    EXPECT_GT(next, share) << share << " " << actual;
                }
                if (e < -loop.band && share >= 30) {
                    EXPECT_LT(next, share) << share << " " << actual;
                }
                if (std::abs(e) <= loop.band) {
                    EXPECT_EQ(next > share, share < 30) << share << " " << actual;
                }
            }
}

// A synthetic plant with the lag of the hysteresis counters: the frame time follows the share of
// `lag` frames before (target reached at a share of 10 x target), noisy, and loaded nodes are
// always refused. The bang-bang loop rides its bounds; the proportional loop does not stick there.
TEST(Feedback, ShareDoesNotStickAtABoundWithALaggingPlant) {
    auto atBounds = [](const ShareLoop& loop) {
        const int lag = 50, frames = 6000;
        std::vector<double> share(frames, 28);
        uint64_t seed = 1;
        int stuck = 0;
        for (int f = 1; f < frames; ++f) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            double noise = 0.9 + 0.2 * double(seed >> 11) / double(1ull << 53);
            double actual = 30 * noise * share[std::max(f - lag, 0)] / 300;
            share[f] = nextHlod0Share(share[f - 1], 30, actual, 1, loop);
            bool atBound = share[f] <= kMinShare * 30 * (1 + 1e-9) || share[f] >= kMaxShare * 30 * (1 - 1e-9);
            stuck += f >= 1000 && atBound;
        }
        return double(stuck) / (frames - 1000);
    };
    ShareLoop proportional;
    EXPECT_LT(atBounds(proportional), 0.01);
    ShareLoop bangBang;
    bangBang.gain = 1e9;
    bangBang.leak = 0;
    EXPECT_GT(atBounds(bangBang), 0.2);  // the plant is one the old loop could not hold
}

namespace {

// One root of 50 m seen from above, with four children; `rootTriangles` sets the true frame
// time (cost model: 1e-3 ms per triangle), `childCost` the cost_n the selection sees.
struct OneBlock {
    Skeleton s;
    CostModelRenderer renderer;
    Constants c;
    Camera camera;
    OneBlock(uint32_t rootTriangles, float childCost) : renderer(model()) {
        Box3f block{{0, 0, 0}, {50, 50, 10}};
        uint32_t root = test::addNode(s, kNone, block, rootTriangles);
        for (int q = 0; q < 4; ++q) {
            Box3f b = block;
            (q & 1 ? b.min.x : b.max.x) = 25;
            (q & 2 ? b.min.y : b.max.y) = 25;
            test::addNode(s, root, b, 512, childCost);
        }
        test::linkSkeleton(s);
        camera.position[0] = camera.position[1] = 25;
        camera.position[2] = 100;  // looking down -Z at the whole block
    }
    static CostModel model() {
        CostModel m;
        m.msPerTexturedTriangle = 1e-3;
        m.noise = 0;
        return m;
    }
    PlayerOptions options() const {
        PlayerOptions po;
        po.threadedLoader = false;
        return po;
    }
};

}  // namespace

// The children are loaded but far too costly for their slices (cumHyst < 0: refused) and the
// frame (the root alone, 2.5 ms) is far under the 30 ms target: the share grows every frame, by
// at most the step, up to kMaxShare x target (no frame ever fills: the leak cannot hold it).
TEST(Feedback, PlayerRaisesShareWhileLoadedNodesAreRefused) {
    OneBlock b(512, 1e6);
    Player player(memorySource(b.s), b.c, b.renderer, b.options());
    double share = player.hlod0ShareMs();
    EXPECT_NEAR(share, 30 - 2, 1e-9);  // the first share: target less the fixed overhead
    uint32_t raised = 0;
    for (int f = 0; f < 200; ++f) {
        FrameStats s = player.frame(b.camera, f * 0.03);
        ASSERT_EQ(s.nodesPerLevel[1], 0u);
        if (s.refused > 0) {
            ASSERT_TRUE(player.hlod0ShareMs() > share || player.hlod0ShareMs() == kMaxShare * 30) << f;
            ASSERT_LE(player.hlod0ShareMs(), share * (1 + b.options().shareLoop.step) + 1e-9) << f;
            ++raised;
        }
        share = player.hlod0ShareMs();
    }
    EXPECT_GT(raised, 190u);  // refused from the frame the children were loaded
    EXPECT_GT(share, 3 * 30);
}

// The hlod0 node alone takes 62 ms, over target * 1.1: the share shrinks every frame, by at most
// the step, towards kMinShare x target; the root is still drawn (hlod0 is never skipped).
TEST(Feedback, PlayerLowersShareWhileFramesRunOver) {
    OneBlock b(60000, 1e6);
    Player player(memorySource(b.s), b.c, b.renderer, b.options());
    double share = player.hlod0ShareMs();
    for (int f = 0; f < 60; ++f) {
        FrameStats s = player.frame(b.camera, f * 0.06);
        ASSERT_GT(s.actualMs, 33) << f;
        ASSERT_EQ(s.nodesPerLevel[0], 1u);
        ASSERT_LT(player.hlod0ShareMs(), share) << f;
        ASSERT_GE(player.hlod0ShareMs(), std::max(share * (1 - b.options().shareLoop.step), kMinShare * 30) - 1e-9) << f;
        share = player.hlod0ShareMs();
    }
    EXPECT_LT(share, 0.5 * 30);
}
