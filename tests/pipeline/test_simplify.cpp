// Simplification (both simplifiers), locked borders, the measured geometric error, and the
// largest border gap between neighbouring pieces simplified at different levels.
#include "helpers.h"

#include <algorithm>
#include <array>
#include <map>
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

// Faces OpenMesh refuses (an edge of three faces: a fin, as scans have) are kept unsimplified,
// without a line of OpenMesh's own on standard error (`PolyMeshT::add_face: complex edge`, one a
// refused face, naming no file, until stop 51).
TEST(Simplify, OpenMeshKeepsRefusedFacesQuietly) {
    Piece p = terrain(30);
    addFins(p, 37);
    ::testing::internal::CaptureStderr();
    const MeshData s = simplifyMesh(p.mesh, 8, Simplifier::OpenMesh);
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_LT(s.triangleCount(), p.mesh.triangleCount() / 2);
    size_t fins = 0;  // the refused faces, kept: each reaches z = 3 or -3
    for (size_t t = 0; t < s.triangleCount(); ++t)
        for (int c = 0; c < 3; ++c) fins += std::abs(s.positions[3 * s.indices[3 * t + c] + 2]) == 3.0f;
    EXPECT_GE(fins, 1u);
}

// Only border vertices on the faces of the piece's shared sides are locked (stop 40): an outline
// on no cut plane simplifies like any open border, so a piece reaches a target its outline
// alone would exceed (240 outline vertices, a target of 120 triangles).
TEST(Simplify, OnlyTheSharedSidesBordersAreLocked) {
    const uint32_t n = 60;
    const Piece p = terrain(n);
    const auto count = [](const std::vector<uint8_t>& v) { return std::count(v.begin(), v.end(), 1); };
    EXPECT_EQ(count(sharedVertices(p)), 4 * n);
    EXPECT_EQ(count(sharedVertices(p, 0)), 0);
    EXPECT_EQ(count(sharedVertices(p, sideBit(0, false))), n + 1);             // x = 0
    EXPECT_EQ(count(sharedVertices(p, sideBit(0, false) | sideBit(1, true))), 2 * n + 1);  // and y = 100
    const double factor = 60, target = p.mesh.triangleCount() / factor;
    const SimplifiedNode locked = simplifyNode(p, factor, Simplifier::Meshopt);
    const SimplifiedNode free = simplifyNode(p, factor, Simplifier::Meshopt, 0);
    EXPECT_GT(double(locked.piece.mesh.triangleCount()), kTargetSlack * target);
    EXPECT_LE(double(free.piece.mesh.triangleCount()), kTargetSlack * target);
    const SimplifiedNode oneSide = simplifyNode(p, factor, Simplifier::Meshopt, sideBit(0, false));
    std::set<std::array<float, 3>> kept;  // the x = 0 side's vertices all stay
    for (size_t i = 0; i < oneSide.piece.mesh.vertexCount(); ++i)
        if (oneSide.piece.mesh.positions[3 * i] == 0) kept.insert({0, oneSide.piece.mesh.positions[3 * i + 1], oneSide.piece.mesh.positions[3 * i + 2]});
    EXPECT_EQ(kept.size(), n + 1);
}

// Stop 41 (--error-cap on, pipeline/TREE.md "Locked borders cost triangles, not accuracy"): a
// ceiling on the simplifier's error stops the simplification there, keeping more triangles than
// the factor asks; a ceiling twice the error the factor reaches changes nothing; the shared sides
// (x = 0 and x = 100, as a §3.2 slab's) stay whole either way.
TEST(Simplify, AnErrorCeilingStopsTheSimplificationThere) {
    const uint32_t n = 60;
    const Piece p = terrain(n);
    const Sides slab = sideBit(0, false) | sideBit(0, true);
    const SimplifiedNode uncapped = simplifyNode(p, 60, Simplifier::Meshopt, slab);
    ASSERT_GT(uncapped.error, 0);
    const SimplifiedNode capped = simplifyNode(p, 60, Simplifier::Meshopt, slab, uncapped.error / 4);
    EXPECT_LE(capped.error, uncapped.error / 4 * (1 + 1e-6));
    EXPECT_GT(capped.piece.mesh.triangleCount(), uncapped.piece.mesh.triangleCount());
    for (float x : {0.0f, 100.0f}) EXPECT_EQ(pointsOnPlane(capped.piece.mesh, 0, x).mesh.vertexCount(), n + 1) << "x = " << x;
    const SimplifiedNode loose = simplifyNode(p, 60, Simplifier::Meshopt, slab, 2 * uncapped.error);
    EXPECT_EQ(loose.piece.mesh.indices, uncapped.piece.mesh.indices);
    EXPECT_EQ(loose.piece.mesh.positions, uncapped.piece.mesh.positions);
}

