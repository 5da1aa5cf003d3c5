// Texture fidelity and size (issue #14, pipeline/TEXTURE_SIZE.md): a leaf's stored texture
// against the source texels its triangles use (texture_fidelity.cpp) - a lossless copy reads
// 100 dB, JPEG a finite PSNR that rises with the quality, a copy off by one texel far less;
// `hlod build --leaf-psnr` writes it per leaf in the build report and `hlod stats` prints it per
// level. What makes the textures smaller (texture.cpp): only the source's 8 x 8 blocks that
// triangles reach, on its grid, and a JPEG source's own quality read back (jpeg_quality.cpp) and
// never exceeded.
#include "helpers.h"

#include "formats/build_report.h"
#include "formats/metrics.h"
#include "pipeline/chart.h"
#include "pipeline/texture_charts.h"
#include "tests/support/chunked_scan.h"
#include "tests/support/run_hlod.h"

#include <array>
#include <random>
#include <set>
#include <tuple>

namespace hlod::test {
namespace {

double jpegPsnr(const MeshData& before, const Image& source, int quality, bool chroma420 = false) {
    MeshData after = before;
    const Image atlas = atlasTexture(textureView(source), 1, after);
    const EncodedBlob blob = encodeTexture(atlas, Codec::Jpeg, quality, chroma420);
    const TextureFidelity f = textureFidelity(before, textureView(source), after, decodeTexture(blob.bytes, Codec::Jpeg, "test"));
    return psnrDb(f.squaredError, f.samples);
}

TEST(TextureFidelity, LosslessCopyReads100AndEveryUsedTexelOnce) {
    const Image source = noisyImage(256);
    const MeshData before = chartsOver256();
    MeshData after = before;
    const Image atlas = atlasTexture(textureView(source), 1, after);
    const TextureFidelity f = textureFidelity(before, textureView(source), after, atlas);
    EXPECT_EQ(f.squaredError, 0);
    EXPECT_EQ(f.samples, 3 * f.texels);
    EXPECT_NEAR(psnrDb(f.squaredError, f.samples), 100, 1e-9);
    // The UV area of the triangles in texels: the texels whose centres they cover, each once.
    double area = 0;
    for (size_t t = 0; t < before.triangleCount(); ++t) {
        const float* a = &before.texcoords[2 * before.indices[3 * t]];
        const float* b = &before.texcoords[2 * before.indices[3 * t + 1]];
        const float* c = &before.texcoords[2 * before.indices[3 * t + 2]];
        area += 0.5 * std::abs(double(b[0] - a[0]) * (c[1] - a[1]) - double(c[0] - a[0]) * (b[1] - a[1])) * 256 * 256;
    }
    EXPECT_NEAR(double(f.texels), area, 0.05 * area);
    EXPECT_LT(f.texels, uint64_t(atlas.width) * atlas.height);
}

TEST(TextureFidelity, JpegIsFiniteAndRisesWithQuality) {
    const Image source = noisyImage(256);
    const double q50 = jpegPsnr(chartsOver256(), source, 50), q85 = jpegPsnr(chartsOver256(), source, 85), q95 = jpegPsnr(chartsOver256(), source, 95);
    EXPECT_GT(q50, 20);
    EXPECT_LT(q50, q85);
    EXPECT_LT(q85, q95);
    EXPECT_LT(q95, 60);
    EXPECT_LT(jpegPsnr(chartsOver256(), source, 85, true), q85);  // 4:2:0 drops chroma detail
}

TEST(TextureFidelity, AStoredTextureOffByOneTexelIsSeen) {
    const Image source = noisyImage(256);
    const MeshData before = chartsOver256();
    MeshData after = before;
    Image atlas = atlasTexture(textureView(source), 1, after);
    Image shifted = atlas;  // the same UVs over the atlas moved one texel right
    for (uint32_t y = 0; y < atlas.height; ++y)
        for (uint32_t x = 1; x < atlas.width; ++x)
            for (int c = 0; c < 3; ++c)
                shifted.pixels[(size_t(y) * atlas.width + x) * 3 + c] = atlas.pixels[(size_t(y) * atlas.width + x - 1) * 3 + c];
    const TextureFidelity f = textureFidelity(before, textureView(source), after, shifted);
    EXPECT_LT(psnrDb(f.squaredError, f.samples), jpegPsnr(before, source, 50));
}

// `hlod build --leaf-psnr`: every textured leaf has a measure, no other node; stats prints it.
TEST(TextureFidelity, BuildReportsLeavesAndStatsPrintsThem) {
    TempDir dir;
    ChunkedScanOptions options;
    options.chartCells = 2;
    options.jpeg = true;
    options.textureSize = 128;
    const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(60), options);
    const std::string db = dir.file("f.hlod");
    const RunResult build = runHlod({"build", scan.obj, "-o", db, "-j", "1", "--leaf-psnr"});
    ASSERT_EQ(build.exitCode, 0) << build.outAndErr();
    const std::optional<BuildReport> report = readBuildReport(buildReportPath(db));
    ASSERT_TRUE(report);
    const Database database = Database::open(db);
    ASSERT_EQ(report->nodes.size(), database.skeleton().nodes.size());
    uint64_t leaves = 0;
    for (size_t i = 0; i < report->nodes.size(); ++i) {
        const NodeQuality& n = report->nodes[i];
        const bool leaf = database.skeleton().nodes[i].firstChild == kNone;
        if (!leaf) {
            EXPECT_EQ(n.fidelitySamples, 0u) << i;
            continue;
        }
        ++leaves;
        EXPECT_GT(n.fidelityTexels, 0u) << i;
        EXPECT_LE(n.fidelityTexels, n.texels) << i;
        EXPECT_GE(psnrDb(n.fidelitySquaredError, n.fidelitySamples), 35) << i;  // smooth source, JPEG 85 4:4:4
        EXPECT_LT(psnrDb(n.fidelitySquaredError, n.fidelitySamples), 100) << i;
    }
    EXPECT_GT(leaves, 1u);
    const RunResult stats = runHlod({"stats", db});
    ASSERT_EQ(stats.exitCode, 0) << stats.outAndErr();
    EXPECT_NE(stats.out.find("stored textures vs source PSNR"), std::string::npos) << stats.out;
    const RunResult plain = runHlod({"build", scan.obj, "-o", dir.file("g.hlod"), "-j", "1"});
    ASSERT_EQ(plain.exitCode, 0) << plain.outAndErr();
    EXPECT_EQ(readFile(db), readFile(dir.file("g.hlod")));  // the measure changes no byte of the database
}

// Whether a triangle of `m` (UVs x w, h) comes within 2 texels (texture.cpp's kReach) of block (bx, by).
bool reached(const MeshData& m, const std::vector<size_t>& triangles, double w, double h, int bx, int by) {
    for (const size_t t : triangles) {
        double x[3], y[3];
        for (int k = 0; k < 3; ++k) x[k] = m.texcoords[2 * m.indices[3 * t + k]] * w, y[k] = m.texcoords[2 * m.indices[3 * t + k] + 1] * h;
        if (triangleMeetsBox(x, y, bx * 8 - 2, by * 8 - 2, bx * 8 + 10, by * 8 + 10)) return true;
    }
    return false;
}

// A leaf's atlas holds the 8 x 8 blocks of the source that its triangles reach, each at the same
// place within the block grid, and no other: an atlas block holds texels (the noisy source's
// blocks are never flat) iff a triangle reaches it, and there are fewer of them than the blocks of
// the charts' bounding rectangles (the second chart's one triangle leaves about half of its
// rectangle unreached). Every empty block is flat in a stored block's mean colour, not black.
TEST(TextureSize, AtlasesHoldOnlyTheBlocksTrianglesReachOnTheSourceGrid) {
    const Image source = noisyImage(256);
    const MeshData before = chartsOver256();
    MeshData after = before;
    const Image atlas = atlasTexture(textureView(source), 1, after);
    for (size_t v = 0; v < before.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a) {  // the same place within an 8 x 8 block in the source and the atlas
            const double s = before.texcoords[2 * v + a] * 256.0, t = after.texcoords[2 * v + a] * double(a ? atlas.height : atlas.width);
            EXPECT_NEAR(std::fmod(s, 8.0), std::fmod(t, 8.0), 1e-3) << v;
        }
    const std::vector<size_t> all = {0, 1, 2};
    const uint32_t columns = atlas.width / 8, rows = atlas.height / 8;
    const auto flat = [&](uint32_t bx, uint32_t by) {
        bool same = true;
        const uint8_t* first = &atlas.pixels[(size_t(by * 8) * atlas.width + bx * 8) * 3];
        for (uint32_t y = 0; y < 8; ++y)
            for (uint32_t x = 0; x < 8; ++x) same = same && std::equal(first, first + 3, &atlas.pixels[(size_t(by * 8 + y) * atlas.width + bx * 8 + x) * 3]);
        return same;
    };
    std::set<std::array<uint8_t, 3>> means;  // of the stored blocks, rounded half up
    for (uint32_t by = 0; by < rows; ++by)
        for (uint32_t bx = 0; bx < columns; ++bx) {
            uint32_t sum[3] = {0, 0, 0};
            for (uint32_t y = 0; y < 8; ++y)
                for (uint32_t x = 0; x < 8; ++x)
                    for (int c = 0; c < 3; ++c) sum[c] += atlas.pixels[(size_t(by * 8 + y) * atlas.width + bx * 8 + x) * 3 + c];
            if (!flat(bx, by)) means.insert({uint8_t((sum[0] + 32) / 64), uint8_t((sum[1] + 32) / 64), uint8_t((sum[2] + 32) / 64)});
        }
    uint64_t stored = 0, padded = 0;
    for (uint32_t by = 0; by < rows; ++by)
        for (uint32_t bx = 0; bx < columns; ++bx) {
            stored += !flat(bx, by);
            EXPECT_EQ(!flat(bx, by), reached(after, all, atlas.width, atlas.height, int(bx), int(by))) << bx << ", " << by;
            if (!flat(bx, by)) continue;
            const uint8_t* texel = &atlas.pixels[(size_t(by * 8) * atlas.width + bx * 8) * 3];
            EXPECT_TRUE(means.count({texel[0], texel[1], texel[2]})) << bx << ", " << by;  // a stored block's mean (not black)
            ++padded;
        }
    EXPECT_GT(padded, 0u);
    uint64_t rectangles = 0;  // blocks of each chart's bounding rectangle, reach included
    for (const std::vector<size_t>& chart : {std::vector<size_t>{0, 1}, std::vector<size_t>{2}}) {
        double lo[2] = {1, 1}, hi[2] = {0, 0};
        for (const size_t t : chart)
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 2; ++a) {
                    const double uv = before.texcoords[2 * before.indices[3 * t + k] + a];
                    lo[a] = std::min(lo[a], uv), hi[a] = std::max(hi[a], uv);
                }
        rectangles += uint64_t(std::floor((hi[0] * 256 + 2) / 8) - std::floor((lo[0] * 256 - 2) / 8) + 1) *
                      uint64_t(std::floor((hi[1] * 256 + 2) / 8) - std::floor((lo[1] * 256 - 2) / 8) + 1);
    }
    EXPECT_GT(stored, 0u);
    EXPECT_LT(double(stored), 0.85 * double(rectangles)) << stored << " of " << rectangles;
    const TextureFidelity f = textureFidelity(before, textureView(source), after, atlas);
    EXPECT_EQ(f.squaredError, 0);  // every texel a triangle uses is the source's
}

