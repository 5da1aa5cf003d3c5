// Geometry blobs keep one position where only another attribute splits a vertex (a UV chart's
// seam; formats/codec_draco.cpp): a grid whose every quad is a chart of its own decodes to the
// same positions and as many points, in a fraction of the bytes of the same quads coded apart; a
// face two of whose corners share a position is dropped, and the counts say so.
#include "helpers.h"

#include <array>
#include <cstdio>
#include <set>

namespace hlod::test {
namespace {

// n x n quads, each with its own four vertices and UVs over its own quarter of a cell of the
// texture (a chart per quad); `gap` moves each quad's positions apart so none is shared.
MeshData quadCharts(uint32_t n, float gap) {
    MeshData m;
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t base = static_cast<uint32_t>(m.vertexCount());
            for (uint32_t k = 0; k < 4; ++k) {
                const float x = float(i + k % 2) + gap * float(i), y = float(j + k / 2) + gap * float(j);
                m.positions.insert(m.positions.end(), {x, y, 0.25f * float((i + j + k % 2 + k / 2) % 3)});
                m.texcoords.insert(m.texcoords.end(), {(float(i) + 0.5f * float(k % 2)) / float(n), (float(j) + 0.5f * float(k / 2)) / float(n)});
            }
            m.indices.insert(m.indices.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
        }
    return m;
}

std::set<std::array<float, 3>> positions(const MeshData& m) {
    std::set<std::array<float, 3>> out;
    for (uint32_t i : m.indices) out.insert({m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]});
    return out;
}

TEST(Seams, ChartsSharingPositionsCodeThemOnce) {
    DracoOptions o;
    o.positionStep = 1.0 / 64;  // every coordinate below is on the lattice
    const MeshData shared = quadCharts(24, 0), apart = quadCharts(24, 1);
    const EncodedBlob blob = encodeGeometry(shared, o);
    const MeshData decoded = decodeGeometry(blob.bytes, "blob");
    EXPECT_EQ(positions(decoded), positions(shared));  // on the lattice: exact
    EXPECT_EQ(blob.info.triangles, shared.triangleCount());
    EXPECT_EQ(blob.info.vertices, shared.vertexCount());  // a point per (position, UV): no UV lost
    const size_t apartBytes = encodeGeometry(apart, o).bytes.size();
    std::printf("24 x 24 quad charts: %zu bytes sharing positions, %zu apart\n", blob.bytes.size(), apartBytes);
    EXPECT_LT(blob.bytes.size(), apartBytes * 3 / 4);
}

// A seam vertex snapped to 0 from below in one chart and from above in the other is one position
// (-0 and +0 are one lattice point): the same bytes as the seam at exactly 0 in both.
TEST(Seams, ZeroFromBelowAndAboveIsOnePosition) {
    DracoOptions o;
    o.positionStep = 1.0 / 64;
    MeshData exact = quadCharts(24, 0);
    for (size_t i = 0; i < exact.positions.size(); i += 3) exact.positions[i] -= 12;  // the seam x = 0 between quads 11 and 12
    MeshData signs = exact;
    for (size_t i = 0; i < signs.positions.size(); i += 3)
        if (signs.positions[i] == 0 && (i / 3) % 2 == 1) signs.positions[i] = -1e-6f;  // the right corners of quad 11: -0 once snapped
    const EncodedBlob a = encodeGeometry(exact, o), b = encodeGeometry(signs, o);
    EXPECT_EQ(a.bytes, b.bytes);
    EXPECT_EQ(positions(decodeGeometry(b.bytes, "blob")), positions(exact));
}

// A face two of whose corners share a lattice position (zero area as decoded) is dropped, with
// the same UV or another; when every face is such, they are all kept, as before.
TEST(Seams, AFaceWithTwoCornersAtOnePositionIsDropped) {
    for (float du : {0.0f, 0.25f}) {
        MeshData m = quadCharts(2, 0);
        const uint32_t copy = static_cast<uint32_t>(m.vertexCount());  // vertex 0's position again
        m.positions.insert(m.positions.end(), {m.positions[0], m.positions[1], m.positions[2]});
        m.texcoords.insert(m.texcoords.end(), {m.texcoords[0] + du, m.texcoords[1]});
        m.indices.insert(m.indices.end(), {0, copy, 1});
        const EncodedBlob blob = encodeGeometry(m, {});
        EXPECT_EQ(blob.info.triangles, m.triangleCount() - 1) << du;
        EXPECT_EQ(decodeGeometry(blob.bytes, "blob").triangleCount(), m.triangleCount() - 1) << du;
        const MeshData flat{{0, 0, 0, 0, 0, 0, 1, 0, 0}, {0, 0, 0.5f, 0, 1, 0}, {}, {}, {0, 1, 2}};  // its only face
        EXPECT_EQ(encodeGeometry(flat, {}).info.triangles, 1u);
    }
}

}  // namespace
}  // namespace hlod::test
