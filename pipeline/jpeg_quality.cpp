// The quality a JPEG source was written with (issue #14, pipeline/TEXTURE_SIZE.md): its luminance
// quantisation table (the DQT segment, ITU-T T.81 §B.2.4.1, stored in zig-zag order, Figure A.6)
// against the standard luminance table of T.81 Annex K (Table K.1) scaled as libjpeg (jcparam.c,
// jpeg_quality_scaling) scales it for quality q: 5000 / q below 50, 200 - 2q from 50, each entry
// (entry x scale + 50) / 100 clamped to 1..255. Only an exact match counts: a table of another
// encoder reads 0 (unknown), never a guess. Its chroma: 4:2:0 when its frame header (SOF0-2,
// T.81 §B.2.2) samples Y 2 x 2 and Cb, Cr 1 x 1.
#include "pipeline/texture_store.h"

#include "formats/jpeg_tables.h"

#include <algorithm>
#include <array>
#include <fstream>

namespace hlod {

namespace {

// Bytes read from the start of a file: the tables precede the scan, after the APPn segments (EXIF,
// ICC: at most 64 KiB each).
constexpr size_t kHeadBytes = 1 << 20;

constexpr std::array<int, 64> kLuminance = {16, 11, 10, 16, 24,  40,  51,  61,  12, 12, 14, 19, 26,  58,  60,  55,
                                            14, 13, 16, 24, 40,  57,  69,  56,  14, 17, 22, 29, 51,  87,  80,  62,
                                            18, 22, 37, 56, 68,  109, 103, 77,  24, 35, 55, 64, 81,  104, 113, 92,
                                            49, 64, 78, 87, 103, 121, 120, 101, 72, 92, 95, 98, 112, 100, 103, 99};
int qualityOf(const std::array<int, 64>& zigzagTable) {
    for (int q = 1; q <= 100; ++q) {
        const int scale = q < 50 ? 5000 / q : 200 - 2 * q;
        bool same = true;
        for (int k = 0; k < 64 && same; ++k)
            same = zigzagTable[k] == std::clamp((kLuminance[kJpegZigZag[k]] * scale + 50) / 100, 1, 255);
        if (same) return q;
    }
    return 0;
}

// visit(marker, payload) for each marker segment before the first scan (T.81 §B.1.1.4), until it
// returns true or a segment is malformed or cut short.
template <class Visit>
void headerSegments(std::span<const uint8_t> bytes, Visit visit) {
    size_t at = 0;
    const auto byte = [&] { return at < bytes.size() ? int(bytes[at++]) : -1; };
    if (byte() != 0xFF || byte() != 0xD8) return;  // SOI
    while (at < bytes.size()) {
        if (byte() != 0xFF) return;
        int marker = byte();
        while (marker == 0xFF) marker = byte();  // fill bytes
        if (marker == 0xDA || marker == 0xD9 || marker < 0) return;  // the scan, or the end
        const int high = byte(), low = byte();  // two calls, in this order (operands of | are unsequenced)
        const int length = high < 0 || low < 0 ? -1 : (high << 8) | low;
        if (length < 2 || at + size_t(length) - 2 > bytes.size()) return;
        if (visit(marker, bytes.subspan(at, size_t(length) - 2))) return;
        at += size_t(length) - 2;
    }
}

}  // namespace

int jpegQuality(std::span<const uint8_t> bytes) {
    int quality = 0;
    headerSegments(bytes, [&](int marker, std::span<const uint8_t> payload) {
        // One or more tables: Pq/Tq, then 64 entries of 8 or 16 bits; the first luminance one (Tq 0).
        for (size_t at = 0; marker == 0xDB && at < payload.size();) {
            const int pqtq = payload[at++];
            const size_t entry = pqtq >> 4 ? 2 : 1;
            if (payload.size() - at < 64 * entry) return true;  // truncated: unknown
            std::array<int, 64> table{};
            for (int& v : table) v = entry == 2 ? (payload[at] << 8) | payload[at + 1] : payload[at], at += entry;
            if ((pqtq & 15) == 0) return quality = qualityOf(table), true;
        }
        return false;
    });
    return quality;
}

bool jpegChroma420(std::span<const uint8_t> bytes) {
    bool half = false;
    headerSegments(bytes, [&](int marker, std::span<const uint8_t> payload) {
        if (marker < 0xC0 || marker > 0xC2) return false;  // baseline, extended or progressive frame (T.81 §B.2.2)
        // P, Y, X, Nf, then per component C, Hi << 4 | Vi, Tq: Y 2 x 2, Cb and Cr 1 x 1
        half = payload.size() >= 15 && payload[5] == 3 && payload[7] == 0x22 && payload[10] == 0x11 && payload[13] == 0x11;
        return true;
    });
    return half;
}

std::vector<uint8_t> jpegFileHead(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> head(kHeadBytes);
    in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<size_t>(in.gcount()));
    return head;
}

}  // namespace hlod
