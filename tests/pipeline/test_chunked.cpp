// Chunked multi-atlas scans (issue #16): inputs cut into ~50 chunks with duplicated border
// vertices and one material and atlas per chunk (tests/support/chunked_scan.h), from a generated
// facade and from the Stanford bunny. The block is welded by position and simplified as one mesh
// (weld.cpp, simplify.cpp): every simplified level stays within kLevelSlack of its §3.2 target,
// hlod0 within kLevelSlack x c_desiredTris, and the coarse levels open no hole: the two-sided
// error (error.cpp) stays within kHoleRatio x the one-sided one at every level (a hole raises
// the first alone: TwoSidedErrorSeesAHole).
#include "helpers.h"

#include "formats/validate.h"
#include "tests/support/chunked_scan.h"
#include "tests/support/run_hlod.h"

#include "formats/build_report.h"

#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

namespace hlod::test {
namespace {

constexpr double kLevelSlack = 1.5;  // issue #16: "hlod0 <= 1.5 x c_desiredTris, each level <= 1.5 x its target"
// Two-sided / one-sided error per level: equal where the simplified surface covers the original,
// larger where it leaves a gap. Measured on these inputs (bench_chunked, pipeline/TREE.md): at
// most 1.14 welded; 1.30-1.93 on the coarse levels when the chunk borders are left unwelded
// (their copies 1e-6 x the extent apart, ChunkedScanOptions::jitter), which open gaps.
// Chosen for these inputs; a scan whose simplification drops whole features (the synthetic
// city's hlod0: 17.3 against 4.4) has a larger ratio without any hole.
constexpr double kHoleRatio = 1.25;

// Baked atlases against the chunks' textures downsampled for the level (bake.cpp's PSNR over
// covered texels): measured 27.0-37.5 dB on these inputs.
constexpr double kMinPsnr = 25;

struct Level {
    uint64_t nodes = 0, triangles = 0, maxTriangles = 0, baked = 0, untextured = 0;
    double minPsnr = 1e9;  // over the baked nodes
    double oneSided = 0, twoSided = 0, mean = 0;
};

struct Result {
    uint64_t triangles = 0;  // welded input
    std::vector<Level> levels;
};

Result buildChunked(const std::string& obj) {
    const SourceMesh source = readObj(obj);
    BuildOptions options;
    std::vector<std::pair<uint32_t, NodeInput>> nodes;
    const BlockStats stats = buildBlock(source.piece, source.materials, 0, options, nullptr,
                                        [&](NodeRecord&& r) { nodes.emplace_back(r.node.level, std::move(r.node)); });
    Result out;
    out.triangles = source.piece.mesh.triangleCount();
    for (size_t i = 0; i < nodes.size(); ++i) {
        const auto& [level, node] = nodes[i];
        if (out.levels.size() <= level) out.levels.resize(level + 1);
        Level& L = out.levels[level];
        uint64_t triangles = 0;
        bool textured = false;
        for (const EncodedBlob& b : node.blobs) {
            if (b.info.kind == BlobKind::Geometry) triangles += b.info.triangles;
            if (b.info.kind == BlobKind::Geometry && b.textureSlot != kNone) textured = true;
        }
        ++L.nodes, L.triangles += triangles, L.maxTriangles = std::max(L.maxTriangles, triangles);
        L.baked += stats.baked.at(i), L.untextured += !textured;
        if (stats.baked.at(i)) L.minPsnr = std::min(L.minPsnr, double(stats.bakePsnr.at(i)));
        const SurfaceError& e = stats.measured.at(i);
        L.oneSided = std::max(L.oneSided, e.oneSided), L.twoSided = std::max(L.twoSided, e.max);
        L.mean += e.mean;
    }
    for (Level& L : out.levels) L.mean /= double(std::max<uint64_t>(1, L.nodes));
    return out;
}

void expectTargetsAndNoHoles(const Result& r, const std::string& what) {
    const double desired = Constants{}.desiredTris, levelFactor = Constants{}.levelFactor;
    ASSERT_GE(r.levels.size(), 3u) << what;
    EXPECT_EQ(r.levels[0].nodes, 1u) << what;
    EXPECT_LE(double(r.levels[0].maxTriangles), kLevelSlack * desired) << what << ": hlod0";
    for (size_t l = 0; l < r.levels.size(); ++l) {
        const Level& L = r.levels[l];
        const double factor = double(r.triangles) / desired / std::pow(levelFactor, double(l));
        std::printf("%s level %zu: %llu nodes, %llu tris (target %.0f), baked %llu (PSNR >= %.1f dB), error one-sided %.4f "
                    "two-sided %.4f mean %.4f\n", what.c_str(), l, (unsigned long long)L.nodes, (unsigned long long)L.triangles,
                    double(r.triangles) / std::max(1.0, factor), (unsigned long long)L.baked, L.baked ? L.minPsnr : 0.0,
                    L.oneSided, L.twoSided, L.mean);
        if (factor <= 1) continue;  // leaves: the original triangles
        EXPECT_LE(double(L.triangles), kLevelSlack * double(r.triangles) / factor) << what << ": level " << l;
        EXPECT_GT(L.twoSided, 0.0) << what << ": level " << l;
        EXPECT_LE(L.twoSided, kHoleRatio * L.oneSided) << what << ": level " << l;
        // A node simplified with its seams keeps the chunks' atlases (cropped per chart); one
        // simplified as geometry only gets a baked atlas.
        EXPECT_EQ(L.untextured, 0u) << what << ": level " << l;
        if (L.baked) {
            EXPECT_GE(L.minPsnr, kMinPsnr) << what << ": level " << l;
        }
    }
}

TEST(Chunked, FacadeInFiftyChunksReachesEveryTargetWithoutHoles) {
    TempDir dir;
    const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(250), {});
    EXPECT_GE(scan.chunks, 40u);
    EXPECT_GT(scan.duplicatedVertices, 1000u);
    expectTargetsAndNoHoles(buildChunked(scan.obj), "facade");
}

TEST(Chunked, FacadeWithFragmentedChartsReachesEveryTargetWithoutHoles) {
    TempDir dir;
    ChunkedScanOptions options;
    options.chartCells = 4;
    const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(250), options);
    EXPECT_GE(scan.charts, 8 * scan.chunks);
    const Result r = buildChunked(scan.obj);
    expectTargetsAndNoHoles(r, "facade-fragmented");
    EXPECT_GT(r.levels[0].baked, 0u) << "fragmented charts stop seam-preserving simplification at hlod0";
}

