// Out-of-core input: a single PLY/OBJ is parsed into spill files and streamed to the
// block grid. The streamed blocks must be the blocks of the in-memory split, whatever the buffer
// size; the streaming OBJ parser must refuse corrupt numbers and truncated lines.
#include "helpers.h"

#include "formats/validate.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace hlod::test {
namespace {

// A triangle as its three (position, uv) corners, rotated so the smallest corner comes first.
using Tri = std::array<std::array<float, 5>, 3>;

std::vector<Tri> triangles(const Piece& p) {
    std::vector<Tri> out;
    const MeshData& m = p.mesh;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        Tri tri;
        for (int c = 0; c < 3; ++c) {
            const uint32_t i = m.indices[3 * t + c];
            tri[c] = {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2], m.texcoords[2 * i], m.texcoords[2 * i + 1]};
        }
        std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
        out.push_back(tri);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// A terrain with a cell grid that cuts through triangles (cells are not multiples of the quads).
struct Fixture {
    TempDir dir;
    Piece input = terrain(90);
    GridSpec grid;
    Fixture() {
        writePly(dir.file("t.ply"), input.mesh, true);
        grid = chooseGrid(pieceBounds(input.mesh), input.mesh.triangleCount(), input.mesh.triangleCount() / 6, 0);
    }
    std::vector<CellFile> stream(uint64_t bufferBytes, ReadStats& stats) {
        const std::string spill = dir.file("raw");
        std::filesystem::create_directories(spill);
        RawMesh raw;
        raw.spillTo(spill);
        parsePly(dir.file("t.ply"), raw);
        return streamSplit(raw, grid, dir.path.string(), bufferBytes, "t.ply", stats, nullptr);
    }
};

TEST(StreamSplit, GivesTheBlocksOfTheInMemorySplitForAnyBufferSize) {
    Fixture f;
    ASSERT_GT(f.grid.cellsU * f.grid.cellsV, 4u);
    const std::vector<Piece> expected = splitByGrid(readMesh(f.dir.file("t.ply")).piece, f.grid);
    for (uint64_t buffer : {uint64_t(1), uint64_t(1) << 30}) {  // flush every 64 KiB per cell / never
        ReadStats stats;
        const std::vector<CellFile> cells = f.stream(buffer, stats);
        size_t nonEmpty = 0;
        for (const Piece& e : expected) nonEmpty += e.mesh.triangleCount() > 0;
        ASSERT_EQ(cells.size(), nonEmpty) << buffer;
        for (const CellFile& cell : cells) {
            const Piece got = loadPiece(cell.file);
            EXPECT_EQ(got.mesh.triangleCount(), cell.triangles);
            EXPECT_TRUE(triangles(got) == triangles(expected[cell.cell])) << "cell " << cell.cell << ", buffer " << buffer;
        }
        EXPECT_EQ(stats.degenerateDropped, 0u);
    }
}

// Issue #14: the parsed arrays stay in memory while they fit the budget and spill midway beyond
// it (spillBeyond), with the same contents as a parse spilled from the start.
TEST(RawMeshSpill, StaysInMemoryWithinItsBudgetAndSpillsMidwayBeyondIt) {
    Fixture f;
    const auto parse = [&](RawMesh& raw) {
        parsePly(f.dir.file("t.ply"), raw);
        raw.seal();
    };
    const std::string dir = f.dir.file("raw");
    std::filesystem::create_directories(dir);
    RawMesh atOnce;
    atOnce.spillTo(dir + "/.."), parse(atOnce);  // the reference: spilled before the first push
    const uint64_t bytes = atOnce.positions.size() * sizeof(float) + atOnce.triangles.size() * sizeof(RawTriangle);
    RawMesh within, beyond;
    within.spillBeyond(8 * bytes, dir), parse(within);  // capacity at most 2 x the bytes, spilled beyond budget / 2
    EXPECT_FALSE(within.positions.spilled());
    EXPECT_FALSE(std::filesystem::exists(dir + "/positions.raw"));
    beyond.spillBeyond(bytes / 2, dir), parse(beyond);
    EXPECT_TRUE(atOnce.positions.spilled());
    EXPECT_TRUE(beyond.positions.spilled() && beyond.triangles.spilled());
    EXPECT_EQ(std::filesystem::file_size(dir + "/positions.raw"), atOnce.positions.size() * sizeof(float));
    for (const RawMesh* raw : {&within, &beyond}) {
        ASSERT_EQ(raw->positions.size(), atOnce.positions.size());
        ASSERT_EQ(raw->triangles.size(), atOnce.triangles.size());
        EXPECT_EQ(std::memcmp(raw->positions.data(), atOnce.positions.data(), atOnce.positions.size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp(raw->triangles.data(), atOnce.triangles.data(), atOnce.triangles.size() * sizeof(RawTriangle)), 0);
    }
}

TEST(StreamSplit, NeighbouringBlocksShareTheirBorderVerticesExactly) {
    Fixture f;
    ReadStats stats;
    const std::vector<CellFile> cells = f.stream(1, stats);
    const float plane = f.grid.minU + f.grid.sizeU * 1.0f;  // the first grid line along U
    std::vector<std::array<float, 3>> left, right;
    for (const CellFile& cell : cells) {
        const uint32_t u = cell.cell % f.grid.cellsU;
        if (u > 1) continue;
        const Piece p = loadPiece(cell.file);
        for (size_t i = 0; i < p.mesh.vertexCount(); ++i)
            if (p.mesh.positions[3 * i + f.grid.axisU] == plane)
                (u == 0 ? left : right).push_back({p.mesh.positions[3 * i], p.mesh.positions[3 * i + 1], p.mesh.positions[3 * i + 2]});
    }
    std::sort(left.begin(), left.end()), std::sort(right.begin(), right.end());
    ASSERT_GT(left.size(), 10u);
    EXPECT_TRUE(left == right);  // bitwise: no crack between the blocks
}

TEST(StreamSplit, BuildOfOnePlyIsValidAndUsesNoMoreThanItsBlocks) {
    TempDir dir;
    const Piece p = terrain(80);
    writePly(dir.file("t.ply"), p.mesh, true);
    BuildRequest request;
    request.input = dir.file("t.ply");
    request.output = dir.file("t.hlod");
    request.options.blockTriangles = p.mesh.triangleCount() / 4;
    std::ostringstream log;
    Progress progress(log, false);
    const BuildSummary summary = runBuild(request, progress);
    EXPECT_GE(summary.blockCount, 4u);
    uint64_t split = 0;  // the in-memory split's triangles: the grid lines cut some triangles in three
    for (const Piece& c : splitByGrid(p, chooseGrid(pieceBounds(p.mesh), p.mesh.triangleCount(), request.options.blockTriangles, 0)))
        split += c.mesh.triangleCount();
    EXPECT_EQ(summary.inputTriangles, split);
    EXPECT_NE(log.str().find("read"), std::string::npos);
    EXPECT_TRUE(validate(Database::open(request.output), ValidateOptions{}).empty());
    for (const auto& entry : std::filesystem::directory_iterator(dir.path))  // temporaries removed
        EXPECT_EQ(entry.path().string().find("hlod-build-"), std::string::npos) << entry.path();
}

// A mesh file with no triangle at all (before stop 36: a division by zero cells, SIGFPE) is an
// input error naming the file, and no database is written.
TEST(StreamSplit, AMeshWithNoTrianglesIsAnEmptyMeshError) {
    TempDir dir;
    std::ofstream(dir.file("buf.bin"), std::ios::binary) << std::string(62, '\0');
    const std::pair<const char*, std::string> cases[] = {
        {"empty.obj", ""},
        {"comments.obj", "# nothing\n\n"},
        {"points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"},
        {"none.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 0\nproperty list uchar int vertex_indices\nend_header\n"},
        {"nomesh.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":99}],)"
                        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
                        R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
                        R"({"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}],)"
                        R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":12}],)"
                        R"("buffers":[{"byteLength":62,"uri":"buf.bin"}]})"},
    };
    for (const auto& [name, text] : cases) {
        std::ofstream(dir.file(name), std::ios::binary) << text;
        BuildRequest request;
        request.input = dir.file(name);
        request.output = dir.file("out.hlod");
        std::ostringstream log;
        Progress progress(log, false);
        EXPECT_EQ(errorOf([&] { runBuild(request, progress); }), request.input + ": empty mesh (no valid triangles)") << name;
        EXPECT_FALSE(std::filesystem::exists(request.output)) << name;
    }
}

