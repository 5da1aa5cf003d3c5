// Node textures: downsampling by the factor, chart repacking with exact UVs, no unused texels.
#include "helpers.h"
#include "pipeline/texture_charts.h"

#include <array>
#include <fstream>

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
    const Image atlas = atlasTexture(textureView(source), 1, after);
    EXPECT_LT(uint64_t(atlas.width) * atlas.height, uint64_t(256) * 256 / 8);  // not the whole source
    for (size_t v = 0; v < before.vertexCount(); ++v) {
        const float u0 = before.texcoords[2 * v], v0 = before.texcoords[2 * v + 1];
        const float u1 = after.texcoords[2 * v], v1 = after.texcoords[2 * v + 1];
        // The translation per group is exact: the same source texel lies under the old and new UV.
        EXPECT_NEAR(u1 * atlas.width - std::floor(u1 * atlas.width), u0 * 256 - std::floor(u0 * 256), 1e-3) << v;
        for (int c = 0; c < 2; ++c) EXPECT_EQ(texel(atlas, u1, v1, c), texel(source, u0, v0, c)) << "vertex " << v;
    }
}

// A black chart and a white chart, small enough to share a JPEG block if packed side by side:
// after JPEG coding each must keep its own colour everywhere under its triangles.
TEST(Texture, JpegCodingDoesNotBleedBetweenCharts) {
    Image source{64, 64, 3, {}};
    for (uint32_t y = 0; y < 64; ++y)
        for (uint32_t x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) source.pixels.push_back(x < 32 ? 0 : 255);
    MeshData mesh = twoCharts();
    mesh.texcoords = {0.05f, 0.05f, 0.09f, 0.05f, 0.05f, 0.09f, 0.80f, 0.80f, 0.84f, 0.80f, 0.80f, 0.84f};
    const Image atlas = atlasTexture(textureView(source), 1, mesh);
    EXPECT_EQ(atlas.width % 8, 0u);
    EXPECT_EQ(atlas.height % 8, 0u);
    const Image decoded = decodeTexture(encodeTexture(atlas, Codec::Jpeg, 85).bytes, Codec::Jpeg, "atlas");
    for (int chart = 0; chart < 2; ++chart) {
        float lo[2] = {1, 1}, hi[2] = {0, 0};
        for (int v = 3 * chart; v < 3 * chart + 3; ++v)
            for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], mesh.texcoords[2 * v + a]), hi[a] = std::max(hi[a], mesh.texcoords[2 * v + a]);
        const int expected = chart == 0 ? 0 : 255;
        for (uint32_t y = uint32_t(lo[1] * decoded.height); y < uint32_t(std::ceil(hi[1] * decoded.height)); ++y)
            for (uint32_t x = uint32_t(lo[0] * decoded.width); x < uint32_t(std::ceil(hi[0] * decoded.width)); ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(decoded.pixels[(size_t(y) * decoded.width + x) * 3 + c], expected, 6) << "chart " << chart << " texel " << x << "," << y;
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

// The box filter: a texel of a 2 x 2 reduction is the mean of the four it covers; of a
// non-integer one, the area-weighted mean (constant image stays constant).
TEST(Texture, BoxFilterAveragesTheCoveredTexels) {
    Image source{4, 2, 1, {0, 100, 10, 30, 200, 40, 20, 50}};
    const Image half = downsampleTexture(source, 4);
    ASSERT_EQ(half.width, 2u);
    ASSERT_EQ(half.height, 1u);
    EXPECT_EQ(half.pixels[0], 85);  // (0 + 100 + 200 + 40) / 4
    EXPECT_EQ(half.pixels[1], 28);  // (10 + 30 + 20 + 50) / 4 = 27.5, rounded
    Image flat{97, 61, 3, std::vector<uint8_t>(97 * 61 * 3, 77)};
    for (const uint8_t t : downsampleTexture(flat, 2.7).pixels) ASSERT_EQ(t, 77);
}

// A rectangle of the downsampled texture (what a node reads, texture_store.cpp) has the texels
// of the whole downsampled image, whatever the rectangle: no seams between charts read apart.
TEST(Texture, ScaledRegionEqualsTheWholeDownsampledImage) {
    const Image source = testImage(256, 128);
    const std::vector<Image> mips = mipLevels(source);
    for (const double factor : {1.0, 2.0, 3.3, 4.0, 9.0, 21.0}) {
        const Image whole = downsampleTexture(source, factor);
        const uint32_t w = scaledSide(256, factor), h = scaledSide(128, factor);
        for (const auto& [x0, y0, x1, y1] : {std::array<uint32_t, 4>{0, 0, w, h}, {3, 5, w / 2, h / 3 + 6}, {w - 7, h - 1, w, h}}) {
            const Image part = scaledRegion(textureView(source, mips), w, h, x0, y0, x1, y1);
            ASSERT_EQ(part.width, x1 - x0);
            for (uint32_t y = y0; y < y1; ++y)
                for (uint32_t x = x0; x < x1; ++x)
                    for (uint32_t c = 0; c < 3; ++c)
                        ASSERT_EQ(part.pixels[((y - y0) * part.width + (x - x0)) * 3 + c], whole.pixels[(y * w + x) * 3 + c])
                            << "factor " << factor << " texel " << x << "," << y;
        }
    }
}

// What a baked node samples: its original triangles by chart, each with only the texels under it
// (two charts in opposite corners: two small rectangles, not the atlas between them), the same
// texels under the rewritten UVs as under the source's.
TEST(Texture, ChartsForBakingHoldOnlyTheirOwnTexels) {
    const Image source = testImage(256, 256);
    const std::vector<Material> materials = {{"m", "", std::make_shared<Image>(source)}};
    std::vector<TextureProblem> problems;
    BlockTextures textures(materials, nullptr, false, problems, nullptr);
    const MeshData mesh = twoCharts();
    const std::vector<TexturedChart> charts = textureCharts(textures, 0, 1, mesh);
    ASSERT_EQ(charts.size(), 2u);
    uint64_t texels = 0;
    for (const TexturedChart& c : charts) {
        texels += uint64_t(c.texels.width) * c.texels.height;
        ASSERT_EQ(c.mesh.triangleCount(), 1u);
        for (size_t v = 0; v < 3; ++v) {
            const float* uv = &c.mesh.texcoords[2 * v];
            const float* original = nullptr;  // the source vertex at the same position
            for (size_t w = 0; w < mesh.vertexCount(); ++w)
                if (mesh.positions[3 * w] == c.mesh.positions[3 * v] && mesh.positions[3 * w + 1] == c.mesh.positions[3 * v + 1])
                    original = &mesh.texcoords[2 * w];
            ASSERT_NE(original, nullptr);
            for (int ch = 0; ch < 2; ++ch) EXPECT_EQ(texel(c.texels, uv[0], uv[1], ch), texel(source, original[0], original[1], ch));
        }
    }
    EXPECT_LT(texels, uint64_t(256) * 256 / 8);
    EXPECT_TRUE(textureCharts(textures, 1, 1, mesh).empty()) << "no such material: untextured";
}

// A texture file goes through the store once (decoded by strips into a temporary file) and reads
// back as loadTexture decodes it; a truncated one is an InputError for every block asking.
TEST(Texture, StoreDecodesAFileOnceAndReadsItBackByRectangles) {
    TempDir dir;
    const Image source = testImage(300, 200);
    for (const Codec codec : {Codec::Png, Codec::Jpeg}) {
        const std::string path = dir.file(codec == Codec::Png ? "t.png" : "t.jpg");
        const EncodedBlob blob = encodeTexture(source, codec);
        std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(blob.bytes.data()), std::streamsize(blob.bytes.size()));
        const Image decoded = loadTexture(path);
        TextureStore store(dir.file("store"));
        const TextureSource a = store.open(path, nullptr), b = store.open(path, nullptr);
        EXPECT_EQ(a.file, b.file) << "decoded once";
        ASSERT_EQ(a.width, 300u);
        ASSERT_EQ(a.height, 200u);
        std::vector<uint8_t> rows(size_t(300) * 200 * 3);
        a.rows(0, 200, 0, 300, rows.data());
        EXPECT_EQ(rows, decoded.pixels);
        std::vector<uint8_t> cut(size_t(20) * 3 * 3);
        a.rows(150, 153, 40, 60, cut.data());
        EXPECT_EQ(cut[0], decoded.pixels[(150 * 300 + 40) * 3]);
        EXPECT_EQ(cut.back(), decoded.pixels[(152 * 300 + 59) * 3 + 2]);
        const std::string truncated = dir.file("cut_" + std::filesystem::path(path).filename().string());
        std::ofstream(truncated, std::ios::binary).write(reinterpret_cast<const char*>(blob.bytes.data()), std::streamsize(blob.bytes.size() / 2));
        EXPECT_THROW(store.open(truncated, nullptr), InputError);
        EXPECT_THROW(store.open(truncated, nullptr), InputError);
    }
}

}  // namespace
}  // namespace hlod::test