TEST(Chunked, BunnyInFiftyChunksReachesEveryTargetWithoutHoles) {
    const std::string input = sharedDir() + "/datasets/A1_stanford_bunny/bun_zipper.ply";
    if (!std::filesystem::exists(input)) GTEST_SKIP() << "no " << input;
    const SourceMesh bunny = readPly(input);
    for (uint32_t chartCells : {1u, 4u}) {
        TempDir dir;
        ChunkedScanOptions options;
        options.chartCells = chartCells;
        const ChunkedScan scan = writeChunkedScan(dir.path.string(), "bunny", bunny.piece.mesh, options);
        EXPECT_GE(scan.chunks, 30u);
        expectTargetsAndNoHoles(buildChunked(scan.obj), "bunny-charts" + std::to_string(chartCells));
    }
}

TEST(Chunked, BuildOfChunkedFacadeValidates) {
    TempDir dir;
    const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(120), {});
    std::ostringstream log;
    Progress progress(log, false);
    BuildRequest r;
    r.input = scan.obj, r.output = dir.file("f.hlod"), r.options.jobs = 1;
    runBuild(r, progress);
    const Database db = Database::open(dir.file("f.hlod"));
    for (const Violation& v : validate(db, ValidateOptions{})) ADD_FAILURE() << "node " << v.node << ": " << v.message;
}

// Issue #14: a textured input gives the same bytes for any --memory-limit and -j (the grid and
// the textures, read by rectangles through the build's texture store, depend on neither). At
// 64 KiB the parsed OBJ spills to files; at 1 and 4 GiB it stays in memory (build.cpp rawFitsInMemory).
TEST(Chunked, TexturedBuildByteIdenticalForAnyMemoryLimitAndJobs) {
    TempDir dir;
    ChunkedScanOptions options;
    options.chartCells = 2, options.textureSize = 128, options.jpeg = true;
    const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(200), options);
    std::string first;
    for (const auto& [limit, jobs] : {std::pair<uint64_t, int>{uint64_t{1} << 30, 1}, {uint64_t{64} << 10, 2}, {uint64_t{4} << 30, 2}}) {
        std::ostringstream log;
        Progress progress(log, false);
        BuildRequest r;
        r.input = scan.obj, r.output = dir.file("f.hlod");
        r.options.constants.desiredTris = 600;
        r.options.blockTriangles = 8000;  // 3 blocks
        r.options.memoryLimit = limit, r.options.jobs = jobs;
        EXPECT_GT(runBuild(r, progress).blockCount, 1u);
        std::ifstream in(r.output, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (first.empty()) first = bytes;
        else EXPECT_TRUE(bytes == first) << "--memory-limit " << limit << " -j " << jobs;
    }
}