// A tiny model: its position lattice follows its size (a lattice clamped at 1e-9 stored a model
// 2e-12 across with a part of its triangles, exit 0, until stop 45); below kMinExtent (float areas
// underflow) it is refused.
TEST(BuildRequestStream, TinyModelsKeepTheirTrianglesOrAreRefused) {
    TempDir dir;
    // Triangles stored at the leaves of a UV sphere of radius `r` (80 x 40 quads; those at the
    // poles r/2,600 across).
    auto leafTriangles = [&](double r) {
        MeshData sphere;
        const uint32_t n = 40;
        for (uint32_t i = 0; i <= n; ++i)
            for (uint32_t j = 0; j < 2 * n; ++j) {
                const double t = M_PI * i / n, p = M_PI * j / n;
                sphere.positions.insert(sphere.positions.end(), {float(r * std::sin(t) * std::cos(p)),
                                                                 float(r * std::sin(t) * std::sin(p)), float(r * std::cos(t))});
            }
        for (uint32_t i = 0; i < n; ++i)
            for (uint32_t j = 0; j < 2 * n; ++j) {
                const uint32_t a = i * 2 * n + j, b = i * 2 * n + (j + 1) % (2 * n);
                sphere.indices.insert(sphere.indices.end(), {a, a + 2 * n, b + 2 * n, a, b + 2 * n, b});
            }
        writePly(dir.file("t.ply"), sphere, true);
        BuildRequest request;
        request.input = dir.file("t.ply");
        request.output = dir.file("t.hlod");
        std::ostringstream log;
        Progress progress(log, false);
        runBuild(request, progress);
        const Database db = Database::open(request.output);
        uint32_t leafLevel = 0;
        uint64_t triangles = 0;
        for (const Node& n : db.skeleton().nodes) leafLevel = std::max(leafLevel, n.level);
        for (const Node& n : db.skeleton().nodes)
            if (n.level == leafLevel) triangles += n.texturedTriangles + n.untexturedTriangles;
        return triangles;
    };
    const uint64_t reference = leafTriangles(1e-3);
    EXPECT_GT(reference, 6000u);
    EXPECT_NEAR(double(leafTriangles(1e-12)), double(reference), 5);  // float rounding; ~1,000 fewer before stop 45
    EXPECT_EQ(errorOf([&] { leafTriangles(2.5e-13); }),
              dir.file("t.ply") + ": the model is 5e-13 units across, below the 1e-12 hlod builds (its triangles' float "
                                  "areas underflow): scale it up");
}