// Two charts (separate triangles) inside one 8 x 8 block of the source share it: the atlas stores
// that block once, and both charts' UVs land in it at their places within the block.
TEST(TextureSize, ChartsReachingOneBlockShareIt) {
    const Image source = noisyImage(256);
    MeshData mesh;
    mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 0, 6, 5, 0, 5, 6, 0};
    mesh.texcoords = {42.5f / 256, 42.5f / 256, 43.5f / 256, 42.5f / 256, 42.5f / 256, 43.5f / 256,  // block (5, 5), 2.5 texels inside
                      44.5f / 256, 44.5f / 256, 45.5f / 256, 44.5f / 256, 44.5f / 256, 45.5f / 256};
    mesh.indices = {0, 1, 2, 3, 4, 5};
    MeshData after = mesh;
    const Image atlas = atlasTexture(textureView(source), 1, after);
    EXPECT_EQ(atlas.width, 8u);
    EXPECT_EQ(atlas.height, 8u);
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a) EXPECT_NEAR(after.texcoords[2 * v + a] * 8, mesh.texcoords[2 * v + a] * 256 - 40, 1e-3) << v;
}

// One triangle with the given UVs.
MeshData oneTriangle(std::vector<float> texcoords) {
    MeshData m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    m.texcoords = std::move(texcoords);
    m.indices = {0, 1, 2};
    return m;
}