// A scanned block riddled with small holes (2 x 2 quads missing every 4 quads: 784 holes, as
// glass and occluders leave in a facade scan) whose outer edge lies on the cut planes (480
// locked vertices). Without closing holes each keeps >= 3 border vertices: with V = B border
// vertices and H holes a surface has F = V + 2H - 2 >= 5H + 478 = 4,398 triangles. With the
// fallback it reaches kTargetSlack x c_desiredTris (2,000 here: the locked outline alone needs
// 478) while every cut-plane vertex stays where it was, and every vertex keeps its exact UV.
Piece holedTerrain(uint32_t n) {
    const Piece full = terrain(n);
    Piece holed;
    holed.mesh = full.mesh, holed.mesh.indices.clear();
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            if (i >= 4 && j >= 4 && i + 4 < n && j + 4 < n && i % 4 < 2 && j % 4 < 2) continue;  // a hole
            const size_t t = 2 * (size_t(j) * n + i);
            holed.mesh.indices.insert(holed.mesh.indices.end(), full.mesh.indices.begin() + 3 * t, full.mesh.indices.begin() + 3 * t + 6);
            holed.materials.insert(holed.materials.end(), {0, 0});
        }
    return holed;
}

TEST(Simplify, HoleRiddledBlockReachesTheTargetWithItsCutPlaneBordersLocked) {
    const Piece holed = holedTerrain(120);
    const std::vector<SubMesh> parts = splitByMaterial(holed);
    ASSERT_EQ(parts.size(), 1u);
    const double desiredTris = 2000;
    const MeshData s = simplifyMesh(parts[0].mesh, parts[0].mesh.triangleCount() / desiredTris, Simplifier::Meshopt, parts[0].locked);
    EXPECT_LE(double(s.triangleCount()), kTargetSlack * desiredTris);
    EXPECT_EQ(borderPositions(s, 100), borderPositions(holed.mesh, 100));
    for (size_t i = 0; i < s.vertexCount(); ++i) {
        ASSERT_NEAR(s.texcoords[2 * i], s.positions[3 * i] / 100.0f, 1e-6f);
        ASSERT_NEAR(s.texcoords[2 * i + 1], s.positions[3 * i + 1] / 100.0f, 1e-6f);
    }
}

// With a ceiling the hole-filling rounds share it (simplify.cpp): the holed block above, whose
// uncapped simplification needs the fallback to reach its target, capped at half its error stays
// within the ceiling over all its rounds, keeps more triangles, and its cut planes and UVs intact.
TEST(Simplify, HoleFillingRoundsShareTheErrorCeiling) {
    const Piece holed = holedTerrain(120);
    const double factor = holed.mesh.triangleCount() / 2000.0;
    const SimplifiedNode uncapped = simplifyNode(holed, factor, Simplifier::Meshopt);
    ASSERT_LE(double(uncapped.piece.mesh.triangleCount()), kTargetSlack * 2000);
    ASSERT_GT(uncapped.error, 0);
    const SimplifiedNode capped = simplifyNode(holed, factor, Simplifier::Meshopt, kAllSides, uncapped.error / 2);
    EXPECT_LE(capped.error, uncapped.error / 2 * (1 + 1e-6));
    EXPECT_GT(capped.piece.mesh.triangleCount(), uncapped.piece.mesh.triangleCount());
    EXPECT_EQ(borderPositions(capped.piece.mesh, 100), borderPositions(holed.mesh, 100));
    const MeshData& m = capped.piece.mesh;
    ASSERT_FALSE(capped.geometryOnly);  // no seams: pass 1 is kept
    for (size_t i = 0; i < m.vertexCount(); ++i) {
        ASSERT_NEAR(m.texcoords[2 * i], m.positions[3 * i] / 100.0f, 1e-6f);
        ASSERT_NEAR(m.texcoords[2 * i + 1], m.positions[3 * i + 1] / 100.0f, 1e-6f);
    }
}

