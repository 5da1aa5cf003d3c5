// Measured geometric error of a node (thesis §3.3 node attribute): the two-sided (symmetric)
// Hausdorff distance between the simplified surface and the node's original triangles
// (surfaceError). One side alone (simplified -> original, surfaceDistance: the measure before
// issue #16) cannot see a hole: the simplified surface is close to the original everywhere it
// exists, and a missing wall costs nothing. So the original is sampled too, each point queried
// against a bounding volume hierarchy of the simplified surface (closest_point.cpp; CGAL's AABB
// tree until issue #14, same distances, ~10 x the cost). Sampling: every vertex and centroid (and
// the simplified side's edge midpoints), and on a triangle longer than `spacing` a barycentric
// grid, or on a thin one rows along its longest edge, of spacing at most `spacing` (build_tree.cpp
// passes a twentieth of the node's extent: a hole of a tenth of it holds a sample at least ~a
// fortieth of the extent from its rim, ~a sixtieth under thin triangles, hence measured).
// The largest distance of each side is exact over its samples (to a millionth of the spacing,
// kEnough) but found by branch and bound (largestDistance): groups of samples whose Lipschitz
// bound is below the largest distance found are not queried one by one; their mean counts each at
// the group centre's distance (pipeline/BUILD_SPEED.md has the measured difference; thin triangles
// and coinciding surfaces: pipeline/CLOSEST_POINT.md).
#include "pipeline/closest_point.h"
#include "pipeline/pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace hlod {
namespace {

// All parts' triangles in one hierarchy (zero-area ones left out).
TriangleBvh bvhOf(const std::vector<SubMesh>& parts) {
    if (parts.size() == 1) return buildTriangleBvh(parts[0].mesh.positions, parts[0].mesh.indices);  // no copy
    std::vector<float> positions;
    std::vector<uint32_t> indices;
    for (const SubMesh& part : parts) {
        const uint32_t base = static_cast<uint32_t>(positions.size() / 3);
        positions.insert(positions.end(), part.mesh.positions.begin(), part.mesh.positions.end());
        for (uint32_t i : part.mesh.indices) indices.push_back(base + i);
    }
    return buildTriangleBvh(positions, indices);
}

double sq(double v) { return v * v; }

bool degenerate(const double a[3], const double b[3], const double c[3]) {
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return u[1] * w[2] - u[2] * w[1] == 0 && u[2] * w[0] - u[0] * w[2] == 0 && u[0] * w[1] - u[1] * w[0] == 0;
}

// A set of lattice cells of side `cell`: whether a point's cell holds a point already.
class CellSet {
public:
    explicit CellSet(double cell) : inverse_(1 / cell) {}
    bool insert(const std::array<double, 3>& p) {  // false when p's cell holds a point
        uint64_t key = 0;  // the three cell numbers' low 21 bits each: cells 2^21 apart share a key (a
                           // node's samples span ~160 cells of spacing / 8; a caller's far wider set loses points)
        for (int k = 0; k < 3; ++k) {
            const double cell = std::floor(p[k] * inverse_);  // beyond int64 (or not a number): one cell
            const int64_t number = std::fabs(cell) < 0x1p62 ? static_cast<int64_t>(cell) : 0;
            key = key << 21 | (static_cast<uint64_t>(number) & 0x1FFFFF);
        }
        return cells_.insert(key).second;
    }

private:
    double inverse_;
    std::unordered_set<uint64_t> cells_;
};

using Point = std::array<double, 3>;

// A distance below a millionth of the sample spacing counts as 0 (closest_point.h, largestDistance's
// `enough`): a node's largest error stays exact above it (the mean's terms move within their
// groups' bounds, as the branch and bound's pruning already moves them). On a
// flat fan of thin triangles, whose coinciding sides made every query visit every box holding its
// point, it cut a 50,000-triangle fan from 8.0 to 2.0 CPU-s and left every database the same bytes
// (Lucy 100k, the bunny, the banana, the sample city, the fans; measured in stop 52).
constexpr double kEnough = 1e-6;

// The n x n barycentric grid of triangle v, corners left out.
template <typename Add>
void gridPoints(const double v[3][3], int n, Add add) {
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            if (i == n || j == n || i + j == 0) continue;  // a corner
            const double a = double(i) / n, b = double(j) / n, c = 1 - a - b;
            add(Point{a * v[0][0] + b * v[1][0] + c * v[2][0], a * v[0][1] + b * v[1][1] + c * v[2][1], a * v[0][2] + b * v[1][2] + c * v[2][2]});
        }
}