// A one-channel source whose sides are not multiples of 8 (100 x 60): a triangle reaching its right
// and bottom edges keeps its texels exactly, and the edge blocks repeat the edge texels past the
// texture; a triangle whose UVs reach far outside [0, 1] but covers the whole texture keeps every
// block (its vertices clamped one by one would not).
TEST(TextureSize, EdgeBlocksAndUvsBeyondTheTexture) {
    Image source{100, 60, 1, std::vector<uint8_t>(6000)};
    for (size_t i = 0; i < source.pixels.size(); ++i) source.pixels[i] = static_cast<uint8_t>(20 + (i * 2654435761u >> 13) % 200);
    const MeshData edge = oneTriangle({0.8f, 0.7f, 1.0f, 0.9f, 0.85f, 1.0f});
    MeshData after = edge;
    const Image atlas = atlasTexture(textureView(source), 1, after);
    const TextureFidelity f = textureFidelity(edge, textureView(source), after, atlas);
    EXPECT_GT(f.texels, 0u);
    EXPECT_EQ(f.squaredError, 0);
    const int dx = static_cast<int>(std::lround(after.texcoords[2] * atlas.width - 100));  // source x -> atlas x
    const int dy = static_cast<int>(std::lround(after.texcoords[5] * atlas.height - 60));
    for (int y = 56; y < 64; ++y)  // the bottom-right block: columns 96..103, rows 56..63 of the source's grid
        for (int x = 96; x < 104; ++x)
            EXPECT_EQ(atlas.pixels[size_t(y + dy) * atlas.width + size_t(x + dx)],
                      source.pixels[size_t(std::min(y, 59)) * 100 + size_t(std::min(x, 99))]) << x << ", " << y;

    MeshData wide = oneTriangle({-1.0f, 0.0f, 2.0f, 0.0f, 0.5f, 3.0f});
    const Image all = atlasTexture(textureView(source), 1, wide);
    ASSERT_EQ(uint64_t(all.width) * all.height, 13u * 8u * 64u);  // 13 x 8 blocks
    for (uint32_t by = 0; by < 8; ++by)
        for (uint32_t bx = 0; bx < 13; ++bx) {  // every one stored: not flat (the noise never is)
            bool same = true;
            for (uint32_t y = 0; y < 8; ++y)
                for (uint32_t x = 0; x < 8; ++x) same = same && all.pixels[size_t(by * 8 + y) * all.width + bx * 8 + x] == all.pixels[size_t(by * 8) * all.width + bx * 8];
            EXPECT_FALSE(same) << bx << ", " << by;
        }
}