// Open border loops of `m` (its open edges joined at their vertices): its outline and its holes.
// Edges are joined by vertex index, so a seam would count as a border: for meshes without seams.
size_t borderLoops(const MeshData& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (size_t c = 0; c < m.indices.size(); ++c) {
        const uint32_t a = m.indices[c], b = m.indices[c - c % 3 + (c + 1) % 3];
        ++uses[{std::min(a, b), std::max(a, b)}];
    }
    std::vector<uint32_t> root(m.vertexCount());
    for (uint32_t i = 0; i < root.size(); ++i) root[i] = i;
    const auto find = [&](uint32_t i) {
        while (root[i] != i) i = root[i] = root[root[i]];
        return i;
    };
    std::set<uint32_t> onBorder;
    for (const auto& [edge, n] : uses)
        if (n == 1) root[find(edge.first)] = find(edge.second), onBorder.insert(edge.first), onBorder.insert(edge.second);
    std::set<uint32_t> loops;
    for (uint32_t v : onBorder) loops.insert(find(v));
    return loops.size();
}

// A hole-filling round that no longer lowers the count is undone (simplify.cpp): the holed block
// capped at a twentieth of its uncapped error stops over the slack with ceiling left; the round
// that adds the patches cannot collapse them within what is left (kept, it would close every hole
// for 6,572 triangles against 5,206), so every hole stays open.
TEST(Simplify, ARoundThatNoLongerLowersTheCountIsUndone) {
    const Piece holed = holedTerrain(120);
    ASSERT_EQ(borderLoops(holed.mesh), 785u);  // the outline and 784 holes
    const double factor = holed.mesh.triangleCount() / 2000.0;
    const SimplifiedNode uncapped = simplifyNode(holed, factor, Simplifier::Meshopt);
    EXPECT_EQ(borderLoops(uncapped.piece.mesh), 1u);  // uncapped, the rounds close them all
    const SimplifiedNode capped = simplifyNode(holed, factor, Simplifier::Meshopt, kAllSides, uncapped.error / 20);
    ASSERT_GT(double(capped.piece.mesh.triangleCount()), kTargetSlack * 2000);
    ASSERT_LT(capped.error, uncapped.error / 20);  // ceiling left after the first round: the rounds went on
    EXPECT_EQ(borderLoops(capped.piece.mesh), 785u);
}

// A piece without seams (one vertex per position) has nothing pass 2 could change: over the
// slack (its locked outline, 240 vertices, exceeds a 40-triangle target) it keeps pass 1's result
// and its exact texture coordinates, capped or not (pass 2 repeated the same collapses and dropped
// the UVs, so such a node got a baked texture).
TEST(Simplify, APieceWithoutSeamsKeepsItsTextureCoordinatesOverTheSlack) {
    const Piece p = terrain(60);
    const double factor = p.mesh.triangleCount() / 40.0;
    const SimplifiedNode uncapped = simplifyNode(p, factor, Simplifier::Meshopt);
    ASSERT_GT(uncapped.error, 0);
    for (const double ceiling : {HUGE_VAL, uncapped.error / 2}) {
        const SimplifiedNode s = simplifyNode(p, factor, Simplifier::Meshopt, kAllSides, ceiling);
        ASSERT_GT(double(s.piece.mesh.triangleCount()), kTargetSlack * 40);
        EXPECT_FALSE(s.geometryOnly);
        EXPECT_LE(s.error, ceiling * (1 + 1e-6));
        EXPECT_EQ(borderPositions(s.piece.mesh, 100), borderPositions(p.mesh, 100));
        const MeshData& m = s.piece.mesh;
        ASSERT_EQ(m.texcoords.size(), 2 * m.vertexCount());
        for (size_t i = 0; i < m.vertexCount(); ++i) {
            ASSERT_NEAR(m.texcoords[2 * i], m.positions[3 * i] / 100.0f, 1e-6f);
            ASSERT_NEAR(m.texcoords[2 * i + 1], m.positions[3 * i + 1] / 100.0f, 1e-6f);
        }
    }
}

