// The two-sided error's sample points on thin triangles (pipeline/error.cpp `samples`): a long
// thin triangle is sampled along its length (rows parallel to its longest edge, one point kept
// per cell of spacing / 4), not on an n x n grid of n = its length / spacing, and a hole under
// thin triangles is still measured.
#include "helpers.h"

#include <cmath>

namespace hlod::test {
namespace {

// A fan of n thin triangles around (0, 0, 0): its rim runs around the square [-100, 100]^2, n
// vertices evenly spaced along the perimeter (n a multiple of 4), as a filled hole or a cylinder's
// cap is triangulated.
MeshData squareFan(uint32_t n) {
    MeshData m;
    m.positions = {0, 0, 0};
    for (uint32_t i = 0; i < n; ++i) {
        const float t = 8.0f * i / n;  // along the perimeter, in half sides
        const int side = static_cast<int>(t / 2);
        const float s = -100 + 100 * (t - 2 * side);
        const float corners[4][2] = {{s, -100}, {100, s}, {-s, 100}, {-100, -s}};
        m.positions.insert(m.positions.end(), {corners[side][0], corners[side][1], 0});
    }
    for (uint32_t i = 0; i < n; ++i) m.indices.insert(m.indices.end(), {0, 1 + i, 1 + (i + 1) % n});
    return m;
}

// The square [-100, 100]^2 as a grid of 2 x 100 x 100 triangles, without those with a corner
// within `hole` of (50, 0).
MeshData holedGrid(double hole) {
    MeshData m;
    constexpr uint32_t n = 100;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) m.positions.insert(m.positions.end(), {-100 + 2.0f * i, -100 + 2.0f * j, 0});
    auto near = [&](uint32_t v) { return std::hypot(m.positions[3 * v] - 50.0, m.positions[3 * v + 1]) < hole; };
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            for (const std::array<uint32_t, 3> t : {std::array<uint32_t, 3>{a, b, d}, std::array<uint32_t, 3>{a, d, c}})
                if (!near(t[0]) && !near(t[1]) && !near(t[2])) m.indices.insert(m.indices.end(), t.begin(), t.end());
        }
    return m;
}

// 2,000 triangles 100-141 long and 0.4 wide at their rim, spacing 10: the grid put 75-133 points on
// each (359,184 on both sides); the rows and their cells keep the vertices, the centroids, the edge
// midpoints of the simplified side and at most one row point per 1.25 x 1.25 cell of the
// 200 x 200 square (161^2 cells) on each side.
TEST(ErrorSampling, AThinFanIsSampledAlongItsLengthNotItsSquare) {
    const MeshData fan = squareFan(2000);
    const SurfaceError e = surfaceError({SubMesh{0, fan, {}}}, fan, 200.0 / 20);
    EXPECT_LE(e.max, 1e-6 * 10);  // a surface against itself: 0 to a millionth of the spacing (error.cpp kEnough)
    const size_t vertices = fan.vertexCount(), triangles = fan.triangleCount(), cells = 161 * 161;
    EXPECT_LE(e.samples, 2 * (vertices + triangles + cells) + 3 * triangles);
    EXPECT_GT(e.samples, 2 * (vertices + triangles) + 3 * triangles);  // and the row points between them
}

// A hole of a tenth of the extent (radius 10 at (50, 0)) under the fan's thin triangles, whose
// samples there are row points and edge midpoints (their corners lie at the centre and on the
// rim): a sample lies within 0.7 of the spacing (10) of the hole's centre (half the spacing, and
// the cell of an eighth that kept it; error.cpp `samples`), so the error measured is at least
// 10 - 7 = 3, and at most what it is (~10 from the hole's centre to its jagged rim, which the
// grid's 2 x 2 cells move by up to ~2.8). Measured 9.9; the grid before stop 52 gave 5.5.
TEST(ErrorSampling, AHoleUnderThinTrianglesIsMeasured) {
    const MeshData fan = squareFan(2000), holed = holedGrid(10);
    const SurfaceError e = surfaceError({SubMesh{0, fan, {}}}, holed, 200.0 / 20);
    EXPECT_GE(e.oneSided, 3.0);
    EXPECT_LE(e.oneSided, 10.0 + 2 * std::sqrt(2.0));
    EXPECT_EQ(e.max, e.oneSided);  // the grid lies on the fan
    const SurfaceError whole = surfaceError({SubMesh{0, fan, {}}}, holedGrid(0), 200.0 / 20);
    EXPECT_LE(whole.max, 1e-6 * 10);
}

}  // namespace
}  // namespace hlod::test