// A triangle wholly beyond the texture (u > 1) still gets its chart a group (the blocks its image
// clamped to the border reaches) and its UVs are rewritten onto the atlas.
TEST(TextureSize, ATriangleWhollyBeyondTheTextureGetsAGroup) {
    Image source{100, 60, 1, std::vector<uint8_t>(6000, 77)};
    const MeshData beyond = oneTriangle({1.2f, 0.5f, 1.4f, 0.5f, 1.2f, 0.7f});
    MeshData after = beyond;
    const Image atlas = atlasTexture(textureView(source), 1, after);
    EXPECT_GE(atlas.width, 8u);
    EXPECT_NE(after.texcoords, beyond.texcoords);
    EXPECT_EQ(atlas.pixels[0], 77);  // a stored block of the source's border
}

// Charts at opposite corners of a texture a million texels wide: each corner's group holds the
// 2 x 2 blocks its triangles reach (4 texels across, 2 texels of reach), two charts reaching one
// block are one group, all found without a grid over the 131,068² blocks between the corners
// (68 GB of it: reachedBlocks lists and sorts the blocks reached).
TEST(TextureSize, BlocksFarApartOnAHugeTextureNeedNoGridBetweenThem) {
    constexpr uint32_t side = 1u << 20, columns = side / 8;
    const float s = float(side), far = s - 32;  // the triangles start on a block's first texel
    MeshData mesh;
    mesh.positions.assign(27, 0);
    mesh.texcoords = {16 / s, 16 / s, 20 / s, 16 / s, 16 / s, 20 / s, far / s, far / s, (far + 4) / s, far / s, far / s, (far + 4) / s,
                      (far + 1) / s, (far + 1) / s, (far + 3) / s, (far + 1) / s, (far + 1) / s, (far + 3) / s};
    mesh.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    std::vector<uint32_t> groupOfChart;
    const std::vector<BlockGroup> groups = reachedBlocks(mesh, {0, 0, 0, 2, 2, 2, 1, 1, 1}, 3, side, side, groupOfChart);
    ASSERT_EQ(groups.size(), 2u);
    EXPECT_EQ(groupOfChart, (std::vector<uint32_t>{0, 1, 1}));
    const auto square = [&](uint64_t b) { return std::vector<uint64_t>{b * columns + b, b * columns + b + 1, (b + 1) * columns + b, (b + 1) * columns + b + 1}; };
    EXPECT_EQ(groups[0].blocks, square(1));
    EXPECT_EQ(groups[1].blocks, square(columns - 5));
    EXPECT_EQ(groups[1].bx0, int(columns - 5));
    EXPECT_EQ(groups[1].by1, int(columns - 4));
}