// `hlod build` reports what it measured per node (issue #16: texels, the two-sided error and the
// one-sided one, baked nodes with their PSNR) in DB.build.json, and `hlod stats` prints it per level.
TEST(Chunked, BuildReportAndStatsGiveEveryNodesMeasuredQuality) {
    TempDir dir;
    ChunkedScanOptions options;
    options.chartCells = 4;  // fragmented charts: hlod0 is baked
    const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(120), options);
    const std::string db = dir.file("f.hlod");
    const RunResult build = runHlod({"build", scan.obj, "-o", db, "-j", "1"});
    ASSERT_EQ(build.exitCode, 0) << build.outAndErr();
    const std::optional<BuildReport> report = readBuildReport(buildReportPath(db));
    ASSERT_TRUE(report);
    const Database database = Database::open(db);
    ASSERT_EQ(report->nodes.size(), database.skeleton().nodes.size());
    uint64_t baked = 0;
    for (const NodeQuality& n : report->nodes) {
        EXPECT_GE(n.errorMax, n.errorMean);
        EXPECT_GE(n.errorMax, n.errorOneSided);
        EXPECT_GT(n.texels, 0u) << "block " << n.block << " node " << n.node;
        if (!n.baked) continue;
        ++baked;
        EXPECT_GE(n.bakePsnrDb, 25.0) << "block " << n.block << " node " << n.node;
    }
    EXPECT_GT(baked, 0u);
    EXPECT_EQ(report->nodes.front().level, 0u);
    const RunResult stats = runHlod({"stats", db});
    ASSERT_EQ(stats.exitCode, 0) << stats.outAndErr();
    EXPECT_NE(stats.out.find("level 0: two-sided mean"), std::string::npos) << stats.out;
    EXPECT_NE(stats.out.find("nodes baked, PSNR min"), std::string::npos) << stats.out;
}

// Welding: positions within epsilon become one, a vertex on a bounding-box face never moves,
// degenerate triangles and coincident copies are dropped, and a vertex shared by two materials is split.
TEST(Weld, MergesNearDuplicatesAndSplitsMaterials) {
    Piece p;
    p.mesh.positions = {-1, -1, -1, 3, -1, -1, -1, 3, 3,             // the bounds: [-1, 3]^3
                        0, 0, 0.5f, 1, 0, 0.5f, 1, 1, 0.5f,          // triangle A (material 0)
                        1.0001f, 0, 0.5f, 2.9999f, 0, 0.5f, 1, 1.0001f, 0.5f,  // B (material 1): copies 1e-4 off
                        3, 0, 0.5f,                                   // on the face x = 3
                        0, 0, 0.50005f};                              // sliver (0, 10, 4)
    p.mesh.texcoords = std::vector<float>(22, 0.5f);
    p.mesh.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 4, 9, 5, 3, 10, 4};
    p.materials = {0, 0, 1, 1, 0};
    const Piece w = weldPiece(p, 0.001);
    // The sliver is degenerate once welded, and B, welded onto (1, 0), (3, 0), (1, 1), is a coincident
    // copy of the fourth triangle: dropped. At epsilon 0 nothing moves: all five stay.
    EXPECT_EQ(w.mesh.triangleCount(), 3u);
    EXPECT_EQ(weldPiece(p, 0).mesh.triangleCount(), 5u);
    std::set<std::array<float, 3>> positions;
    for (size_t i = 0; i < w.mesh.vertexCount(); ++i)
        positions.insert({w.mesh.positions[3 * i], w.mesh.positions[3 * i + 1], w.mesh.positions[3 * i + 2]});
    EXPECT_EQ(positions.size(), 7u);  // 3 bounds + 0, 1, 1' and the face vertex
    EXPECT_TRUE(positions.count({1, 0, 0.5f}) && positions.count({1, 1, 0.5f}));
    EXPECT_TRUE(positions.count({3, 0, 0.5f})) << "the face vertex stays; its near copy moves onto it";
    EXPECT_FALSE(positions.count({2.9999f, 0, 0.5f}));
    // (1, 0) and (1, 1) serve triangles of both materials: two vertices each.
    EXPECT_EQ(w.mesh.vertexCount(), 9u);
    EXPECT_EQ(weldPiece(p, 0).mesh.vertexCount(), 13u);  // epsilon 0: exact duplicates only
}

