// Closest-point queries on a triangle set (closest_point.cpp): a bounding volume hierarchy
// (Ericson, "Real-Time Collision Detection" 2005, §6.2 top-down construction, median split on
// the longest axis; §6.6 closest-point traversal, children nearest first; given a previous
// answer as a hint, our choice: from the hint's leaf up, each sibling subtree in turn) with
// Ericson's §5.1.5 ClosestPtPointTriangle at the leaves; and the first hit of a ray with the
// triangles facing a given direction (Möller & Trumbore 1997, "Fast, minimum storage
// ray-triangle intersection", the test Ericson §5.3.6 gives with scalar triple products; boxes
// by the slab test, Kay & Kajiya 1986, "Ray tracing complex scenes", Ericson §5.3.3, with
// Ize 2013's margin, "Robust BVH ray traversal" §3, so rounding never culls a box the ray meets). It replaced CGAL's AABB tree in the geometric
// error (error.cpp; pipeline/BUILD_SPEED.md has the measurements: the same exact distances, ~10 x
// cheaper per query on the node-sized meshes the build queries) and in the texture baker
// (bake.cpp; pipeline/TEXTURE_SPEED.md, round 3). Its memory layout: pipeline/CLOSEST_POINT.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace hlod {

struct TriangleBvh {
    // Nodes are numbered 0 (the root), 1 (unused), then children in pairs (even, even + 1), and
    // stored by pairs, one 64-byte line each: both children's boxes are read and their distances
    // computed together (SSE2 lanes), lane `node % 2` of pair `node / 2`.
    struct alignas(64) Pair {
        float lo[3][2], hi[3][2];  // per axis, per lane
        uint32_t first[2], count[2];  // count > 0: a leaf of triangles [first, first + count); else children first, first + 1
    };
    // A triangle's box and corners in one 64-byte line (the leaves' tests read both). Its corners
    // are the input's floats, so the box of the floats is exact.
    struct alignas(64) Triangle {
        float lo[3], hi[3];
        float corners[9];  // a, b, c
    };
    std::vector<Triangle> triangles;  // in leaf order
    std::vector<uint32_t> input;      // per triangle in leaf order, its index in the input (`indices` / 3)
    std::vector<Pair> pairs;      // pair 0: the root (lane 0); then the children of the nodes
    std::vector<uint32_t> parent; // per pair, its nodes' parent (pair 0's: 0)
    std::vector<uint32_t> leaf;   // per triangle in leaf order, its leaf node
    bool empty() const { return triangles.empty(); }
};

// `positions` 3 per vertex, `indices` 3 per triangle; zero-area triangles are left out.
TriangleBvh buildTriangleBvh(const std::vector<float>& positions, const std::vector<uint32_t>& indices);

// Squared distance from p to the nearest triangle; `hint` (a triangle index from a previous
// query, or any value) seeds the search and receives the nearest triangle. Infinity when empty.
// With a valid hint the search climbs from the hint's leaf, searching each sibling subtree.
// `enough2` > 0 ends the search at the first triangle found within it: the result, that triangle's
// distance, is then at most enough2 and at least the exact one (which it stays when above enough2).
// On two coinciding surfaces (a flat fan of thin triangles and its simplification) every sample
// lies a rounding error from its triangle while every box holding it lies at exactly 0, so an exact
// search visits all of them (error.cpp: 6 x fewer triangle tests on a 50,000-triangle fan).
double squaredDistance(const TriangleBvh& bvh, const double p[3], uint32_t& hint, double enough2 = 0);

// The nearest hit of the ray origin + t direction, 0 <= t < maxT, with a triangle whose normal
// (b - a) x (c - a) has a positive dot product with `facing` (edges and corners count as hits):
// returns its t and puts the triangle (leaf order) in `hit`; infinity, `hit` unchanged, when
// there is none (or the hierarchy is empty). Boxes farther along the ray than the nearest hit so
// far (at first maxT) are not visited.
double firstHit(const TriangleBvh& bvh, const double origin[3], const double direction[3], double maxT, const double facing[3],
                uint32_t& hit);

// Exact largest distance from the points to the triangles, by best-first branch
// and bound over a k-d split of the points: the distance to a surface is 1-Lipschitz, so a group
// whose centre lies at d from the surface and whose points lie within r of that centre holds no
// point farther than d + r, and is not queried point by point once d + r <= the largest distance
// found (the centre: the group's point nearest the middle of its box; a group wider than that
// distance is split without querying its centre, its own bound could not prune it). `sum`
// receives the summed distance, exact for the queried points and count x d for a pruned group
// (each term within r of the exact one). The points are reordered (the k-d split partitions them
// in place: no index array, and each group's points lie together in memory). Each point's distance
// is searched to `enough` (squaredDistance's enough2 = enough^2): the largest distance stays exact
// when above `enough` (the point that gives it never ends its search early), else it is at most
// `enough`; a queried point's term of `sum` lies within `enough` of its exact distance, a pruned
// group's within its radius r plus `enough` (an early answer can change which groups are pruned).
double largestDistance(const TriangleBvh& bvh, std::vector<std::array<double, 3>>& points, double& sum, double enough = 0);

}  // namespace hlod
