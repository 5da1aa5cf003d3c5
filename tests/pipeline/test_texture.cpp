// Node textures: downsampling by the factor, chart repacking with exact UVs, no unused texels.
#include "helpers.h"

namespace hlod::test {
namespace {

// Two separate charts in the corners of a 256 x 256 source whose red/green encode the texel.
MeshData twoCharts() {
    MeshData m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 0, 6, 5, 0, 5, 6, 0};
    m.texcoords = {0.05f, 0.05f, 0.20f, 0.05f, 0.05f, 0.15f, 0.80f, 0.70f, 0.95f, 0.70f, 0.80f, 0.90f};
    m.indices = {0, 1, 2, 3, 4, 5};
    return m;
}

uint8_t texel(const Image& img, float u, float v, int channel) {
    const uint32_t x = std::min(img.width - 1, static_cast<uint32_t>(u * img.width));
    const uint32_t y = std::min(img.height - 1, static_cast<uint32_t>(v * img.height));
    return img.pixels[(static_cast<size_t>(y) * img.width + x) * img.channels + channel];
}

TEST(Texture, AtlasKeepsOnlyUsedChartsAndMapsUVsExactly) {
    const Image source = testImage(256, 256);
    const MeshData before = twoCharts();
    MeshData after = before;
    const Image atlas = atlasTexture(source, after);
    EXPECT_LT(uint64_t(atlas.width) * atlas.height, uint64_t(256) * 256 / 8);  // not the whole source
    for (size_t v = 0; v < before.vertexCount(); ++v) {
        const float u0 = before.texcoords[2 * v], v0 = before.texcoords[2 * v + 1];
        const float u1 = after.texcoords[2 * v], v1 = after.texcoords[2 * v + 1];
        // The affine map per chart is exact: the same source texel lies under the old and new UV.
        EXPECT_NEAR(u1 * atlas.width - std::floor(u1 * atlas.width), u0 * 256 - std::floor(u0 * 256), 1e-3) << v;
        for (int c = 0; c < 2; ++c) EXPECT_EQ(texel(atlas, u1, v1, c), texel(source, u0, v0, c)) << "vertex " << v;
    }
}

TEST(Texture, DownsampleDividesTexelsByTheFactor) {
    const Image source = testImage(256, 128);
    const Image half = downsampleTexture(source, 4);
    EXPECT_EQ(half.width, 128u);
    EXPECT_EQ(half.height, 64u);
    EXPECT_EQ(downsampleTexture(source, 0.5).pixels, source.pixels);  // leaves keep full resolution
    EXPECT_NEAR(texel(half, 0.5f, 0.5f, 0), texel(source, 0.5f, 0.5f, 0), 2);
}

}  // namespace
}  // namespace hlod::test
