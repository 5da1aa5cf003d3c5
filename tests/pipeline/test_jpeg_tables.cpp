// Huffman tables fitted to an image (formats/jpeg_tables.h, issue #14): a valid JPEG prefix code
// for any counts, and a block the sample missed still coded (the decoded texels are those of
// libjpeg's standard tables). Their bytes against libjpeg's exact optimisation:
// ImageIo.FittedTablesKeepTheCoefficients.
#include "formats/codec.h"
#include "formats/image_io.h"
#include "formats/jpeg_tables.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace hlod::test {
namespace {

// Each coded symbol's code length, from the DHT form (bits per length, then symbols in order).
std::map<int, int> codeLengths(const HuffmanTable& table) {
    std::map<int, int> lengths;
    size_t next = 0;
    for (int length = 1; length <= 16; ++length)
        for (int i = 0; i < table.bits[length]; ++i) {
            EXPECT_LT(next, table.values.size());
            if (next < table.values.size()) {
                EXPECT_TRUE(lengths.emplace(table.values[next++], length).second) << "symbol twice";
            }
        }
    EXPECT_EQ(next, table.values.size());
    return lengths;
}

// A prefix code of 1..16 bits for exactly the counted symbols, the all-ones code unused. Below
// 16 bits (no length limited by Annex K.3) a more frequent symbol never has a longer code.
void expectValidCode(const std::array<uint64_t, 256>& frequency) {
    const std::map<int, int> lengths = codeLengths(optimalHuffmanTable(frequency));
    int longest = 0;
    for (const auto& [symbol, length] : lengths) longest = std::max(longest, length);
    double kraft = 0;
    for (int s = 0; s < 256; ++s) {
        const auto found = lengths.find(s);
        ASSERT_EQ(found != lengths.end(), frequency[s] != 0) << "symbol " << s;
        if (found == lengths.end()) continue;
        EXPECT_GE(found->second, 1);
        EXPECT_LE(found->second, 16);
        kraft += std::ldexp(1.0, -found->second);
        for (const auto& [other, length] : lengths) {
            if (frequency[other] > frequency[s] && longest < 16) {
                EXPECT_LE(length, found->second) << other << " vs " << s;
            }
        }
    }
    EXPECT_LT(kraft, 1.0);  // the all-ones code stays unused (T.81 Annex C)
}

TEST(JpegTables, OptimalCodesArePrefixCodesOfAtMostSixteenBits) {
    std::array<uint64_t, 256> fibonacci{}, uniform{}, one{}, scattered{};
    fibonacci[0] = fibonacci[1] = 1;  // unlimited Huffman lengths would reach 30 bits
    for (int i = 2; i < 32; ++i) fibonacci[i] = fibonacci[i - 1] + fibonacci[i - 2];
    uniform.fill(5);
    one[0x37] = 1000;
    uint64_t state = 12345;
    for (uint64_t& f : scattered) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        f = (state >> 60) < 4 ? 0 : (state >> 33) % 100000;
    }
    for (const auto* frequency : {&fibonacci, &uniform, &one, &scattered}) expectValidCode(*frequency);

    std::array<uint64_t, 256> dyadic{};  // with the reserved count-1 symbol: 8, 4, 2, 1, 1
    dyadic[10] = 8, dyadic[20] = 4, dyadic[30] = 2, dyadic[40] = 1;
    const std::map<int, int> lengths = codeLengths(optimalHuffmanTable(dyadic));
    EXPECT_EQ(lengths, (std::map<int, int>{{10, 1}, {20, 2}, {30, 3}, {40, 4}}));
}

// A large flat image with two 16 x 16 patches of noise that the sample (512 of its 16,384 or
// 65,536 MCUs) misses (checked when written: no sampled pair touches their MCUs), so the counts
// hold only flat blocks' symbols; yet every symbol of the patches has a code (taking out the
// count of one for every symbol makes this fail), and the file decodes to the standard tables'
// texels.
TEST(JpegTables, ABlockOutsideTheSampleStillHasACode) {
    for (const uint32_t channels : {1u, 3u})
        for (const bool chroma420 : {false, true}) {
            SCOPED_TRACE(std::to_string(channels) + (chroma420 ? " 4:2:0" : " 4:4:4"));
            const uint32_t side = 2048;
            Image image{side, side, channels, std::vector<uint8_t>(size_t(side) * side * channels, 128)};
            uint64_t state = 99;
            for (const auto& [x0, y0] : {std::pair{1000u, 1000u}, std::pair{16u, 2000u}})
                for (uint32_t y = y0; y < y0 + 16; ++y)
                    for (size_t i = (size_t(y) * side + x0) * channels; i < (size_t(y) * side + x0 + 16) * channels; ++i) {
                        state = state * 6364136223846793005ull + 1442695040888963407ull;
                        image.pixels[i] = uint8_t(state >> 56);
                    }
            ASSERT_GT(jpegMcuCount(image, chroma420), kSampledMcus);  // the sampled path
            const std::vector<uint8_t> fitted = encodeJpeg(image, 95, chroma420, true, false);
            const std::vector<uint8_t> standard = encodeJpeg(image, 95, chroma420, false, false);
            EXPECT_TRUE(decodeTexture(fitted, Codec::Jpeg, "f").pixels == decodeTexture(standard, Codec::Jpeg, "s").pixels);
        }
}

// The sampled tables of images down to one MCU (sampled pairs overlapping, one MCU alone): a code
// for every symbol a baseline encoder can emit, in every table.
TEST(JpegTables, TinyImagesGetACodeForEverySymbol) {
    std::array<uint16_t, 64> quantisers;
    quantisers.fill(16);
    for (const auto& [w, h] : {std::pair{1u, 1u}, std::pair{8u, 8u}, std::pair{17u, 9u}, std::pair{300u, 2u}})
        for (const uint32_t channels : {1u, 3u})
            for (const bool chroma420 : {false, true}) {
                SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(channels) + (chroma420 ? " 4:2:0" : ""));
                Image image{w, h, channels, std::vector<uint8_t>(size_t(w) * h * channels)};
                for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = uint8_t(i * 37);
                const JpegHuffmanTables tables = sampledHuffmanTables(image, quantisers.data(), quantisers.data(), chroma420);
                for (int t = 0; t < 2; ++t) {
                    EXPECT_EQ(codeLengths(tables.dc[t]).size(), 12u);
                    EXPECT_EQ(codeLengths(tables.ac[t]).size(), 162u);
                }
            }
}

}  // namespace
}  // namespace hlod::test
