// Measured geometric error of a node (thesis §3.3 node attribute): the two-sided (symmetric)
// Hausdorff distance between the simplified surface and the node's original triangles
// (surfaceError). One side alone (simplified -> original, surfaceDistance: the measure before
// issue #16) cannot see a hole: the simplified surface is close to the original everywhere it
// exists, and a missing wall costs nothing. So the original is sampled too, each point queried
// against a CGAL AABB tree of the simplified surface. Sampling: every vertex and centroid (and
// the simplified side's edge midpoints), and on a triangle longer than `spacing` a barycentric
// grid of spacing at most `spacing` (build_tree.cpp passes a twentieth of the node's extent: a hole of a tenth of it
// holds a sample at least ~a fortieth of the extent from its rim, hence measured).
#include "pipeline/pipeline.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>

namespace hlod {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point vertex(const MeshData& m, uint32_t i) {
    return {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]};
}

std::vector<Triangle> trianglesOf(const std::vector<SubMesh>& parts) {
    std::vector<Triangle> triangles;
    for (const SubMesh& part : parts)
        for (size_t t = 0; t < part.mesh.triangleCount(); ++t) {
            const uint32_t* i = &part.mesh.indices[3 * t];
            Triangle tri(vertex(part.mesh, i[0]), vertex(part.mesh, i[1]), vertex(part.mesh, i[2]));
            if (!tri.is_degenerate()) triangles.push_back(tri);
        }
    return triangles;
}

// Visits the sample points of `tri` other than its corners: a barycentric grid of n x n cells
// (n >= minCells; n >= 2 puts the edge midpoints among them), n the longest edge / spacing,
// plus the centroid.
template <typename Visit>
void samples(const Triangle& tri, double spacing, int minCells, Visit&& visit) {
    const double longest = std::sqrt(std::max({CGAL::squared_distance(tri[0], tri[1]), CGAL::squared_distance(tri[1], tri[2]),
                                               CGAL::squared_distance(tri[2], tri[0])}));
    const int n = std::max(minCells, static_cast<int>(std::ceil(longest / spacing)));
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            if (i == n || j == n || i + j == 0) continue;  // a corner
            const double a = double(i) / n, b = double(j) / n, c = 1 - a - b;
            visit(Point(a * tri[0].x() + b * tri[1].x() + c * tri[2].x(), a * tri[0].y() + b * tri[1].y() + c * tri[2].y(),
                        a * tri[0].z() + b * tri[1].z() + c * tri[2].z()));
        }
    visit(CGAL::centroid(tri[0], tri[1], tri[2]));
}

// Largest and summed distance from the samples of `from` (its vertices once each, and the
// triangles' samples) to the surface `to`; `count` gets the samples.
double sideDistance(const std::vector<SubMesh>& from, const std::vector<Triangle>& fromTriangles, const std::vector<Triangle>& to,
                    double spacing, int minCells, double& sum, uint64_t& count) {
    Tree tree(to.begin(), to.end());
    tree.accelerate_distance_queries();
    double worst = 0;
    auto visit = [&](const Point& p) {
        const double d = std::sqrt(tree.squared_distance(p));
        worst = std::max(worst, d), sum += d, ++count;
    };
    for (const SubMesh& part : from)
        for (uint32_t v = 0; v < part.mesh.vertexCount(); ++v) visit(vertex(part.mesh, v));
    for (const Triangle& tri : fromTriangles) samples(tri, spacing, minCells, visit);
    return worst;
}

}  // namespace

double surfaceDistance(const std::vector<SubMesh>& simplified, const std::vector<SubMesh>& original) {
    const std::vector<Triangle> triangles = trianglesOf(original);
    if (triangles.empty()) return 0;
    Tree tree(triangles.begin(), triangles.end());
    tree.accelerate_distance_queries();
    double worst = 0;
    for (const SubMesh& part : simplified) {
        const MeshData& m = part.mesh;
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            const uint32_t* i = &m.indices[3 * t];
            const Point a = vertex(m, i[0]), b = vertex(m, i[1]), c = vertex(m, i[2]);
            for (const Point& p : {CGAL::midpoint(a, b), CGAL::midpoint(b, c), CGAL::midpoint(c, a), CGAL::centroid(a, b, c)})
                worst = std::max(worst, tree.squared_distance(p));
        }
    }
    return std::sqrt(worst);
}

SurfaceError surfaceError(const std::vector<SubMesh>& simplified, const std::vector<SubMesh>& original, double spacing) {
    const std::vector<Triangle> a = trianglesOf(simplified), b = trianglesOf(original);
    SurfaceError e;
    if (a.empty() || b.empty() || !(spacing > 0)) return e;
    double sum = 0;
    uint64_t count = 0;
    // The simplified side's triangles are few and large (edge midpoints always); the original's
    // many and small, mostly sampled by their vertices and centroids alone.
    e.oneSided = sideDistance(simplified, a, b, spacing, 2, sum, count);
    e.max = std::max(e.oneSided, sideDistance(original, b, a, spacing, 1, sum, count));
    e.mean = count ? sum / double(count) : 0;
    return e;
}

}  // namespace hlod
