// Test fixture: recomputes the skeleton and header checksums of a whole `.hlod` file image in
// place (formats/FORMAT.md §Header), so that a test's or a fuzzer's mutation reaches the checks
// behind the checksums. No-op on an image too short to hold a header.
#pragma once

#include "formats/layout.h"

#include <cstdint>
#include <span>

namespace hlod::test {

inline void fixChecksums(std::span<uint8_t> file) {
    using namespace layout;
    if (file.size() < kOffHeaderSize + 4) return;
    const uint32_t headerSize = load<uint32_t>(file, kOffHeaderSize);
    if (headerSize < kHeaderSize || headerSize > file.size()) return;
    const uint64_t skOff = load<uint64_t>(file, kOffSkeletonOffset);
    const uint64_t skSize = load<uint64_t>(file, kOffSkeletonSize);
    if (skOff <= file.size() && skSize <= file.size() - skOff)
        store(file, kOffSkeletonChecksum, checksum(file.subspan(skOff, skSize)));
    store(file, headerSize - 8, checksum(file.first(headerSize - 8)));
}

}  // namespace hlod::test
