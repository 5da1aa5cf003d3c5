// Huffman tables fitted to an image from a sample of its blocks: optimal prefix codes (Huffman
// 1952) limited to 16 bits as JPEG requires (ITU T.81 Annex K.2, the procedure libjpeg's
// jpeg_gen_optimal_table follows), from the symbol counts of 256 pairs of neighbouring MCUs spread over the image.
//
// Why: libjpeg's own optimisation (optimize_coding) runs two passes and keeps every quantised
// DCT block of the image between them (6 B per texel at 4:4:4); its statistics pass is C code.
// With tables given up front, libjpeg codes in one pass through its SIMD Huffman coder. The
// coefficients (and so the decoded texels) are the same either way; only the codes' lengths
// differ. The sample's counts come from a float DCT of our own (the quantised values of libjpeg's
// integer DCT within ±1 near rounding boundaries), and every symbol the encoder can emit counts
// at least once,
// so a block the sample missed still has a code, only a longer one. pipeline/TEXTURE_SPEED.md
// (round 4) measures the bytes against libjpeg's exact optimisation.
#include "formats/jpeg_tables.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

namespace hlod {

namespace {

using Counts = std::array<uint64_t, 256>;

// Pairs of neighbouring MCUs sampled in an image larger than kSampledMcus: 512 MCUs (at most an
// eighth of its MCUs), ~1,500 blocks, tens of thousands of symbols. The pairs' first MCUs follow
// Weyl's sequence frac(i x golden ratio) over the raster order: spread over rows and columns
// whatever the width, the same MCUs on every machine.
constexpr uint64_t kSamplePairs = 256;
constexpr double kGoldenFraction = 0.6180339887498949;

// Size category of a coefficient or DC difference (T.81 Tables F.1 and F.2): its bit count.
int category(int v) {
    unsigned magnitude = static_cast<unsigned>(v < 0 ? -v : v);
    int bits = 0;
    for (; magnitude != 0; magnitude >>= 1) ++bits;
    return bits;
}

// One 8-point pass of the scaled DCT of Arai, Agui & Nakajima (1988), as libjpeg's jfdctflt.c
// (Pennebaker & Mitchell, Figure 4-8): output k is the DCT-II's coefficient times
// kAanScale[k] x 2√2.
void aanPass(float* d, int step) {
    const float t0 = d[0] + d[7 * step], t7 = d[0] - d[7 * step], t1 = d[step] + d[6 * step], t6 = d[step] - d[6 * step];
    const float t2 = d[2 * step] + d[5 * step], t5 = d[2 * step] - d[5 * step], t3 = d[3 * step] + d[4 * step];
    const float t4 = d[3 * step] - d[4 * step];
    const float e10 = t0 + t3, e13 = t0 - t3, e11 = t1 + t2, e12 = t1 - t2;  // even part
    d[0] = e10 + e11;
    d[4 * step] = e10 - e11;
    const float z1 = (e12 + e13) * 0.707106781f;
    d[2 * step] = e13 + z1;
    d[6 * step] = e13 - z1;
    const float o10 = t4 + t5, o11 = t5 + t6, o12 = t6 + t7;  // odd part
    const float z5 = (o10 - o12) * 0.382683433f, z2 = 0.541196100f * o10 + z5, z4 = 1.306562965f * o12 + z5;
    const float z3 = o11 * 0.707106781f, z11 = t7 + z3, z13 = t7 - z3;
    d[5 * step] = z13 + z2;
    d[3 * step] = z13 - z2;
    d[step] = z11 + z4;
    d[7 * step] = z11 - z4;
}

// Multipliers that quantise the AAN output (libjpeg's jcdctmgr.c, JDCT_FLOAT): 1 / (quantiser x
// scale(row) x scale(column) x 8), scale(0) = 1, scale(k) = √2 cos(kπ/16).
struct Quantisers {
    float multiplier[64];
    explicit Quantisers(const uint16_t* quantisers) {
        double scale[8];
        for (int k = 0; k < 8; ++k) scale[k] = k == 0 ? 1.0 : std::sqrt(2.0) * std::cos(k * std::numbers::pi / 16);
        for (int i = 0; i < 64; ++i) multiplier[i] = static_cast<float>(1.0 / (quantisers[i] * scale[i / 8] * scale[i % 8] * 8));
    }
    int operator()(float coefficient, int i) const {  // half away from zero, as libjpeg
        const float v = coefficient * multiplier[i];
        return static_cast<int>(v + (v < 0 ? -0.5f : 0.5f));
    }
};

// The symbols of one block (T.81 §F.1.2): the DC difference's category against `predictor`
// unless none, then run/size, ZRL for 16 zeros and EOB. Returns the block's quantised DC.
int countBlock(float (&samples)[64], const Quantisers& quantise, const int* predictor, Counts& dc, Counts& ac) {
    for (int row = 0; row < 8; ++row) aanPass(samples + 8 * row, 1);
    for (int column = 0; column < 8; ++column) aanPass(samples + column, 8);
    const int dcValue = quantise(samples[0], 0);
    if (predictor) ++dc[std::min(category(dcValue - *predictor), 11)];
    int run = 0;
    for (int k = 1; k < 64; ++k) {
        const int natural = kJpegZigZag[k];
        const int v = quantise(samples[natural], natural);
        if (v == 0) {
            ++run;
            continue;
        }
        for (; run > 15; run -= 16) ++ac[0xF0];
        ++ac[(run << 4) | std::min(category(v), 10)];
        run = 0;
    }
    if (run > 0) ++ac[0x00];
    return dcValue;
}

// Every symbol an 8-bit baseline encoder can emit: DC categories 0..11; AC EOB, ZRL and
// run/size with size 1..10.
void countEverySymbolOnce(Counts& dc, Counts& ac) {
    for (int s = 0; s <= 11; ++s) ++dc[s];
    ++ac[0x00];
    ++ac[0xF0];
    for (int run = 0; run < 16; ++run)
        for (int size = 1; size <= 10; ++size) ++ac[(run << 4) | size];
}

// YCbCr of T.81's JFIF convention (as libjpeg's jccolor.c), level-shifted by 128.
void toYcc(const uint8_t* p, uint32_t channels, float (&ycc)[3]) {
    if (channels != 3) {
        ycc[0] = float(p[0]) - 128;
        return;
    }
    const float r = p[0], g = p[1], b = p[2];
    ycc[0] = 0.299f * r + 0.587f * g + 0.114f * b - 128;
    ycc[1] = -0.168736f * r - 0.331264f * g + 0.5f * b;
    ycc[2] = 0.5f * r - 0.418688f * g - 0.081312f * b;
}

// The blocks of one MCU in coding order (T.81 §A.2.3): factor² luma blocks, then Cb and Cr, each
// chroma sample the mean of factor x factor texels; the image's edges replicated (libjpeg pads
// the texels so; at 4:2:0 it codes a luma block wholly beyond the edge as a dummy block, which
// only the counts see differently).
struct Mcu {
    uint32_t luma = 1, blocks = 1;
    float block[6][64];

