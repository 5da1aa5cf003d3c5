// Huffman tables fitted to one image from a sample of its blocks (formats/jpeg_tables.cpp), so
// that libjpeg encodes it in one pass instead of two (formats/image_jpeg.cpp).
#pragma once

#include "formats/codec.h"

#include <array>
#include <cstdint>
#include <vector>

namespace hlod {

// Natural (row-major) index of the k-th coefficient in zig-zag order (ITU T.81 Figure A.6).
inline constexpr std::array<int, 64> kJpegZigZag = {
    0,  1,  8,  16, 9,  2,  3,  10, 17, 24, 32, 25, 18, 11, 4,  5,  12, 19, 26, 33, 40, 48,
    41, 34, 27, 20, 13, 6,  7,  14, 21, 28, 35, 42, 49, 56, 57, 50, 43, 36, 29, 22, 15, 23,
    30, 37, 44, 51, 58, 59, 52, 45, 38, 31, 39, 46, 53, 60, 61, 54, 47, 55, 62, 63};

// One JPEG Huffman table as a DHT segment holds it (ITU T.81 §B.2.4.2): bits[k] codes of
// length k (k = 1..16, bits[0] unused), then the symbols in order of increasing length.
struct HuffmanTable {
    std::array<uint8_t, 17> bits{};
    std::vector<uint8_t> values;
};

// Luminance (0) and chrominance (1) tables, DC and AC, as libjpeg's defaults number them.
struct JpegHuffmanTables {
    HuffmanTable dc[2], ac[2];
};

// An image of at most this many MCUs takes libjpeg's exact two-pass optimisation
// (formats/image_jpeg.cpp); a larger one, tables from a sample of its MCUs.
inline constexpr uint64_t kSampledMcus = 4096;

// Code lengths for `frequency` (256 symbols; a zero frequency gets no code), limited to 16 bits
// and leaving the all-ones code unused (ITU T.81 Annex K.2).
HuffmanTable optimalHuffmanTable(const std::array<uint64_t, 256>& frequency);

// MCUs of an image (1 or 3 channels; 16 x 16 at 4:2:0, else 8 x 8).
uint64_t jpegMcuCount(const Image& image, bool chroma420);

// Tables for `image` (1 or 3 channels) quantised by `luma` / `chroma` (64 quantisers in natural
// order): symbol counts from 256 pairs of neighbouring MCUs (the same MCUs more than once in an
// image of fewer than 512), every symbol the encoder can emit given a count of at least one, so
// every block has a code whether sampled or not.
JpegHuffmanTables sampledHuffmanTables(const Image& image, const uint16_t* luma, const uint16_t* chroma, bool chroma420);

}  // namespace hlod
