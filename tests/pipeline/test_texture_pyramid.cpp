// The texture store's mip pyramid (texture_store.cpp): each level the box-filtered halving of the
// one before, the same from the temporary file as in memory, and a node's downsampling filtered
// from the level just finer than its size.
#include "helpers.h"
#include "pipeline/texture_store.h"

#include <fstream>

namespace hlod::test {
namespace {

// Texels that change at every texel (a smooth image would hide a filter reading the wrong ones).
Image noise(uint32_t w, uint32_t h, uint32_t channels) {
    Image image{w, h, channels, std::vector<uint8_t>(size_t(w) * h * channels)};
    uint32_t state = 12345;
    for (uint8_t& t : image.pixels) state = state * 1664525u + 1013904223u, t = static_cast<uint8_t>(state >> 24);
    return image;
}

// The direct box filter of a 2^k reduction: the rounded mean of each 2^k x 2^k block.
Image blockMeans(const Image& source, uint32_t side) {
    Image out{source.width / side, source.height / side, source.channels, {}};
    out.pixels.resize(size_t(out.width) * out.height * out.channels);
    for (uint32_t y = 0; y < out.height; ++y)
        for (uint32_t x = 0; x < out.width; ++x)
            for (uint32_t c = 0; c < source.channels; ++c) {
                double sum = 0;
                for (uint32_t dy = 0; dy < side; ++dy)
                    for (uint32_t dx = 0; dx < side; ++dx)
                        sum += source.pixels[((size_t(y) * side + dy) * source.width + x * side + dx) * source.channels + c];
                out.pixels[(size_t(y) * out.width + x) * out.channels + c] = static_cast<uint8_t>(std::lround(sum / (side * side)));
            }
    return out;
}

int maxDifference(const Image& a, const Image& b) {
    int worst = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) worst = std::max(worst, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
    return worst;
}

TEST(TexturePyramid, LevelsHalveDownToOneTexelByBoxFilter) {
    const Image source = noise(64, 20, 3);
    const std::vector<Image> mips = mipLevels(source);
    const std::vector<std::pair<uint32_t, uint32_t>> sides = {{32, 10}, {16, 5}, {8, 3}, {4, 2}, {2, 1}, {1, 1}};
    ASSERT_EQ(mips.size(), sides.size());
    for (size_t k = 0; k < mips.size(); ++k) EXPECT_EQ(std::make_pair(mips[k].width, mips[k].height), sides[k]) << "level " << k + 1;
    EXPECT_EQ(mips[0].pixels, blockMeans(source, 2).pixels) << "level 1: each texel the mean of its 2 x 2 (exact)";
    // Level 2 from the rounded level 1: within one of the direct 4 x 4 mean (one more rounding).
    EXPECT_LE(maxDifference(mips[1], blockMeans(source, 4)), 1);
    // An odd side (5 rows -> 3): the area-weighted mean, a constant image stays constant.
    const Image flat{33, 5, 1, std::vector<uint8_t>(33 * 5, 200)};
    for (const Image& m : mipLevels(flat))
        for (uint8_t t : m.pixels) ASSERT_EQ(t, 200);
}

// A node's size between two levels is filtered from the finer one, never from the source: levels
// replaced by constant images show which one was read.
TEST(TexturePyramid, ScaledRegionReadsTheLevelJustFinerThanItsSize) {
    const Image source = noise(256, 128, 1);
    std::vector<Image> fake;
    for (const Image& m : mipLevels(source)) fake.push_back({m.width, m.height, 1, std::vector<uint8_t>(m.pixels.size(), uint8_t(fake.size() + 1))});
    const TextureSource view = textureView(source, fake);
    const auto levelRead = [&](uint32_t w, uint32_t h) { return scaledRegion(view, w, h, 0, 0, w, h).pixels.at(0); };
    EXPECT_EQ(levelRead(128, 64), 1) << "level 1's size: a copy of it";
    EXPECT_EQ(levelRead(100, 50), 1);
    EXPECT_EQ(levelRead(64, 40), 1) << "level 2 is 32 rows, fewer than 40";
    EXPECT_EQ(levelRead(64, 32), 2);
    EXPECT_EQ(levelRead(33, 9), 2) << "level 3 is 32 columns";
    EXPECT_EQ(levelRead(32, 9), 3);
    EXPECT_EQ(levelRead(1, 1), 8);
    EXPECT_EQ(scaledRegion(view, 200, 100, 0, 0, 200, 100).pixels, scaledRegion(textureView(source), 200, 100, 0, 0, 200, 100).pixels)
        << "larger than level 1: from the source";
}

// The store's pyramid (in the temporary file, filtered by strips of rows read back) is the one
// mipLevels computes in memory from the decoded image, and so are the node rectangles from it.
TEST(TexturePyramid, StoreFileHoldsTheSamePyramidAsMemory) {
    TempDir dir;
    // Even sides: level 1 halved from the decoded strips (the last one shorter); odd: read back.
    for (const auto& [width, height] : {std::pair<uint32_t, uint32_t>{300, 190}, {301, 97}}) {
        const std::string path = dir.file(std::to_string(width) + "_texture.png");
        const Image source = noise(width, height, 3);
        const EncodedBlob blob = encodeTexture(source, Codec::Png);
        std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(blob.bytes.data()), std::streamsize(blob.bytes.size()));
        TextureStore files(dir.file("store")), memory;
        const TextureSource a = files.open(path, nullptr), b = memory.open(path, nullptr);
        const std::vector<Image> mips = mipLevels(source);
        ASSERT_EQ(a.levels.size(), mips.size() + 1);
        ASSERT_EQ(b.levels.size(), mips.size() + 1);
        for (size_t k = 1; k < a.levels.size(); ++k) {
            const Image& m = mips[k - 1];
            ASSERT_EQ(a.levels[k].width, m.width);
            ASSERT_EQ(a.levels[k].height, m.height);
            std::vector<uint8_t> fromFile(m.pixels.size()), fromMemory(m.pixels.size());
            a.rows(0, m.height, 0, m.width, fromFile.data(), k);
            b.rows(0, m.height, 0, m.width, fromMemory.data(), k);
            EXPECT_EQ(fromFile, m.pixels) << width << " level " << k;
            EXPECT_EQ(fromMemory, m.pixels) << width << " level " << k;
        }
        for (const double factor : {2.0, 5.0, 40.0}) {
            const uint32_t w = scaledSide(width, factor), h = scaledSide(height, factor);
            const Image whole = downsampleTexture(source, factor);
            EXPECT_EQ(scaledRegion(a, w, h, 0, 0, w, h).pixels, whole.pixels) << factor;
            EXPECT_EQ(scaledRegion(b, w, h, 0, 0, w, h).pixels, whole.pixels) << factor;
        }
    }
}

// The temporary file's tiles (kTile = 64 texels a side, texture_store.cpp): any rectangle of any
// level reads back as the in-memory pyramid's, across tile borders, for sides that are not
// multiples of the tile (the last tiles narrower and shorter), a single row or column, 1 texel.
TEST(TexturePyramid, StoreTilesReadBackAnyRectangleOfEveryLevel) {
    TempDir dir;
    const std::vector<std::pair<uint32_t, uint32_t>> sides = {{1, 1}, {1, 70}, {200, 1}, {64, 64}, {65, 63}, {130, 257}, {257, 130}};
    for (const uint32_t channels : {1u, 3u})
        for (const auto& [width, height] : sides) {
            const std::string path = dir.file(std::to_string(width) + "x" + std::to_string(height) + "_" + std::to_string(channels) + ".png");
            const Image source = noise(width, height, channels);
            const EncodedBlob blob = encodeTexture(source, Codec::Png);
            std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(blob.bytes.data()), std::streamsize(blob.bytes.size()));
            TextureStore store(dir.file("store"));
            const TextureSource file = store.open(path, nullptr);
            ASSERT_EQ(file.channels, channels);
            const std::vector<Image> mips = mipLevels(source);
            std::vector<Image> levels = mips;
            levels.insert(levels.begin(), source);
            ASSERT_EQ(file.levels.size(), levels.size()) << width << " x " << height;
            const TextureSource memory = textureView(source, mips);
            for (size_t k = 0; k < levels.size(); ++k) {
                const Image& level = levels[k];
                const std::string what = std::to_string(width) + " x " + std::to_string(height) + " x " + std::to_string(channels) +
                                         ", level " + std::to_string(k);
                // Rectangles starting and ending on both sides of the tile borders 64 and 128.
                const std::vector<uint32_t> cuts = {0, 1, 63, 64, 65, 127, 128, 129, 200};
                for (const uint32_t x0 : cuts)
                    for (const uint32_t xLast : cuts)
                        for (const uint32_t y0 : cuts)
                            for (const uint32_t yLast : cuts) {
                                const uint32_t x1 = std::min(xLast + 1, level.width), y1 = std::min(yLast + 1, level.height);
                                if (x0 >= x1 || y0 >= y1) continue;
                                std::vector<uint8_t> got(size_t(x1 - x0) * (y1 - y0) * channels, 0), want;
                                for (uint32_t y = y0; y < y1; ++y)
                                    want.insert(want.end(), level.pixels.begin() + (size_t(y) * level.width + x0) * channels,
                                                level.pixels.begin() + (size_t(y) * level.width + x1) * channels);
                                file.rows(y0, y1, x0, x1, got.data(), k);
                                ASSERT_EQ(got, want) << what << ", [" << x0 << ", " << x1 << ") x [" << y0 << ", " << y1 << ")";
                            }
            }
            // A node's rectangles (a copy, a halving, the filter) from the file equal those from memory.
            for (const double factor : {1.0, 4.0, 3.0, 17.0}) {
                const uint32_t w = scaledSide(width, factor), h = scaledSide(height, factor);
                for (const auto& [x0, y0] : {std::pair<uint32_t, uint32_t>{0, 0}, {w / 3, h / 2}, {w / 2, h / 3}}) {
                    const uint32_t x1 = std::max(x0 + 1, w - w / 5), y1 = std::max(y0 + 1, h - h / 7);
                    ASSERT_EQ(scaledRegion(file, w, h, x0, y0, x1, y1).pixels, scaledRegion(memory, w, h, x0, y0, x1, y1).pixels)
                        << width << " x " << height << " x " << channels << ", factor " << factor << ", from " << x0 << ", " << y0;
                }
            }
        }
}

// Every channel count the filter is specialised for filters each channel as a grey image alone.
TEST(TexturePyramid, EachChannelFilteredAlone) {
    for (const uint32_t channels : {2u, 3u, 4u}) {
        const Image image = noise(90, 70, channels);
        for (const double factor : {2.9, 11.0}) {
            const Image all = downsampleTexture(image, factor);
            for (uint32_t c = 0; c < channels; ++c) {
                Image grey{90, 70, 1, {}};
                for (size_t i = c; i < image.pixels.size(); i += channels) grey.pixels.push_back(image.pixels[i]);
                const Image one = downsampleTexture(grey, factor);
                ASSERT_EQ(one.pixels.size() * channels, all.pixels.size());
                for (size_t i = 0; i < one.pixels.size(); ++i)
                    ASSERT_EQ(all.pixels[i * channels + c], one.pixels[i]) << channels << " channels, factor " << factor << ", channel " << c;
            }
        }
    }
}

}  // namespace
}  // namespace hlod::test
