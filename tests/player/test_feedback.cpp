// The two feedback loops of thesis §4.2: v_time towards the measured rate (first loop); the
// hlod0 share raised while loaded nodes are refused and the frame is well under target, lowered
// while frames run well over, and clamped to [kMinShare, kMaxShare] x c_targetTime (second loop),
// in isolation and through the Player.
#include "player/cost_model_renderer.h"
#include "player/feedback.h"
#include "player/player.h"
#include "tests/support/memory_source.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

using namespace hlod;

TEST(Feedback, VTimeMovesGainTowardsMeasuredRate) {
    // measured (12 - 2) / 5000 = 0.002; 0.001 + 0.2 * (0.002 - 0.001)
    EXPECT_DOUBLE_EQ(nextVTime(0.001, 12, 2, 5000, 0.2), 0.0012);
    EXPECT_DOUBLE_EQ(nextVTime(0.001, 12, 2, 0, 0.2), 0.001);  // nothing drawn: unchanged
    EXPECT_DOUBLE_EQ(nextVTime(0.001, 1, 2, 5000, 1), 1e-9);   // under the overhead: floored
}

TEST(Feedback, ShareRaisedOnlyWhenRefusedAndWellUnder) {
    ShareLoop loop;  // band 0.1, step 0.05
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 20, 3, loop), 105);  // refused, 20 < 27
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 20, 0, loop), 100);  // nothing refused
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 27, 3, loop), 100);  // not "well" under
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 30, 3, loop), 100);  // in the band
}

TEST(Feedback, ShareLoweredWhenWellOverWhateverWasRefused) {
    ShareLoop loop;
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 34, 0, loop), 95);
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 34, 5, loop), 95);
    EXPECT_DOUBLE_EQ(nextHlod0Share(100, 30, 33, 5, loop), 100);  // not "well" over
}

TEST(Feedback, ShareClampedToBounds) {
    ShareLoop loop;
    EXPECT_DOUBLE_EQ(nextHlod0Share(590, 30, 10, 1, loop), kMaxShare * 30);
    EXPECT_DOUBLE_EQ(nextHlod0Share(3.1, 30, 50, 0, loop), kMinShare * 30);
    EXPECT_DOUBLE_EQ(nextHlod0Share(1e6, 30, 30, 0, loop), kMaxShare * 30);  // clamped in the band too
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
// frame (the root alone, 2.5 ms) is far under the 30 ms target: the share grows by 5% a frame
// up to kMaxShare x target and stays there.
TEST(Feedback, PlayerRaisesShareWhileLoadedNodesAreRefused) {
    OneBlock b(512, 1e6);
    Player player(memorySource(b.s), b.c, b.renderer, b.options());
    double share = player.hlod0ShareMs();
    EXPECT_NEAR(share, 30 - 2, 1e-9);  // the first share: target less the fixed overhead
    uint32_t raised = 0;
    for (int f = 0; f < 200; ++f) {
        FrameStats s = player.frame(b.camera, f * 0.03);
        ASSERT_EQ(s.nodesPerLevel[1], 0u);
        double expected = std::min(share * 1.05, kMaxShare * 30);
        if (s.refused > 0) {
            ASSERT_NEAR(player.hlod0ShareMs(), expected, 1e-9) << f;
            ++raised;
        }
        share = player.hlod0ShareMs();
    }
    EXPECT_GT(raised, 190u);  // refused from the frame the children were loaded
    EXPECT_DOUBLE_EQ(share, kMaxShare * 30);
}

// The hlod0 node alone takes 62 ms, over target * 1.1: the share shrinks by 5% a frame down to
// kMinShare x target; the root is still drawn (hlod0 is never skipped).
TEST(Feedback, PlayerLowersShareWhileFramesRunOver) {
    OneBlock b(60000, 1e6);
    Player player(memorySource(b.s), b.c, b.renderer, b.options());
    double share = player.hlod0ShareMs();
    for (int f = 0; f < 100; ++f) {
        FrameStats s = player.frame(b.camera, f * 0.06);
        ASSERT_GT(s.actualMs, 33) << f;
        ASSERT_EQ(s.nodesPerLevel[0], 1u);
        ASSERT_NEAR(player.hlod0ShareMs(), std::max(share * 0.95, kMinShare * 30), 1e-9) << f;
        share = player.hlod0ShareMs();
    }
    EXPECT_DOUBLE_EQ(share, kMinShare * 30);
}
