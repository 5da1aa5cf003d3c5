// On-disk layout of an HLOD database (formats/FORMAT.md): header fields, section tags, record
// sizes, sane limits, and little-endian byte packing shared by the reader, the writer, the
// fuzzers and the tests. Internal to formats/.
#pragma once

#include "formats/db.h"

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace hlod::layout {

static_assert(std::endian::native == std::endian::little, "hlod assumes a little-endian host");

// PNG-style magic: high bit, name, CR LF (catches text-mode transfers), EOF, LF.
inline constexpr std::array<uint8_t, 8> kMagic = {0x89, 'H', 'L', 'D', '\r', '\n', 0x1a, '\n'};
inline constexpr uint32_t kHeaderSize = 64;
inline constexpr uint32_t kMaxHeaderSize = 4096;

// Header field offsets (FORMAT.md §Header).
inline constexpr size_t kOffMajor = 8, kOffMinor = 10, kOffHeaderSize = 12, kOffSkeletonOffset = 16,
                        kOffSkeletonSize = 24, kOffSkeletonChecksum = 32, kOffFileSize = 40,
                        kOffFlags = 48;

inline constexpr uint32_t tag(const char (&s)[5]) {
    return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
           uint32_t(uint8_t(s[3])) << 24;
}
inline constexpr uint32_t kTagInfo = tag("INFO");
inline constexpr uint32_t kTagNode = tag("NODE");
inline constexpr uint32_t kTagBlob = tag("BLOB");
inline constexpr uint32_t kTagMeta = tag("META");

inline constexpr uint32_t kSectionEntrySize = 32;  // tag, recordSize, offset, size, count
inline constexpr uint32_t kInfoRecordSize = 8;
inline constexpr uint32_t kNodeRecordSize = 120;
inline constexpr uint32_t kBlobRecordSize = 56;

// Sane limits, checked before any allocation (FORMAT.md §Limits).
inline constexpr uint64_t kMaxSkeletonSize = uint64_t(1) << 32;
inline constexpr uint32_t kMaxSections = 256;
inline constexpr uint32_t kMaxTextureSide = 32768;
// A texture blob of N bytes may decode to at most kMaxTexelsPerBlobByte x N + kFreeTexels texels:
// deflate stops near 1032:1 (344 RGB texels a byte) and JPEG near 64 texels a byte, so a real
// image stays far below; a header claiming 26473 x 26376 texels in 700 bytes (a decompression
// bomb a fuzzer found) does not.
inline constexpr uint64_t kMaxTexelsPerBlobByte = 1024;
inline constexpr uint64_t kFreeTexels = uint64_t(1) << 20;
inline constexpr uint32_t kMaxElements = uint32_t(1) << 28;  // triangles or vertices per blob
inline constexpr uint32_t kMaxBlobsPerNode = 65536;
inline constexpr uint32_t kMaxMetaString = 1 << 20;

// Appends little-endian values to a byte vector.
struct ByteWriter {
    std::vector<uint8_t>& out;
    template <class T>
    void put(T value) {
        const size_t at = out.size();
        out.resize(at + sizeof(T));
        std::memcpy(out.data() + at, &value, sizeof(T));
    }
    void bytes(std::span<const uint8_t> s) { out.insert(out.end(), s.begin(), s.end()); }
};

// Reads little-endian values from a span; never reads past the end (throws FormatError).
struct ByteReader {
    std::span<const uint8_t> in;
    const std::string& name;
    const char* what;
    size_t pos = 0;

    template <class T>
    T get() {
        T value;
        need(sizeof(T));
        std::memcpy(&value, in.data() + pos, sizeof(T));
        pos += sizeof(T);
        return value;
    }
    std::span<const uint8_t> take(size_t n) {
        need(n);
        auto s = in.subspan(pos, n);
        pos += n;
        return s;
    }
    void need(size_t n) const {
        if (n > in.size() - pos) throw FormatError(name + ": truncated " + what);
    }
};

template <class T>
T load(std::span<const uint8_t> bytes, size_t offset) {
    T value;
    std::memcpy(&value, bytes.data() + offset, sizeof(T));
    return value;
}
template <class T>
void store(std::span<uint8_t> bytes, size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

// XXH3-64 of a byte range.
uint64_t checksum(std::span<const uint8_t> bytes);

// Serialised skeleton of `s` (sections INFO, NODE, BLOB, META) and a header for it.
std::vector<uint8_t> encodeSkeleton(const Skeleton& s);
std::array<uint8_t, kHeaderSize> encodeHeader(uint64_t skeletonOffset, std::span<const uint8_t> skeleton);

// The header's fields after every check of FORMAT.md §Header against the file size.
struct HeaderInfo {
    uint16_t major = 0, minor = 0;
    uint32_t headerSize = 0;
    uint64_t skeletonOffset = 0, skeletonSize = 0, skeletonChecksum = 0, fileSize = 0;
};
// `header` holds the file's first bytes (at least the header when the file is long enough).
HeaderInfo parseHeader(std::span<const uint8_t> header, uint64_t fileSize, const std::string& name);

}  // namespace hlod::layout