// Rows parallel to the edge PQ, `rows` steps from PQ (row 0) to the opposite corner R (not
// included), row j cut into steps of at most `step` (at least one), corners left out.
template <typename Add>
void rowPoints(const double* P, const double* Q, const double* R, double length, int rows, double step, Add add) {
    for (int j = 0; j < rows; ++j) {  // row j runs from P + f (R - P) to Q + f (R - Q)
        const double f = double(j) / rows;
        const int steps = std::max(1, static_cast<int>(std::ceil((1 - f) * length / step)));
        for (int i = j == 0 ? 1 : 0; i <= (j == 0 ? steps - 1 : steps); ++i) {
            const double g = double(i) / steps;
            Point q;
            for (int k = 0; k < 3; ++k) q[k] = (1 - g) * (P[k] + f * (R[k] - P[k])) + g * (Q[k] + f * (R[k] - Q[k]));
            add(q);
        }
    }
}

// The sample points of `from`: its vertices once each and, per non-degenerate triangle, a
// barycentric grid of n x n cells other than the corners (n >= minCells; n >= 2 puts the edge
// midpoints among them), n the longest edge / spacing, plus the centroid: every point of the
// triangle within half the spacing of a sample. A thin triangle, whose rounded-up height /
// spacing is at most n / 4, takes rows along its longest edge instead (rowPoints, rows and steps
// at most half the spacing: the same half spacing, measured on thin shapes up to 100 x 0.01; the
// three edge midpoints added when minCells is 2): its points grow with its length, not with its
// length squared (the grid put 210 on a capped cylinder's 300 x 0.014 side triangle; the
// 20,000-triangle cylinder built in 76 CPU-s), and they are kept one per cell of an eighth of
// the spacing, the first made, each within 0.22 spacings of the points it stands for (a fan of
// 5,000 thin triangles around one vertex sampled the same ground 5,000 times, and each query
// visits the fan's overlapping boxes: 6.3 CPU-s). The grid stays for the other triangles: rows on
// every triangle moved Lucy 100k's measured errors by up to 25 % (sampling elsewhere within the
// spacing); pipeline/CLOSEST_POINT.md has the figures.
std::vector<Point> samples(const std::vector<const MeshData*>& from, double spacing, int minCells) {
    std::vector<Point> points;
    CellSet kept(spacing / 8);
    for (const MeshData* mesh : from) {
        const MeshData& m = *mesh;
        for (size_t i = 0; i + 2 < m.positions.size(); i += 3) points.push_back({m.positions[i], m.positions[i + 1], m.positions[i + 2]});
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            double v[3][3];
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k) v[j][k] = m.positions[3 * size_t(m.indices[3 * t + j]) + k];
            if (degenerate(v[0], v[1], v[2])) continue;
            auto d2 = [&](int a, int b) { return sq(v[a][0] - v[b][0]) + sq(v[a][1] - v[b][1]) + sq(v[a][2] - v[b][2]); };
            int p = 0;  // the longest edge runs from corner p to p + 1
            for (int e = 1; e < 3; ++e)
                if (d2(e, (e + 1) % 3) > d2(p, (p + 1) % 3)) p = e;
            const double length = std::sqrt(d2(p, (p + 1) % 3));
            const int n = std::max(minCells, static_cast<int>(std::ceil(length / spacing)));
            double u[3], w[3];
            for (int k = 0; k < 3; ++k) u[k] = v[(p + 1) % 3][k] - v[p][k], w[k] = v[(p + 2) % 3][k] - v[p][k];
            const double height = std::sqrt(sq(u[1] * w[2] - u[2] * w[1]) + sq(u[2] * w[0] - u[0] * w[2]) + sq(u[0] * w[1] - u[1] * w[0])) / length;
            const int across = static_cast<int>(std::ceil(height / spacing));
            if (4 * across <= n) {
                if (minCells >= 2)  // the edge midpoints, always
                    for (int e = 0; e < 3; ++e)
                        points.push_back({0.5 * (v[e][0] + v[(e + 1) % 3][0]), 0.5 * (v[e][1] + v[(e + 1) % 3][1]), 0.5 * (v[e][2] + v[(e + 1) % 3][2])});
                const int rows = std::max(1, static_cast<int>(std::ceil(2 * height / spacing)));
                rowPoints(v[p], v[(p + 1) % 3], v[(p + 2) % 3], length, rows, spacing / 2, [&](const Point& q) {
                    if (kept.insert(q)) points.push_back(q);
                });
            } else
                gridPoints(v, n, [&](const Point& q) { points.push_back(q); });
            points.push_back({(v[0][0] + v[1][0] + v[2][0]) / 3, (v[0][1] + v[1][1] + v[2][1]) / 3, (v[0][2] + v[1][2] + v[2][2]) / 3});
        }
    }
    return points;
}

}  // namespace

