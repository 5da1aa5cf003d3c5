// Closest-point queries on a triangle set (closest_point.cpp): a bounding volume hierarchy
// (Ericson, "Real-Time Collision Detection" 2005, §6.2 top-down construction, median split on
// the longest axis; §6.6 closest-point traversal, children nearest first) with Ericson's
// §5.1.5 ClosestPtPointTriangle at the leaves. It replaces CGAL's AABB tree in the geometric
// error (error.cpp; pipeline/BUILD_SPEED.md has the measurements): the same exact distances,
// ~10 x cheaper per query on the node-sized meshes the build queries.
#pragma once

#include <cstdint>
#include <vector>

namespace hlod {

struct TriangleBvh {
    struct Node {
        float lo[3], hi[3];
        uint32_t first, count;  // count > 0: a leaf of triangles [first, first + count); else children first, first + 1
    };
    std::vector<double> corners;  // 9 per triangle, in leaf order
    std::vector<float> boxes;     // 6 per triangle (low, high corner; rounded outwards), in leaf order
    std::vector<Node> nodes;
    bool empty() const { return corners.empty(); }
};

// `positions` 3 per vertex, `indices` 3 per triangle; zero-area triangles are left out.
TriangleBvh buildTriangleBvh(const std::vector<float>& positions, const std::vector<uint32_t>& indices);

// Squared distance from p to the nearest triangle; `hint` (a triangle index from a previous
// query, or any value) seeds the search and receives the nearest triangle. Infinity when empty.
double squaredDistance(const TriangleBvh& bvh, const double p[3], uint32_t& hint);

// Exact largest distance from the points (3 doubles each) to the triangles, by best-first branch
// and bound over a k-d split of the points: the distance to a surface is 1-Lipschitz, so a group
// whose centre lies at d from the surface and whose points lie within r of that centre holds no
// point farther than d + r, and is not queried point by point once d + r <= the largest distance
// found (the centre: the group's point nearest the middle of its box; a group wider than that
// distance is split without querying its centre, its own bound could not prune it). `sum`
// receives the summed distance, exact for the queried points and count x d for a pruned group
// (each term within r of the exact one).
double largestDistance(const TriangleBvh& bvh, const std::vector<double>& points, double& sum);

}  // namespace hlod