// The grid and the sorted list find the same groups: small triangles of 20 charts scattered over
// a 2048² texture, every fourth beside the one before (one group), found on a grid of the 256² blocks' box (the
// default) and on the list (gridBlocks 0: the list of ~500 candidates is the smaller).
TEST(TextureSize, GridAndListFindTheSameGroups) {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> at(0.01f, 0.99f), near(-6.0f / 2048, 6.0f / 2048);
    MeshData mesh;
    std::vector<uint32_t> chart;
    float u = 0, v = 0;
    for (uint32_t c = 0; c < 20; ++c) {
        if (c % 4 != 1) u = at(random), v = at(random);  // else beside the chart before: blocks shared
        for (int t = 0; t < 3; ++t) {  // a chart's triangles within a few texels of each other
            const float du = near(random), dv = near(random);
            for (int k = 0; k < 3; ++k) {
                mesh.positions.insert(mesh.positions.end(), {0, 0, 0});
                mesh.texcoords.insert(mesh.texcoords.end(), {u + du + (k == 1 ? 3.0f / 2048 : 0), v + dv + (k == 2 ? 3.0f / 2048 : 0)});
                mesh.indices.push_back(static_cast<uint32_t>(mesh.indices.size()));
                chart.push_back(c);
            }
        }
    }
    std::vector<uint32_t> gridGroups, listGroups;
    const std::vector<BlockGroup> grid = reachedBlocks(mesh, chart, 20, 2048, 2048, gridGroups);
    const std::vector<BlockGroup> list = reachedBlocks(mesh, chart, 20, 2048, 2048, listGroups, 0);
    ASSERT_EQ(grid.size(), list.size());
    EXPECT_LE(grid.size(), 15u);  // 5 pairs of charts share blocks
    EXPECT_GE(grid.size(), 10u);
    EXPECT_EQ(gridGroups, listGroups);
    for (size_t g = 0; g < grid.size(); ++g) {
        EXPECT_EQ(grid[g].blocks, list[g].blocks) << g;
        EXPECT_EQ(std::tie(grid[g].bx0, grid[g].by0, grid[g].bx1, grid[g].by1), std::tie(list[g].bx0, list[g].by0, list[g].bx1, list[g].by1)) << g;
    }
}

