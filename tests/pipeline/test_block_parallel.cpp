// The nodes of one block built in parallel (build_tree.cpp: a top-down level's nodes, a bottom-up
// node's children's subtrees): a single-block build of several levels gives the same database
// bytes and the same per-node report at any -j, top-down and bottom-up (with either error), textured (the block's
// texture cache shared by the nodes) and not; several blocks at once with more cores than one
// block keeps busy, under a memory gate that admits one block at a time, finish with the same bytes.
#include "helpers.h"

#include "tests/support/chunked_scan.h"

#include <sstream>

namespace hlod::test {
namespace {

struct Built {
    std::vector<uint8_t> bytes;
    BuildSummary summary;
};

Built build(const std::string& input, const std::string& output, BuildOptions options, int jobs) {
    std::ostringstream log;
    Progress progress(log, false);
    BuildRequest r;
    options.jobs = jobs;
    r.input = input, r.output = output, r.options = options;
    Built b;
    b.summary = runBuild(r, progress);
    b.bytes = readFile(output);
    return b;
}

void expectSameNodes(const BuildSummary& a, const BuildSummary& b, int jobs) {
    ASSERT_EQ(a.nodes.size(), b.nodes.size()) << "-j " << jobs;
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        const NodeQuality &x = a.nodes[i], &y = b.nodes[i];
        EXPECT_TRUE(x.block == y.block && x.node == y.node && x.level == y.level && x.triangles == y.triangles &&
                    x.texels == y.texels && x.errorMax == y.errorMax && x.errorMean == y.errorMean && x.baked == y.baked &&
                    x.bakePsnrDb == y.bakePsnrDb && x.fidelitySquaredError == y.fidelitySquaredError)
            << "node " << i << " differs at -j " << jobs;
    }
}

// One block (blockTriangles above the input's), 5 levels (1 + 4 + 16 + 64 + 256 nodes).
BuildOptions oneBlock(BuildMode mode) {
    BuildOptions o;
    o.constants.desiredTris = 100;
    o.blockTriangles = 1'000'000;
    o.mode = mode;
    o.leafPsnr = true;  // the leaves read the source textures again
    return o;
}

void expectSameForAnyJobs(const std::string& input, const TempDir& dir, const BuildOptions& options) {
    const Built one = build(input, dir.file("j1.hlod"), options, 1);
    ASSERT_EQ(one.summary.blockCount, 1u);
    ASSERT_GE(one.summary.nodesPerLevel.size(), 4u);
    for (const int jobs : {2, 4}) {
        const Built many = build(input, dir.file("jn.hlod"), options, jobs);
        EXPECT_TRUE(one.bytes == many.bytes) << "-j " << jobs;
        expectSameNodes(one.summary, many.summary, jobs);
    }
}

TEST(BlockParallel, TexturedSingleBlockByteIdenticalForAnyJobsTopDown) {
    TempDir dir;
    ChunkedScanOptions scan;
    scan.chunks = 12, scan.chartCells = 2, scan.jpeg = true;  // fragmented charts: coarse nodes are baked
    const ChunkedScan input = writeChunkedScan(dir.path.string(), "facade", facadeMesh(100), scan);
    expectSameForAnyJobs(input.obj, dir, oneBlock(BuildMode::TopDown));
}

TEST(BlockParallel, TexturedSingleBlockByteIdenticalForAnyJobsBottomUp) {
    TempDir dir;
    ChunkedScanOptions scan;
    scan.chunks = 12, scan.chartCells = 2;
    const ChunkedScan input = writeChunkedScan(dir.path.string(), "facade", facadeMesh(100), scan);
    expectSameForAnyJobs(input.obj, dir, oneBlock(BuildMode::BottomUp));
}

// --bottom-up-error simplifier: no distance measured, the estimates of the children's subtrees
// combined in child order.
TEST(BlockParallel, TexturedSingleBlockByteIdenticalForAnyJobsSimplifierError) {
    TempDir dir;
    ChunkedScanOptions scan;
    scan.chunks = 12, scan.chartCells = 2;
    const ChunkedScan input = writeChunkedScan(dir.path.string(), "facade", facadeMesh(100), scan);
    BuildOptions o = oneBlock(BuildMode::BottomUp);
    o.bottomUpError = BottomUpError::Simplifier;
    expectSameForAnyJobs(input.obj, dir, o);
}

TEST(BlockParallel, UntexturedSingleBlockByteIdenticalForAnyJobs) {
    TempDir dir;
    writePly(dir.file("terrain.ply"), terrain(80).mesh, true);  // 12,800 triangles
    expectSameForAnyJobs(dir.file("terrain.ply"), dir, oneBlock(BuildMode::TopDown));
}

// 8 threads admit 2 blocks at once (build.cpp: blocksAtOnce); a 1-byte limit makes the second wait
// on the gate while the first's nodes run on every thread. No deadlock, and the same bytes.
TEST(BlockParallel, BlocksWaitingOnTheGateDoNotStallTheOthers) {
    TempDir dir;
    writePly(dir.file("terrain.ply"), terrain(80).mesh, true);
    BuildOptions o = oneBlock(BuildMode::TopDown);
    o.blockTriangles = 2000;
    const Built one = build(dir.file("terrain.ply"), dir.file("j1.hlod"), o, 1);
    ASSERT_GE(one.summary.blockCount, 4u);
    o.memoryLimit = 1;
    const Built many = build(dir.file("terrain.ply"), dir.file("j8.hlod"), o, 8);
    EXPECT_TRUE(one.bytes == many.bytes);
    expectSameNodes(one.summary, many.summary, 8);
}

}  // namespace
}  // namespace hlod::test