// A terrain whose every quad is its own UV chart (four vertices per quad: every edge a seam), as
// fragmented photogrammetry charts are.
Piece quadCharts(uint32_t n) {
    const Piece t = terrain(n);
    Piece p;
    for (size_t q = 0; q < t.mesh.triangleCount() / 2; ++q) {
        const uint32_t* c = &t.mesh.indices[6 * q];  // a, b, d, a, d, c
        const uint32_t base = static_cast<uint32_t>(p.mesh.vertexCount());
        for (uint32_t v : {c[0], c[1], c[2], c[5]}) {
            p.mesh.positions.insert(p.mesh.positions.end(), t.mesh.positions.begin() + 3 * v, t.mesh.positions.begin() + 3 * v + 3);
            p.mesh.texcoords.insert(p.mesh.texcoords.end(), {float(q) + 0.25f * (v == c[1] || v == c[2]), 0.25f * (v == c[2] || v == c[5])});
        }
        p.mesh.indices.insert(p.mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        p.materials.insert(p.materials.end(), {0, 0});
    }
    return p;
}

// A piece with seams chooses its pass as without a ceiling (simplify.cpp): one seam (two materials
// welded apart along x = 50) lets the uncapped seam-preserving pass reach the target, so a capped
// pass over the slack is kept and keeps its UVs; charts of one quad each keep the seam-preserving
// pass over the slack, so the capped node is geometry only, within its ceiling, its cut planes whole.
TEST(Simplify, APieceWithSeamsChoosesItsPassAsWithoutACeiling) {
    const Piece seam = weldPiece(terrain(60, 100, true), 1e-6);
    ASSERT_GT(seam.mesh.vertexCount(), 61u * 61u);  // the x = 50 column twice
    const double factor = seam.mesh.triangleCount() / 100.0;
    const SimplifiedNode uncapped = simplifyNode(seam, factor, Simplifier::Meshopt, 0);
    ASSERT_FALSE(uncapped.geometryOnly);
    const SimplifiedNode capped = simplifyNode(seam, factor, Simplifier::Meshopt, 0, uncapped.error / 8);
    ASSERT_GT(double(capped.piece.mesh.triangleCount()), kTargetSlack * 100);
    EXPECT_FALSE(capped.geometryOnly);
    EXPECT_LE(capped.error, uncapped.error / 8 * (1 + 1e-6));
    EXPECT_EQ(capped.piece.mesh.texcoords.size(), 2 * capped.piece.mesh.vertexCount());

    const Piece charts = quadCharts(40);
    const double chartsFactor = charts.mesh.triangleCount() / 100.0;
    const SimplifiedNode chartsUncapped = simplifyNode(charts, chartsFactor, Simplifier::Meshopt);
    ASSERT_TRUE(chartsUncapped.geometryOnly);
    const SimplifiedNode chartsCapped = simplifyNode(charts, chartsFactor, Simplifier::Meshopt, kAllSides, chartsUncapped.error / 4);
    EXPECT_TRUE(chartsCapped.geometryOnly);
    EXPECT_LE(chartsCapped.error, chartsUncapped.error / 4 * (1 + 1e-6));
    EXPECT_GT(chartsCapped.piece.mesh.triangleCount(), chartsUncapped.piece.mesh.triangleCount());
    EXPECT_EQ(borderPositions(chartsCapped.piece.mesh, 100), borderPositions(terrain(40).mesh, 100));
}

// The patches close every hole and only holes: the holed terrain's holes filled give a surface
// whose only open border is its outline (on the cut planes), each edge used once per direction.
TEST(Simplify, HolePatchesCloseHolesButNotTheOutline) {
    const uint32_t n = 24;
    Piece p = terrain(n);
    std::vector<uint32_t> indices;
    for (size_t t = 0; t < p.mesh.triangleCount(); ++t)
        if (t / 2 != 5 * n + 5 && t / 2 != 12 * n + 14 && t / 2 != 12 * n + 15)  // a 1-quad and a 2-quad hole
            indices.insert(indices.end(), p.mesh.indices.begin() + 3 * t, p.mesh.indices.begin() + 3 * t + 3);
    const std::vector<uint32_t> patches = holePatches(p.mesh, indices, std::vector<uint8_t>(p.mesh.vertexCount()));
    EXPECT_EQ(patches.size(), 3u * (2 + 4));  // a 4-vertex loop needs 2 triangles, a 6-vertex loop 4
    indices.insert(indices.end(), patches.begin(), patches.end());
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t e = 0; e < indices.size(); ++e) ++directed[{indices[e], indices[e - e % 3 + (e + 1) % 3]}];
    size_t open = 0;
    for (const auto& [edge, uses] : directed) {
        EXPECT_EQ(uses, 1);
        open += !directed.count({edge.second, edge.first});
    }
    EXPECT_EQ(open, 4u * n);  // the outline alone
    // A locked vertex on a loop keeps that hole open.
    std::vector<uint8_t> locked(p.mesh.vertexCount());
    locked[5 * (n + 1) + 5] = 1;
    EXPECT_EQ(holePatches(p.mesh, std::vector<uint32_t>(indices.begin(), indices.end() - patches.size()), locked).size(), 3u * 4);
}

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
