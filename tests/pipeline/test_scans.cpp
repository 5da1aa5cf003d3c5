// Builds of the real scans in ../shared/datasets (bunny PLY ascii, Lucy PLY binary, banana OBJ
// with a 4096^2 atlas): the database validates with every blob decoded, levels follow the
// factors, errors are measured. Labelled slow (several seconds each; skipped under ASan).
#include "helpers.h"

#include "formats/validate.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hlod::test {
namespace {

struct Scan {
    const char* path;
    uint64_t triangles;
    bool textured;
};

class Scans : public ::testing::TestWithParam<Scan> {};

TEST_P(Scans, BuildValidatesAndFollowsTheFactors) {
    const std::string input = sharedDir() + "/datasets/" + GetParam().path;
    if (!std::filesystem::exists(input)) GTEST_SKIP() << "no " << input;
    TempDir dir;
    std::ostringstream log;
    Progress progress(log, false);
    BuildRequest r;
    r.input = input, r.output = dir.file("scan.hlod"), r.options.jobs = 2;
    const BuildSummary summary = runBuild(r, progress);
    EXPECT_GE(summary.inputTriangles, GetParam().triangles * 99 / 100);
    const Database db = Database::open(dir.file("scan.hlod"));
    for (const Violation& v : validate(db, ValidateOptions{})) ADD_FAILURE() << "node " << v.node << ": " << v.message;
    const Skeleton& s = db.skeleton();
    ASSERT_EQ(s.roots().size(), 1u);
    // hlod0 holds about c_desiredTris (900) triangles; each next level c_levelFactor (4) times more.
    std::vector<uint64_t> perLevel;
    for (const Node& n : s.nodes) {
        if (perLevel.size() <= n.level) perLevel.resize(n.level + 1);
        perLevel[n.level] += n.triangles();
        if (n.firstChild != kNone) {
            EXPECT_GT(n.geometricError, 0.0f) << "node " << n.id;
        }
        // Nodes simplified as geometry only (fragmented UVs, simplify.cpp) get a baked texture.
        if (GetParam().textured) {
            EXPECT_GT(n.texelCount, 0u) << "node " << n.id;
        }
    }
    // Stop 41 (--error-cap on): no node measures more than twice its parent's error
    // (pipeline/TREE.md: without the cap a level-1 node measured 7-8 x the root on these scans).
    const std::vector<NodeQuality>& measured = summary.nodes;
    ASSERT_EQ(measured.size(), s.nodes.size());
    for (const Node& n : s.nodes) {
        ASSERT_EQ(measured[n.id].level, n.level) << "node " << n.id;  // one block: breadth-first ids
        // The report's triangles are the stored ones: Draco drops faces its quantization collapses
        // (the banana's texture seams: 15 of 85 nodes counted 1-5 more until stop 48).
        EXPECT_EQ(measured[n.id].triangles, n.triangles()) << "node " << n.id;
        if (n.parent != kNone) {
            EXPECT_LE(measured[n.id].errorMax, 2 * measured[n.parent].errorMax) << "node " << n.id;
        }
    }
    for (size_t level = 0; level + 1 < perLevel.size(); ++level) {
        EXPECT_GE(perLevel[level], 0.8 * 900 * std::pow(4.0, double(level))) << "level " << level;
        // Issue #16: each level within 1.5 x its target, the banana's fragmented atlas included
        // (its coarse levels simplify the geometry alone where the UV seams stop the simplifier).
        EXPECT_LE(perLevel[level], 1.5 * 900 * std::pow(4.0, double(level))) << "level " << level;
        EXPECT_LT(perLevel[level], perLevel[level + 1]) << "level " << level;
    }
}

INSTANTIATE_TEST_SUITE_P(Real, Scans,
                         ::testing::Values(Scan{"A1_stanford_bunny/bun_zipper.ply", 69451, false},
                                           Scan{"A3_stanford_lucy_100k/Lucy100k.ply", 100000, false},
                                           Scan{"A2_ycb_011_banana_textured_scan/textured_simple_reoriented.obj", 15728, true}));

// Stop 43 (pipeline/TREE.md "Stop 43"): bottom-up, a node whose children are leaves gets no
// free-border reference, so no cap. It simplifies the original triangles by at most c_levelFactor
// (the default leaf rule), its locked border as fine as the rest. On the bunny each such node
// comes out as with the cap off (before, the cap bound 21 of its 64 and changed the triangle count
// of 19), and the nodes above are still capped.
TEST(ScanErrorCap, BottomUpLeavesParentsAreNotCapped) {
    const std::string input = sharedDir() + "/datasets/A1_stanford_bunny/bun_zipper.ply";
    if (!std::filesystem::exists(input)) GTEST_SKIP() << "no " << input;
    const auto build = [&](bool errorCap) {
        TempDir dir;
        std::ostringstream log;
        Progress progress(log, false);
        BuildRequest r;
        r.input = input, r.output = dir.file("b.hlod"), r.options.jobs = 1;
        r.options.mode = BuildMode::BottomUp, r.options.errorCap = errorCap;
        return runBuild(r, progress).nodes;
    };
    const std::vector<NodeQuality> capped = build(true), uncapped = build(false);
    ASSERT_EQ(capped.size(), uncapped.size());
    uint32_t leafLevel = 0;
    for (const NodeQuality& n : capped) leafLevel = std::max(leafLevel, n.level);
    size_t leavesParents = 0, cappedAbove = 0;
    for (size_t i = 0; i < capped.size(); ++i) {
        ASSERT_EQ(capped[i].level, uncapped[i].level);
        if (capped[i].level + 1 == leafLevel) {
            ++leavesParents;
            EXPECT_EQ(capped[i].triangles, uncapped[i].triangles) << "node " << capped[i].node;
        } else if (capped[i].level + 1 < leafLevel) {
            cappedAbove += capped[i].triangles != uncapped[i].triangles;
        }
    }
    EXPECT_EQ(leavesParents, 64u);
    EXPECT_GT(cappedAbove, 0u);
}

}  // namespace
}  // namespace hlod::test
