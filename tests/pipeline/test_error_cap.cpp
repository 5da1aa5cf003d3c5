// --error-cap on (stop 41, pipeline/TREE.md "Locked borders cost triangles, not accuracy"): a
// block's root whose shared sides keep their borders whole stops at kFreeBorderSlack (2) x the
// error the same piece reaches with no border locked, so its borders cost triangles rather than
// accuracy; with the cap off the root reaches its factor by merging the rest into long fans. A
// block with no shared side gets the same root as before.
#include "helpers.h"

#include <algorithm>

namespace hlod::test {
namespace {

BlockStats buildTerrain(bool errorCap, Sides shared, BuildMode mode = BuildMode::TopDown) {
    BuildOptions o;
    o.jobs = 1;
    o.mode = mode;
    o.errorCap = errorCap;
    o.constants.desiredTris = 300;  // factor 170.7: 640 locked border vertices leave little for the rest
    return buildBlock(terrain(160), {}, 0, o, nullptr, [](NodeRecord&&) {}, shared);
}

TEST(ErrorCap, ALockedRootKeepsItsFreeBordersAccuracy) {
    const BlockStats free = buildTerrain(true, 0), capped = buildTerrain(true, kAllSides), uncapped = buildTerrain(false, kAllSides);
    ASSERT_GT(free.measured[0].max, 0);
    // Measured when written: free 0.358, capped 0.720 (kFreeBorderSlack 2), uncapped 3.36.
    EXPECT_GT(uncapped.measured[0].max, 4 * free.measured[0].max) << "the case this option is for";
    EXPECT_LE(capped.measured[0].max, 3 * free.measured[0].max);
    EXPECT_LT(capped.measured[0].max, uncapped.measured[0].max / 3);
    EXPECT_GT(capped.triangles[0], uncapped.triangles[0]);
    EXPECT_EQ(buildTerrain(false, 0).triangles[0], free.triangles[0]) << "no shared side: the root is not capped";
}

// Top-down, a child stops at its parent's simplifier error: on the same block with no shared side
// the root is the same either way, and its level-1 slabs (two division planes locked each)
// measure 3.6 x the root without the cap, 0.79 x with it (when written).
TEST(ErrorCap, NoChildFarCoarserThanItsParent) {
    const auto worstLevel1 = [](const BlockStats& b) {
        double worst = 0;
        for (size_t i = 1; i < b.levels.size(); ++i)
            if (b.levels[i] == 1) worst = std::max(worst, b.measured[i].max);
        return worst;
    };
    const BlockStats capped = buildTerrain(true, 0), uncapped = buildTerrain(false, 0);
    ASSERT_EQ(capped.measured[0].max, uncapped.measured[0].max);
    EXPECT_GT(worstLevel1(uncapped), 2 * uncapped.measured[0].max) << "the case this option is for";
    EXPECT_LE(worstLevel1(capped), 1.5 * capped.measured[0].max);
}

// Bottom-up (--mode bottom-up, capped by default since stop 43) every node with shared sides is
// capped at twice its input's free-border error, the root included, but the leaves' parents
// (ScanErrorCap.BottomUpLeavesParentsAreNotCapped).
TEST(ErrorCap, BottomUpNodesKeepTheirFreeBordersAccuracy) {
    const BlockStats capped = buildTerrain(true, kAllSides, BuildMode::BottomUp);
    const BlockStats uncapped = buildTerrain(false, kAllSides, BuildMode::BottomUp);
    // Measured when written: capped 0.679 (736 triangles), uncapped 4.67 (638).
    EXPECT_LT(capped.measured[0].max, uncapped.measured[0].max / 3);
    EXPECT_GT(capped.triangles[0], uncapped.triangles[0]);
}

}  // namespace
}  // namespace hlod::test
