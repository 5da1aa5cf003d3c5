// Baking on a real scan: the banana (15,728 triangles, one 4096^2 atlas) welded by position, so
// that its UV seams do not stop simplification, simplified 20x and baked into 4096^2 / 20 texels
// (the count texture.cpp's downsampling gives). Prints the PSNR (benchmark figure for
// pipeline/BAKE.md) and asserts a loose bound. Labelled slow with the other scans.
#include "helpers.h"

#include <cstdio>
#include <map>

namespace hlod::test {
namespace {

TEST(BakeScan, BananaSimplified20xBakesFaithfully) {
    const std::string input = sharedDir() + "/datasets/A2_ycb_011_banana_textured_scan/textured_simple_reoriented.obj";
    if (!std::filesystem::exists(input)) GTEST_SKIP() << "no " << input;
    const SourceMesh scan = readObj(input);
    ASSERT_FALSE(scan.materials.empty());
    const Image atlas = loadTexture(scan.materials[0].texturePath);
    MeshData welded;
    std::map<std::array<float, 3>, uint32_t> ids;
    const MeshData& m = scan.piece.mesh;
    for (uint32_t v : m.indices) {
        const std::array<float, 3> p = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
        auto [it, added] = ids.emplace(p, static_cast<uint32_t>(ids.size()));
        if (added) welded.positions.insert(welded.positions.end(), p.begin(), p.end());
        welded.indices.push_back(it->second);
    }
    const MeshData coarse = simplifyMesh(welded, 20, Simplifier::Meshopt);
    ASSERT_LE(coarse.triangleCount(), m.triangleCount() / 10);
    const uint64_t budget = uint64_t(atlas.width) * atlas.height / 20;
    const BakedTexture baked = bakeTexture(coarse, {{&m, &atlas}}, budget);
    EXPECT_LE(uint64_t(baked.image.width) * baked.image.height, budget);
    EXPECT_GE(baked.coveredTexels, budget / 4);
    for (float c : baked.mesh.texcoords) {
        EXPECT_GE(c, 0.0f);
        EXPECT_LE(c, 1.0f);
    }
    std::printf("banana 20x: %zu triangles, atlas %ux%u, %llu covered texels, PSNR %.2f dB\n", coarse.triangleCount(),
                baked.image.width, baked.image.height, static_cast<unsigned long long>(baked.coveredTexels), baked.psnr);
    EXPECT_GE(baked.psnr, 40.0);  // measured 51.2 dB
}

}  // namespace
}  // namespace hlod::test
