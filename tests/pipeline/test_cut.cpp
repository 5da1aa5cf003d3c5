// Plane cut (Fig. 3.2), division into c_levelFactor pieces, grid split and border consistency.
#include "helpers.h"

#include <algorithm>
#include <array>

namespace hlod::test {
namespace {

// Every vertex of the terrain has u = x/100, v = y/100: a cut that interpolates exactly keeps it.
void expectUVsExact(const MeshData& m) {
    for (size_t i = 0; i < m.vertexCount(); ++i) {
        ASSERT_NEAR(m.texcoords[2 * i], m.positions[3 * i] / 100.0f, 2e-6f) << "vertex " << i;
        ASSERT_NEAR(m.texcoords[2 * i + 1], m.positions[3 * i + 1] / 100.0f, 2e-6f) << "vertex " << i;
    }
}

TEST(Cut, SplitTrianglesKeepAreaAndInterpolateUVsExactly) {
    const Piece p = terrain(40);
    const CutResult cut = cutPiece(p, 0, 37.3f);  // crosses a whole column of triangles
    EXPECT_GT(cut.below.mesh.triangleCount() + cut.above.mesh.triangleCount(), p.mesh.triangleCount());
    EXPECT_NEAR(meshArea(cut.below.mesh) + meshArea(cut.above.mesh), meshArea(p.mesh), 1e-6 * meshArea(p.mesh));
    for (const Piece* side : {&cut.below, &cut.above}) {
        expectUVsExact(side->mesh);
        EXPECT_EQ(side->materials.size(), side->mesh.triangleCount());
    }
    for (size_t i = 0; i < cut.below.mesh.vertexCount(); ++i) EXPECT_LE(cut.below.mesh.positions[3 * i], 37.3f);
    for (size_t i = 0; i < cut.above.mesh.vertexCount(); ++i) EXPECT_GE(cut.above.mesh.positions[3 * i], 37.3f);
}

TEST(Cut, BothSidesShareTheSameVerticesOnThePlane) {
    const CutResult cut = cutPiece(terrain(30), 1, 51.7f);
    auto onPlane = [](const MeshData& m) {
        std::vector<std::array<float, 3>> v;
        for (size_t i = 0; i < m.vertexCount(); ++i)
            if (m.positions[3 * i + 1] == 51.7f) v.push_back({m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]});
        std::sort(v.begin(), v.end());
        return v;
    };
    const auto below = onPlane(cut.below.mesh), above = onPlane(cut.above.mesh);
    EXPECT_EQ(below.size(), 61u);  // one new vertex per crossed edge: 31 grid edges + 30 diagonals
    EXPECT_EQ(below, above);       // bit-identical: no crack between the two sides
}

TEST(Cut, TriangleWithAVertexOnThePlaneSplitsIntoTwo) {
    Piece p;
    p.mesh.positions = {0, 0, 0, 2, -1, 0, 2, 1, 0};
    p.mesh.indices = {0, 1, 2};
    p.materials = {0};
    const CutResult cut = cutPiece(p, 1, 0.0f);
    EXPECT_EQ(cut.below.mesh.triangleCount(), 1u);
    EXPECT_EQ(cut.above.mesh.triangleCount(), 1u);
    EXPECT_NEAR(meshArea(cut.below.mesh), 1.0, 1e-6);
}

TEST(Divide, PiecesHaveEqualTriangleCountsAndTileTheParent) {
    const Piece p = terrain(64, 100, true);
    const std::vector<Piece> pieces = dividePiece(p, 4);
    ASSERT_EQ(pieces.size(), 4u);
    double area = 0;
    size_t triangles = 0;
    for (const Piece& c : pieces) {
        area += meshArea(c.mesh);
        triangles += c.mesh.triangleCount();
        EXPECT_NEAR(double(c.mesh.triangleCount()) / p.mesh.triangleCount(), 0.25, 0.04);  // + cut triangles
        expectUVsExact(c.mesh);
    }
    EXPECT_NEAR(area, meshArea(p.mesh), 1e-6 * area);
    EXPECT_GE(triangles, p.mesh.triangleCount());
    for (size_t k = 1; k < pieces.size(); ++k)  // consecutive slabs along x, touching
        EXPECT_EQ(pieceBounds(pieces[k - 1].mesh).max.x, pieceBounds(pieces[k].mesh).min.x);
}

// Each slab's sides (stop 40): the piece's own, and the planes that cut it from its neighbours.
TEST(Divide, EachPieceKnowsTheSidesItShares) {
    const Piece p = terrain(64);
    const Sides highY = sideBit(1, true);
    std::vector<Sides> sides;
    const std::vector<Piece> pieces = dividePiece(p, 4, Planes::Balanced, highY, &sides);
    ASSERT_EQ(pieces.size(), 4u);
    ASSERT_EQ(sides.size(), 4u);
    EXPECT_EQ(sides[0], highY | sideBit(0, true));
    EXPECT_EQ(sides[1], highY | sideBit(0, false) | sideBit(0, true));
    EXPECT_EQ(sides[2], highY | sideBit(0, false) | sideBit(0, true));
    EXPECT_EQ(sides[3], highY | sideBit(0, false));
    Piece ends;  // the middle slabs of even planes are empty and dropped: the outer two keep their cuts
    ends.mesh = p.mesh, ends.mesh.indices.clear();
    for (size_t t = 0; t < p.mesh.triangleCount(); ++t)
        if (const float x = p.mesh.positions[3 * p.mesh.indices[3 * t]]; x < 19 || x > 81) {
            ends.mesh.indices.insert(ends.mesh.indices.end(), p.mesh.indices.begin() + 3 * t, p.mesh.indices.begin() + 3 * t + 3);
            ends.materials.push_back(0);
        }
    ASSERT_EQ(dividePiece(ends, 4, Planes::Even, 0, &sides).size(), 2u);
    EXPECT_EQ(sides, (std::vector<Sides>{sideBit(0, true), sideBit(0, false)}));
}

// A block shares only the sides on grid lines: the input's outline borders nothing (stop 40).
TEST(Grid, ABlockSharesTheSidesOnGridLines) {
    const Piece p = terrain(50, 100);
    const GridSpec g = chooseGrid(pieceBounds(p.mesh), p.mesh.triangleCount(), 1250, 0);
    ASSERT_EQ(g.cellsU * g.cellsV, 4u);
    const std::vector<Piece> cells = splitByGrid(p, g);
    const Sides highU = sideBit(g.axisU, true), highV = sideBit(g.axisV, true);
    EXPECT_EQ(blockSides(pieceBounds(cells[0].mesh), g), highU | highV);
    EXPECT_EQ(blockSides(pieceBounds(cells[3].mesh), g), sideBit(g.axisU, false) | sideBit(g.axisV, false));
    EXPECT_EQ(blockSides(pieceBounds(p.mesh), g), 0);  // the whole input touches no line with a face
}

TEST(Grid, SplitTilesTheInputOverTheTwoLongestAxes) {
    Piece p = terrain(50, 100);
    for (size_t i = 0; i < p.mesh.vertexCount(); ++i) std::swap(p.mesh.positions[3 * i + 1], p.mesh.positions[3 * i + 2]);
    const GridSpec g = chooseGrid(pieceBounds(p.mesh), p.mesh.triangleCount(), 1250, 0);
    EXPECT_EQ(g.axisU, 0);
    EXPECT_EQ(g.axisV, 2);  // y is the thin (vertical) axis here
    EXPECT_EQ(g.cellsU * g.cellsV, 4u);
    const std::vector<Piece> cells = splitByGrid(p, g);
    double area = 0;
    for (const Piece& c : cells) area += meshArea(c.mesh);
    EXPECT_NEAR(area, meshArea(p.mesh), 1e-6 * area);
    EXPECT_EQ(chooseGrid(pieceBounds(p.mesh), 5000, 1, 30).cellsU, 4u);  // --block-size 30 over 100 units
    EXPECT_THROW(chooseGrid(pieceBounds(p.mesh), 5000, 1, 0.01), std::invalid_argument);  // 4096 x 4096 blocks
}

// --planes even (§3.2 read literally): planes at 1/4, 2/4, 3/4 of the longest side, whatever the
// density; a piece with nothing between two planes gets no child there.
TEST(DividePiece, EvenPlanesAreEvenlySpacedAndEmptyPiecesAreDropped) {
    const Piece p = terrain(30, 100);
    const std::vector<Piece> pieces = dividePiece(p, 4, Planes::Even);
    ASSERT_EQ(pieces.size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
        EXPECT_EQ(pieceBounds(pieces[k].mesh).min.x, 25.0f * k);
        EXPECT_EQ(pieceBounds(pieces[k].mesh).max.x, 25.0f * (k + 1));
    }
    Piece ends;  // triangles only where x < 20 or x > 80: the two middle slabs are empty
    ends.mesh = p.mesh, ends.mesh.indices.clear();
    for (size_t t = 0; t < p.mesh.triangleCount(); ++t) {
        const float x = p.mesh.positions[3 * p.mesh.indices[3 * t]];
        if (x < 19 || x > 81) {
            ends.mesh.indices.insert(ends.mesh.indices.end(), p.mesh.indices.begin() + 3 * t, p.mesh.indices.begin() + 3 * t + 3);
            ends.materials.push_back(0);
        }
    }
    EXPECT_EQ(dividePiece(ends, 4, Planes::Even).size(), 2u);
    EXPECT_EQ(dividePiece(ends, 4, Planes::Balanced).size(), 4u);  // balanced planes follow the triangles
}

TEST(TempBlocks, PieceRoundTripsThroughItsFileAndChunksAreWelded) {
    TempDir dir;
    const Piece p = terrain(20);
    const CutResult cut = cutPiece(p, 0, 50.0f);
    appendPiece(dir.file("b"), cut.below);
    appendPiece(dir.file("b"), cut.above);
    const Piece back = loadPiece(dir.file("b"));
    EXPECT_EQ(back.mesh.triangleCount(), cut.below.mesh.triangleCount() + cut.above.mesh.triangleCount());
    EXPECT_EQ(back.mesh.vertexCount(), p.mesh.vertexCount());  // the 21 shared plane vertices welded
    EXPECT_TRUE(back.mesh.normals.empty());  // absent attributes stay absent
    EXPECT_TRUE(back.mesh.colors.empty());
    EXPECT_THROW(loadPiece(dir.file("missing")), std::runtime_error);
}

}  // namespace
}  // namespace hlod::test
