// Polygon faces cut by their shape (pipeline/polygon.h): a convex polygon keeps the fan, a concave
// one is ear-clipped so its triangles cover it once (until stop 46 an L-shaped face of area 3 read as
// triangles of area 4 folded over its notch), in OBJ and PLY alike, whether the vertices are held in
// memory or spilled to disk while the faces are read.
#include "helpers.h"

#include "pipeline/polygon.h"

#include <numeric>

namespace hlod::test {
namespace {

// Twice the signed area of every triangle of `corners` cut by triangulatePolygon, in the x-y plane.
std::vector<double> cutAreas(const std::vector<std::array<double, 3>>& corners, std::vector<std::array<uint32_t, 3>>& triangles) {
    triangles.clear();
    triangulatePolygon(corners, triangles);
    std::vector<double> areas;
    for (const auto& [a, b, c] : triangles) {
        const auto &p = corners[a], &q = corners[b], &r = corners[c];
        areas.push_back((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
    }
    return areas;
}

const std::vector<std::array<double, 3>> kL = {{2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}};  // area 3

TEST(Polygon, ConvexKeepsTheFanConcaveCoversItsAreaOnce) {
    std::vector<std::array<uint32_t, 3>> t;
    const std::vector<double> square = cutAreas({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, t);
    EXPECT_EQ(t, (std::vector<std::array<uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}}));
    const std::vector<double> l = cutAreas(kL, t);
    ASSERT_EQ(l.size(), 4u);
    for (double a : l) EXPECT_GT(a, 0);  // every triangle in the polygon's winding: none folded
    EXPECT_DOUBLE_EQ(std::accumulate(l.begin(), l.end(), 0.0), 6.0);  // twice the area 3
    // Clockwise, in another plane (y-z), from another corner: the same cover.
    std::vector<std::array<double, 3>> turned;
    for (size_t i = 0; i < kL.size(); ++i) turned.push_back({5, kL[(kL.size() - i + 2) % kL.size()][0], kL[(kL.size() - i + 2) % kL.size()][1]});
    t.clear();
    triangulatePolygon(turned, t);
    EXPECT_EQ(t.size(), 4u);
    // A star of 10 corners (5 reflex): 8 triangles, the star's area once.
    std::vector<std::array<double, 3>> star;
    for (int i = 0; i < 10; ++i) {
        const double r = i % 2 ? 1.0 : 3.0, a = i * M_PI / 5;
        star.push_back({r * std::cos(a), r * std::sin(a), 0});
    }
    const std::vector<double> s = cutAreas(star, t);
    ASSERT_EQ(s.size(), 8u);
    double shoelace = 0;
    for (size_t i = 0; i < star.size(); ++i) shoelace += star[i][0] * star[(i + 1) % 10][1] - star[(i + 1) % 10][0] * star[i][1];
    for (double a : s) EXPECT_GT(a, 0);
    EXPECT_NEAR(std::accumulate(s.begin(), s.end(), 0.0), shoelace, 1e-9);
    // A polygon crossing itself (a bow tie) has no ear: fanned, no hang.
    EXPECT_EQ(cutAreas({{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {1, 3, 0}, {0, 2, 0}}, t).size(), 3u);
}

// Twice the signed x-y area of a read mesh.
double readArea(const SourceMesh& m) {
    double sum = 0;
    const MeshData& g = m.piece.mesh;
    for (size_t t = 0; t < g.triangleCount(); ++t) {
        const float *p = &g.positions[3 * g.indices[3 * t]], *q = &g.positions[3 * g.indices[3 * t + 1]], *r = &g.positions[3 * g.indices[3 * t + 2]];
        sum += std::abs(double(q[0] - p[0]) * (r[1] - p[1]) - double(q[1] - p[1]) * (r[0] - p[0]));
    }
    return sum;
}

TEST(Polygon, ObjAndPlyFacesAreCutByTheirShapeInMemoryOrSpilled) {
    TempDir dir;
    std::ofstream obj(dir.file("l.obj")), ply(dir.file("l.ply"));
    // 90,000 more vertices after the L's: spilled, the L's are written out (over 1 MiB of floats)
    // before the face is read, which then reads them back from the file.
    constexpr int kMore = 90000;
    ply << "ply\nformat ascii 1.0\nelement vertex " << 6 + kMore << "\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& p : kL) obj << "v " << p[0] << " " << p[1] << " 0\n", ply << p[0] << " " << p[1] << " 0\n";
    for (int i = 0; i < kMore; ++i) obj << "v 9 9 9\n", ply << "9 9 9\n";
    obj << "f 1 2 3 4 5 6\n", ply << "6 0 1 2 3 4 5\n";
    obj.close(), ply.close();
    for (const std::string name : {"l.obj", "l.ply"}) {
        const SourceMesh m = readMesh(dir.file(name));
        EXPECT_EQ(m.piece.mesh.triangleCount(), 4u) << name;
        EXPECT_DOUBLE_EQ(readArea(m), 6.0) << name;  // 8 when fanned from the reflex corner's neighbour
        RawMesh spilled;  // the vertices on disk while the face is read: the same triangles
        std::filesystem::create_directories(dir.file("spill-" + name));
        spilled.spillTo(dir.file("spill-" + name));
        if (name == "l.obj") parseObj(dir.file(name), spilled);
        else parsePly(dir.file(name), spilled);
        const SourceMesh s = toSourceMesh(spilled, name);
        EXPECT_EQ(s.piece.mesh.indices, m.piece.mesh.indices) << name;
    }
}

}  // namespace
}  // namespace hlod::test