    Mcu(const Image& image, uint32_t factor, uint32_t mcuColumns, uint64_t index) {
        const uint32_t channels = image.channels == 3 ? 3 : 1, side = 8 * factor;
        const uint32_t x0 = uint32_t(index % mcuColumns) * side, y0 = uint32_t(index / mcuColumns) * side;
        luma = factor * factor;
        blocks = luma + channels - 1;
        float ycc[3][16][16];
        for (uint32_t y = 0; y < side; ++y)
            for (uint32_t x = 0; x < side; ++x) {
                const size_t px = std::min(x0 + x, image.width - 1), py = std::min(y0 + y, image.height - 1);
                float pixel[3];
                toYcc(image.pixels.data() + (py * image.width + px) * image.channels, channels, pixel);
                for (uint32_t c = 0; c < channels; ++c) ycc[c][y][x] = pixel[c];
            }
        for (uint32_t b = 0; b < luma; ++b)
            for (int i = 0; i < 64; ++i) block[b][i] = ycc[0][(b / factor) * 8 + i / 8][(b % factor) * 8 + i % 8];
        for (uint32_t c = 1; c < channels; ++c)
            for (int i = 0; i < 64; ++i) {
                float sum = 0;
                for (uint32_t dy = 0; dy < factor; ++dy)
                    for (uint32_t dx = 0; dx < factor; ++dx) sum += ycc[c][(i / 8) * factor + dy][(i % 8) * factor + dx];
                block[luma + c - 1][i] = sum / float(factor * factor);
            }
    }
};

}  // namespace

HuffmanTable optimalHuffmanTable(const Counts& frequency) {
    constexpr int kSymbols = 257;  // 256 is a reserved symbol of count 1: no real code is all ones
    std::array<int, kSymbols> codeSize{}, others{};
    others.fill(-1);
    // K.2 Figure K.1: merge the two least frequent, lengthening both chains; the least count first,
    // ties to the larger symbol (Figure K.2, as libjpeg), the merged node named by the first
    std::set<std::pair<uint64_t, int>> queue;  // (count, -symbol)
    for (int i = 0; i < 256; ++i)
        if (frequency[i] != 0) queue.emplace(frequency[i], -i);
    queue.emplace(1, -256);
    while (queue.size() > 1) {
        const auto [count1, negative1] = *queue.begin();
        queue.erase(queue.begin());
        const auto [count2, negative2] = *queue.begin();
        queue.erase(queue.begin());
        queue.emplace(count1 + count2, negative1);
        int c1 = -negative1, c2 = -negative2;
        for (++codeSize[c1]; others[c1] >= 0; ++codeSize[c1]) c1 = others[c1];
        others[c1] = c2;
        for (++codeSize[c2]; others[c2] >= 0; ++codeSize[c2]) c2 = others[c2];
    }
    std::array<int, kSymbols + 1> bits{};  // a length can reach 256 only for counts beyond 2^64
    for (int i = 0; i < kSymbols; ++i)
        if (codeSize[i] > 0) ++bits[codeSize[i]];
    for (int i = kSymbols; i > 16; --i)  // K.2 Figure K.3: lengths above 16 move up the tree
        while (bits[i] > 0) {
            int j = i - 2;
            while (bits[j] == 0) --j;
            bits[i] -= 2;
            ++bits[i - 1];
            bits[j + 1] += 2;
            --bits[j];
        }
    int longest = 16;
    while (longest > 0 && bits[longest] == 0) --longest;
    if (longest > 0) --bits[longest];  // the reserved symbol's code, one of the longest
    HuffmanTable table;
    for (int k = 1; k <= 16; ++k) table.bits[k] = static_cast<uint8_t>(bits[k]);
    for (int size = 1; size <= kSymbols; ++size)  // K.2 Figure K.4: symbols by length, then value
        for (int s = 0; s < 256; ++s)
            if (codeSize[s] == size) table.values.push_back(static_cast<uint8_t>(s));
    return table;
}

uint64_t jpegMcuCount(const Image& image, bool chroma420) {
    const uint32_t side = image.channels == 3 && chroma420 ? 16 : 8;
    return uint64_t((image.width + side - 1) / side) * ((image.height + side - 1) / side);
}

JpegHuffmanTables sampledHuffmanTables(const Image& image, const uint16_t* luma, const uint16_t* chroma, bool chroma420) {
    Counts dc[2]{}, ac[2]{};
    const Quantisers quantisers[2] = {Quantisers(luma), Quantisers(chroma)};
    const uint32_t factor = image.channels == 3 && chroma420 ? 2 : 1;  // luma blocks per MCU side
    const uint32_t mcuColumns = (image.width + 8 * factor - 1) / (8 * factor);
    const uint64_t mcus = jpegMcuCount(image, chroma420);
    for (uint64_t i = 0; i < kSamplePairs; ++i) {
        const uint64_t first = uint64_t(std::fmod(0.5 + double(i) * kGoldenFraction, 1.0) * double(mcus - 1));  // < mcus - 1, or 0
        int previous[3] = {};  // each component's last DC; none before the first MCU of a run
        for (uint64_t index = first; index < std::min(mcus, first + 2); ++index) {  // one MCU when mcus = 1
            Mcu mcu(image, factor, mcuColumns, index);
            for (uint32_t b = 0; b < mcu.blocks; ++b) {
                const uint32_t component = b < mcu.luma ? 0 : b - mcu.luma + 1, table = component == 0 ? 0 : 1;
                // the DC predictor (T.81 §F.1.1.5.1): the component's block coded just before
                const bool predicted = index > first || (component == 0 && b > 0);
                previous[component] = countBlock(mcu.block[b], quantisers[table], predicted ? &previous[component] : nullptr, dc[table], ac[table]);
            }
        }
    }
    JpegHuffmanTables tables;
    for (int t = 0; t < 2; ++t) {
        countEverySymbolOnce(dc[t], ac[t]);
        tables.dc[t] = optimalHuffmanTable(dc[t]);
        tables.ac[t] = optimalHuffmanTable(ac[t]);
    }
    return tables;
}

}  // namespace hlod
