// Simplification (both simplifiers), locked borders, the measured geometric error, and the
// largest border gap between neighbouring pieces simplified at different levels.
#include "helpers.h"

#include <algorithm>
#include <array>
#include <set>

namespace hlod::test {
namespace {

// Vertices of `m` whose `axis` coordinate equals `value` (on a cut plane), as degenerate
// "triangles" so surfaceDistance samples exactly those points.
SubMesh pointsOnPlane(const MeshData& m, int axis, float value) {
    SubMesh out;
    for (size_t i = 0; i < m.vertexCount(); ++i)
        if (m.positions[3 * i + axis] == value) {
            const uint32_t k = static_cast<uint32_t>(out.mesh.vertexCount());
            out.mesh.positions.insert(out.mesh.positions.end(), m.positions.begin() + 3 * i, m.positions.begin() + 3 * i + 3);
            out.mesh.indices.insert(out.mesh.indices.end(), {k, k, k});
        }
    return out;
}

std::set<std::array<float, 3>> borderPositions(const MeshData& m, float size) {
    std::set<std::array<float, 3>> s;
    for (size_t i = 0; i < m.vertexCount(); ++i) {
        const float x = m.positions[3 * i], y = m.positions[3 * i + 1];
        if (x == 0 || y == 0 || x == size || y == size) s.insert({x, y, m.positions[3 * i + 2]});
    }
    return s;
}

class Simplify : public ::testing::TestWithParam<Simplifier> {};

TEST_P(Simplify, ReachesTheFactorAndKeepsBorderVertices) {
    const Piece p = terrain(GetParam() == Simplifier::Meshopt ? 60 : 30);
    const double factor = 8;
    const MeshData s = simplifyMesh(p.mesh, factor, GetParam());
    const double expected = p.mesh.triangleCount() / factor;
    // Locked borders (4 n border edges) bound how far a small piece can go: allow +60 %.
    EXPECT_GE(double(s.triangleCount()), 0.9 * expected);
    EXPECT_LE(double(s.triangleCount()), 1.6 * expected);
    EXPECT_EQ(borderPositions(s, 100), borderPositions(p.mesh, 100));
    EXPECT_EQ(s.texcoords.size(), 2 * s.vertexCount());
    for (size_t i = 0; i < s.vertexCount(); ++i)  // surviving vertices keep their exact UVs
        ASSERT_NEAR(s.texcoords[2 * i], s.positions[3 * i] / 100.0f, 1e-6f);
}

INSTANTIATE_TEST_SUITE_P(Both, Simplify, ::testing::Values(Simplifier::Meshopt, Simplifier::OpenMesh));

TEST(Simplify, FactorBelowOneKeepsTheOriginal) {
    const Piece p = terrain(10);
    EXPECT_EQ(simplifyMesh(p.mesh, 0.8, Simplifier::Meshopt).indices, p.mesh.indices);
}

TEST(Simplify, SplitByMaterialKeepsEveryTriangle) {
    const Piece p = terrain(20, 100, true);
    const std::vector<SubMesh> parts = splitByMaterial(p);
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_EQ(parts[0].mesh.triangleCount() + parts[1].mesh.triangleCount(), p.mesh.triangleCount());
}

TEST(GeometricError, IsMeasuredAndGrowsWithTheFactor) {
    const Piece p = terrain(60);
    const std::vector<SubMesh> original = splitByMaterial(p);
    EXPECT_LT(surfaceDistance(original, original), 1e-9);
    double previous = 0;
    for (double factor : {4.0, 16.0, 64.0}) {
        std::vector<SubMesh> simplified = original;
        simplified[0].mesh = simplifyMesh(original[0].mesh, factor, Simplifier::Meshopt);
        const double error = surfaceDistance(simplified, original);
        EXPECT_GT(error, 0.0);
        EXPECT_LT(error, 4.0);  // the wave's amplitude is 2
        EXPECT_GE(error, previous * 0.99);
        previous = error;
    }
}

// Neighbouring pieces A and B of one parent; A simplified at level L, B's children at L+1:
// every vertex on their common plane must lie on the other side's surface.
TEST(Cracks, LargestBorderGapBetweenLevelsIsZero) {
    const Piece block = terrain(96);
    const std::vector<Piece> pieces = dividePiece(block, 4);
    ASSERT_EQ(pieces.size(), 4u);
    const float plane = pieceBounds(pieces[0].mesh).max.x;
    const MeshData a = simplifyMesh(pieces[0].mesh, 6, Simplifier::Meshopt);
    std::vector<SubMesh> bChildren;
    for (Piece& child : dividePiece(pieces[1], 4)) bChildren.push_back({0, simplifyMesh(child.mesh, 1.5, Simplifier::Meshopt), {}});
    const double gapAtoB = surfaceDistance({pointsOnPlane(a, 0, plane)}, bChildren);
    std::vector<SubMesh> bPoints;
    for (const SubMesh& c : bChildren) bPoints.push_back(pointsOnPlane(c.mesh, 0, plane));
    const double gapBtoA = surfaceDistance(bPoints, {{0, a, {}}});
    EXPECT_GT(pointsOnPlane(a, 0, plane).mesh.vertexCount(), 10u);
    EXPECT_LE(gapAtoB, 1e-5);
    EXPECT_LE(gapBtoA, 1e-5);
}

}  // namespace
}  // namespace hlod::test
