// Test helpers for formats/: small meshes and images, and byte patching of the skeleton (with
// checksums fixed so that only the patched fact is wrong). TempDir and file bytes: temp_dir.h.
#pragma once

#include "formats/codec.h"
#include "formats/db.h"
#include "formats/layout.h"
#include "tests/support/fix_checksums.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <vector>

namespace hlod::test {

// An n x n grid in the plane z = height over [x0, x0 + size]^2, with texcoords.
inline MeshData gridMesh(uint32_t n, float x0 = 0, float size = 1, float height = 0) {
    MeshData m;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            float u = float(i) / float(n), v = float(j) / float(n);
            m.positions.insert(m.positions.end(), {x0 + u * size, x0 + v * size, height + 0.1f * u * v});
            m.texcoords.insert(m.texcoords.end(), {u, v});
        }
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}

inline Image gradientImage(uint32_t w, uint32_t h, uint32_t channels) {
    Image img{w, h, channels, std::vector<uint8_t>(size_t(w) * h * channels)};
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = uint8_t((i * 7 + i / (w * channels) * 13) & 0xff);
    return img;
}

// Absolute file offset of record `index` of section `tag` in a database image.
inline size_t recordOffset(const std::vector<uint8_t>& file, uint32_t tag, uint32_t index) {
    using namespace layout;
    const uint64_t sk = load<uint64_t>(file, kOffSkeletonOffset);
    const uint32_t count = load<uint32_t>(file, sk), entry = load<uint32_t>(file, sk + 4);
    for (uint32_t i = 0; i < count; ++i) {
        const size_t e = sk + 8 + size_t(i) * entry;
        if (load<uint32_t>(file, e) == tag) return sk + load<uint64_t>(file, e + 8) + size_t(index) * load<uint32_t>(file, e + 4);
    }
    ADD_FAILURE() << "no section with that tag";
    return 0;
}

// Overwrites a field of a record, then fixes the skeleton and header checksums.
template <class T>
void patchRecord(std::vector<uint8_t>& file, uint32_t tag, uint32_t index, size_t fieldOffset, T value) {
    layout::store(std::span(file), recordOffset(file, tag, index) + fieldOffset, value);
    fixChecksums(file);
}

// Field offsets inside a NODE / BLOB record (FORMAT.md §Node record, §Blob record).
inline constexpr size_t kNodeParent = 4, kNodeFirstChild = 8, kNodeNextSibling = 12, kNodeLevel = 16,
                        kNodeBoundsMinX = 24, kNodeCost = 48, kNodeTextured = 72;
inline constexpr size_t kBlobWidth = 24, kBlobOffset = 32, kBlobSize = 40;

}  // namespace hlod::test