TEST(ReadObjStream, CorruptNumbersAndTruncatedLinesAreRefused) {
    TempDir dir;
    const std::pair<const char*, const char*> cases[] = {
        {"v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n", "t.obj:2: corrupt OBJ (bad number 'x')"},
        {"v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "vertex 1 has a NaN/Inf coordinate"},
        {"v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n", "vertex 1 has a NaN/Inf coordinate"},
        {"v 0 0 0\nv 1 0 2e37\nv 0 1 0\nf 1 2 3\n", "vertex 1 has a coordinate beyond 1e15 (the limit)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "corrupt OBJ (bad face index '0')"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n", "face index -7 out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2", "t.obj:5: truncated or corrupt OBJ (face with fewer than 3 vertices)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1", "t.obj:4: truncated or corrupt OBJ (missing number)"},
        // the face's line and the index as written (a fanned triangle's 0-based vertex until stop 46)
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n", "t.obj:5: face index 9 names one of 3 vertices"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/5\n", "t.obj:5: face index 5 names one of 1 texture coordinates"},
        {"f 1 2 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "t.obj:1: face index 4 names one of 3 vertices"},
    };
    for (const auto& [text, message] : cases) {
        std::ofstream(dir.file("t.obj")) << text;
        EXPECT_NE(errorOf([&] { readMesh(dir.file("t.obj")); }).find(message), std::string::npos)
            << text << "\n-> " << errorOf([&] { readMesh(dir.file("t.obj")); });
    }
    // A number below float's range is 0, as strtof reads it ("bad number" until stop 45); one
    // beyond it is refused.
    std::ofstream(dir.file("t.obj")) << "v 0 0 0\nv 1 0 7.5e-53\nv 0 1 -1e-4000\nf 1 2 3\n";
    const SourceMesh tiny = readMesh(dir.file("t.obj"));
    EXPECT_EQ(tiny.piece.mesh.positions[5], 0.0f);
    EXPECT_EQ(tiny.piece.mesh.positions[8], 0.0f);
    std::ofstream(dir.file("t.obj")) << "v 0 0 0\nv 1 0 1e39\nv 0 1 0\nf 1 2 3\n";
    EXPECT_EQ(errorOf([&] { readMesh(dir.file("t.obj")); }), dir.file("t.obj") + ":2: corrupt OBJ (bad number '1e39')");
    // A NUL in a token ended the message mid-quote (until stop 44); a long token is cut.
    std::ofstream(dir.file("t.obj")) << std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\0x\n", 34);
    EXPECT_EQ(errorOf([&] { readMesh(dir.file("t.obj")); }), dir.file("t.obj") + ":4: corrupt OBJ (bad face index '3\\x00x')");
    std::ofstream(dir.file("t.obj")) << "v 0 0 " << std::string(100, '7') << "z\n";
    EXPECT_EQ(errorOf([&] { readMesh(dir.file("t.obj")); }), dir.file("t.obj") + ":1: corrupt OBJ (bad number '" + std::string(40, '7') + "...')");
}

TEST(ReadObjStream, PolygonsNegativeIndicesAndMissingLibraries) {
    TempDir dir;
    std::ofstream(dir.file("q.obj")) << "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n";
    const SourceMesh s = readMesh(dir.file("q.obj"));
    EXPECT_EQ(s.piece.mesh.triangleCount(), 2u);  // the quad fanned
    EXPECT_EQ(s.piece.mesh.vertexCount(), 4u);
    ASSERT_EQ(s.stats.warnings.size(), 1u);
    EXPECT_NE(s.stats.warnings[0].find("material library 'nowhere.mtl' not found"), std::string::npos);
}

}  // namespace
}  // namespace hlod::test
