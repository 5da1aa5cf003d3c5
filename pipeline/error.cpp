// Measured geometric error of a node (thesis §3.3 node attribute): the one-sided
// Hausdorff distance from the simplified surface to the node's original triangles, sampled at
// edge midpoints and centroids (the vertices are original vertices: distance 0), each point
// queried against a CGAL AABB tree of the original piece.
#include "pipeline/pipeline.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

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

}  // namespace

double surfaceDistance(const std::vector<SubMesh>& simplified, const std::vector<SubMesh>& original) {
    std::vector<Triangle> triangles;
    for (const SubMesh& part : original)
        for (size_t t = 0; t < part.mesh.triangleCount(); ++t) {
            const uint32_t* i = &part.mesh.indices[3 * t];
            Triangle tri(vertex(part.mesh, i[0]), vertex(part.mesh, i[1]), vertex(part.mesh, i[2]));
            if (!tri.is_degenerate()) triangles.push_back(tri);
        }
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

}  // namespace hlod