// The horizon packing keeps to its column cap unless one mask is wider.
TEST(TextureSize, PackingKeepsToTheColumnCap) {
    BlockMask one;
    one.wb = one.hb = 1, one.blocks = {1};
    finishMask(one);
    std::vector<BlockMask> masks(40, one);
    EXPECT_LE(packMasks(masks, 4).columns, 4);
    EXPECT_GT(packMasks(masks, 100).columns, 4);  // sqrt(40) and more without the cap
    BlockMask wide;
    wide.wb = 6, wide.hb = 1, wide.blocks.assign(6, 1);
    finishMask(wide);
    masks.push_back(wide);
    EXPECT_EQ(packMasks(masks, 4).columns, 6);
}

TEST(TextureSize, JpegQualityIsReadBackFromTheTables) {
    const Image image = noisyImage(64);
    for (int q : {30, 75, 85, 90, 100}) EXPECT_EQ(jpegQuality(encodeTexture(image, Codec::Jpeg, q).bytes), q);
    EXPECT_EQ(jpegQuality(encodeTexture(image, Codec::Png).bytes), 0);
    std::vector<uint8_t> cut = encodeTexture(image, Codec::Jpeg, 75).bytes;
    cut.resize(40);  // the table cut short
    EXPECT_EQ(jpegQuality(cut), 0);
    EXPECT_EQ(jpegQuality(std::vector<uint8_t>{}), 0);
}

// A JPEG source below --jpeg-quality is re-coded at its own quality, one above it at --jpeg-quality.
TEST(TextureSize, NodeTexturesNeverExceedTheSourcesQuality) {
    for (int sourceQuality : {60, 95}) {
        TempDir dir;
        ChunkedScanOptions options;
        options.jpeg = true;
        options.jpegQuality = sourceQuality;
        options.textureSize = 128;
        const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(40), options);
        const std::string db = dir.file("f.hlod");
        const RunResult build = runHlod({"build", scan.obj, "-o", db, "-j", "1"});
        ASSERT_EQ(build.exitCode, 0) << build.outAndErr();
        const Database database = Database::open(db);
        uint64_t textures = 0;
        for (const Node& n : database.skeleton().nodes)
            for (uint32_t b = 0; b < n.blobCount; ++b) {
                const BlobRef& ref = database.skeleton().blobs[n.firstBlob + b];
                if (ref.kind != BlobKind::Texture) continue;
                ++textures;
                EXPECT_EQ(jpegQuality(database.readBlob(n.firstBlob + b)), std::min(sourceQuality, 85)) << sourceQuality;
            }
        EXPECT_GT(textures, 0u);
    }
}

}  // namespace
}  // namespace hlod::test