double surfaceDistance(const std::vector<SubMesh>& simplified, const std::vector<SubMesh>& original) {
    const TriangleBvh bvh = bvhOf(original);
    if (bvh.empty()) return 0;
    std::vector<std::array<double, 3>> points;  // edge midpoints and centroids
    for (const SubMesh& part : simplified) {
        const MeshData& m = part.mesh;
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            const float* v[3];
            for (int j = 0; j < 3; ++j) v[j] = &m.positions[3 * size_t(m.indices[3 * t + j])];
            for (int j = 0; j < 3; ++j) {
                std::array<double, 3>& mid = points.emplace_back();
                for (int k = 0; k < 3; ++k) mid[k] = 0.5 * (double(v[j][k]) + v[(j + 1) % 3][k]);
            }
            std::array<double, 3>& centroid = points.emplace_back();
            for (int k = 0; k < 3; ++k) centroid[k] = (double(v[0][k]) + v[1][k] + v[2][k]) / 3;
        }
    }
    double sum = 0;
    return largestDistance(bvh, points, sum);
}

// The diagonal of the meshes' bounding box: the error of a surface drawn where the other side has
// none (every triangle degenerate), or of one missing altogether.
double diagonal(const std::vector<const MeshData*>& meshes) {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const MeshData* m : meshes)
        for (uint32_t i : m->indices)
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], double(m->positions[3 * size_t(i) + k])), hi[k] = std::max(hi[k], double(m->positions[3 * size_t(i) + k]));
    return lo[0] <= hi[0] ? std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) : 0;
}

SurfaceError surfaceError(const std::vector<SubMesh>& simplified, const MeshData& original, double spacing) {
    SurfaceError e;
    if (!(spacing > 0)) return e;
    std::vector<const MeshData*> simplifiedMeshes;
    for (const SubMesh& part : simplified) simplifiedMeshes.push_back(&part.mesh);
    const TriangleBvh a = bvhOf(simplified), b = buildTriangleBvh(original.positions, original.indices);
    if (a.empty() != b.empty()) {  // one side shows nothing of area: as far off as the other side is large
        e.max = e.mean = diagonal(a.empty() ? std::vector<const MeshData*>{&original} : simplifiedMeshes);
        e.oneSided = b.empty() ? e.max : 0;
        return e;
    }
    if (a.empty()) return e;
    double sum = 0;
    // The simplified side's triangles are few and large (edge midpoints always); the original's
    // many and small, mostly sampled by their vertices and centroids alone.
    std::vector<std::array<double, 3>> fromSimplified = samples(simplifiedMeshes, spacing, 2), fromOriginal = samples({&original}, spacing, 1);
    e.samples = fromSimplified.size() + fromOriginal.size();
    const double count = double(e.samples);
    e.oneSided = largestDistance(b, fromSimplified, sum, kEnough * spacing);
    e.max = std::max(e.oneSided, largestDistance(a, fromOriginal, sum, kEnough * spacing));
    e.mean = count > 0 ? sum / count : 0;
    return e;
}

}  // namespace hlod