// A flat model: every vertex lies on a face of its bounding box (z = 0), so none moves; its exact
// copies still merge. Here an epsilon of 50 spans the whole 100 x 100 grid (as the lattice of a
// model with a triangle 10^6 away makes it): the weld looked the face vertices' copies up by
// scanning the cells around each, which held every vertex (quadratic; stop 52 looks them up by
// their bits). The grid is given twice, each copy with its own vertices. This locks the result,
// which the old lookup gave too, slowly; the speed is a figure (README "Reliability", stop 52).
TEST(Weld, AFlatModelKeepsItsVerticesAndMergesItsCopies) {
    Piece p = terrain(100, 100);
    for (size_t i = 2; i < p.mesh.positions.size(); i += 3) p.mesh.positions[i] = 0;
    const uint32_t n = static_cast<uint32_t>(p.mesh.vertexCount());
    const std::vector<uint32_t> once = p.mesh.indices;
    p.mesh.positions.insert(p.mesh.positions.end(), p.mesh.positions.begin(), p.mesh.positions.end());
    p.mesh.texcoords.insert(p.mesh.texcoords.end(), p.mesh.texcoords.begin(), p.mesh.texcoords.end());
    for (uint32_t i : once) p.mesh.indices.push_back(n + i);
    p.materials.insert(p.materials.end(), p.materials.begin(), p.materials.end());
    const Piece w = weldPiece(p, 50);
    EXPECT_EQ(w.mesh.triangleCount(), once.size() / 3);  // the copies coincide: dropped
    EXPECT_EQ(w.mesh.vertexCount(), n);
    std::set<std::array<float, 3>> before, after;
    for (size_t i = 0; i < n; ++i) before.insert({p.mesh.positions[3 * i], p.mesh.positions[3 * i + 1], 0});
    for (size_t i = 0; i < w.mesh.vertexCount(); ++i) after.insert({w.mesh.positions[3 * i], w.mesh.positions[3 * i + 1], w.mesh.positions[3 * i + 2]});
    EXPECT_EQ(after, before);  // no vertex moved
}

// The one-sided error cannot see a hole; the two-sided one measures it.
TEST(GeometricError, TwoSidedErrorSeesAHole) {
    const Piece p = terrain(100);
    SubMesh holed{0, p.mesh, {}};
    holed.mesh.indices.clear();
    for (size_t t = 0; t < p.mesh.triangleCount(); ++t) {
        const float* a = &p.mesh.positions[3 * p.mesh.indices[3 * t]];
        if (std::hypot(a[0] - 50, a[1] - 50) > 5)  // a hole of a tenth of the extent (100)
            holed.mesh.indices.insert(holed.mesh.indices.end(), p.mesh.indices.begin() + 3 * t, p.mesh.indices.begin() + 3 * t + 3);
    }
    const SurfaceError e = surfaceError({holed}, p.mesh, 100.0 / 20);
    EXPECT_LT(e.oneSided, 1e-4);
    EXPECT_GT(e.max, 3.0);  // the hole's centre lies ~5 from its rim
    EXPECT_GT(e.mean, 0.0);
}

// A side with no triangle of area (every one degenerate) is as far off as the other side is large,
// not 0: a node that shows nothing of its original must not claim to be exact.
TEST(GeometricError, ASideOfNoAreaIsAsFarOffAsTheOtherIsLarge) {
    const Piece p = terrain(100);
    const Box3f box = pieceBounds(p.mesh);
    const double diagonal = std::hypot(double(box.max.x) - box.min.x, double(box.max.y) - box.min.y, double(box.max.z) - box.min.z);
    SubMesh nothing{0, p.mesh, {}};
    nothing.mesh.indices = {0, 0, 1};  // one triangle, of no area
    const SurfaceError missing = surfaceError({nothing}, p.mesh, 100.0 / 20);
    EXPECT_EQ(missing.oneSided, 0.0);
    EXPECT_NEAR(missing.max, diagonal, 1e-3 * diagonal);
    const SurfaceError extra = surfaceError({SubMesh{0, p.mesh, {}}}, nothing.mesh, 100.0 / 20);
    EXPECT_NEAR(extra.oneSided, diagonal, 1e-3 * diagonal);
    EXPECT_EQ(extra.max, extra.oneSided);
    EXPECT_EQ(surfaceError({nothing}, nothing.mesh, 100.0 / 20).max, 0.0);
}

}  // namespace
}  // namespace hlod::test
