// Closest-point queries on a triangle set and the largest point-to-surface distance of a point
// set (closest_point.h): Ericson, "Real-Time Collision Detection" (2005), §6.2 (top-down BVH,
// median split), §6.6 (closest-point traversal) and §5.1.5 (closest point on a triangle); the
// branch and bound over points is the Lipschitz bound of the header. The ray query: Möller &
// Trumbore 1997 at the leaves, the slab test (Ericson §5.3.3) with Ize 2013's margin for boxes.
#include "pipeline/closest_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

namespace hlod {
namespace {

constexpr uint32_t kLeafTriangles = 4;
constexpr uint32_t kLeafPoints = 8;  // a group this small is queried point by point
constexpr uint32_t kNoTriangle = ~0u;

double sq(double v) { return v * v; }

// Ericson §5.1.5 ClosestPtPointTriangle, returning the squared distance.
double triangleDistance2(const double* t, const double p[3]) {
    const double* a = t;
    const double* b = t + 3;
    const double* c = t + 6;
    double ab[3], ac[3], ap[3];
    for (int k = 0; k < 3; ++k) ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
    auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
    auto at = [&](double v, double w) {  // squared distance to a + v ab + w ac
        double d = 0;
        for (int k = 0; k < 3; ++k) d += sq(a[k] + v * ab[k] + w * ac[k] - p[k]);
        return d;
    };
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return at(0, 0);
    double bp[3];
    for (int k = 0; k < 3; ++k) bp[k] = p[k] - b[k];
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return at(1, 0);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(d1 / (d1 - d3), 0);
    double cp[3];
    for (int k = 0; k < 3; ++k) cp[k] = p[k] - c[k];
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return at(0, 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(0, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return at(1 - w, w);
    }
    const double denom = 1 / (va + vb + vc);
    return at(vb * denom, vc * denom);
}

double boxDistance2(const float lo[3], const float hi[3], const double p[3]) {
    double d = 0;
    for (int k = 0; k < 3; ++k) d += sq(std::max({double(lo[k]) - p[k], 0.0, p[k] - double(hi[k])}));
    return d;
}
double boxDistance2(const TriangleBvh::Node& n, const double p[3]) { return boxDistance2(n.lo, n.hi, p); }

}  // namespace

TriangleBvh buildTriangleBvh(const std::vector<float>& positions, const std::vector<uint32_t>& indices) {
    TriangleBvh bvh;
    std::vector<double> corners;
    corners.reserve(3 * indices.size());  // 9 per triangle: growing by doubling could hold twice that
    std::vector<uint32_t> input;          // per kept triangle, its index in the input
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        double v[9];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) v[3 * j + k] = positions[3 * size_t(indices[t + j]) + k];
        const double u[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]}, w[3] = {v[6] - v[0], v[7] - v[1], v[8] - v[2]};
        const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        if (n[0] == 0 && n[1] == 0 && n[2] == 0) continue;  // zero area
        corners.insert(corners.end(), v, v + 9);
        input.push_back(static_cast<uint32_t>(t / 3));
    }
    const uint32_t count = static_cast<uint32_t>(corners.size() / 9);
    if (count == 0) return bvh;
    // Per triangle its centroid (x 3), its box rounded outwards to float (the box of a node is the
    // union of its triangles': the same floats as rounding the node's double bounds outwards, since
    // rounding down is monotone) and its index, partitioned in place (the same order as
    // partitioning indices into separate arrays, without the random reads).
    struct Item {
        float centroid[3], lo[3], hi[3];
        uint32_t index;
    };
    std::vector<Item> items(count);
    for (uint32_t t = 0; t < count; ++t) {
        Item& item = items[t];
        item.index = t;
        for (int k = 0; k < 3; ++k) {
            const double* v = &corners[9 * size_t(t) + k];
            item.centroid[k] = float(v[0] + v[3] + v[6]);
            const double lo = std::min({v[0], v[3], v[6]}), hi = std::max({v[0], v[3], v[6]});
            item.lo[k] = float(lo), item.hi[k] = float(hi);
            if (item.lo[k] > lo) item.lo[k] = std::nextafter(item.lo[k], -std::numeric_limits<float>::max());
            if (item.hi[k] < hi) item.hi[k] = std::nextafter(item.hi[k], std::numeric_limits<float>::max());
        }
    }
    struct Task { uint32_t node, lo, hi; };
    std::vector<Task> stack{{0, 0, count}};
    bvh.nodes.push_back({});
    bvh.parent.push_back(0);
    bvh.leaf.resize(count);
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        TriangleBvh::Node& node = bvh.nodes[task.node];
        for (int k = 0; k < 3; ++k) node.lo[k] = std::numeric_limits<float>::max(), node.hi[k] = -node.lo[k];
        for (uint32_t i = task.lo; i < task.hi; ++i)  // the box holds its triangles
            for (int k = 0; k < 3; ++k) node.lo[k] = std::min(node.lo[k], items[i].lo[k]), node.hi[k] = std::max(node.hi[k], items[i].hi[k]);
        if (task.hi - task.lo <= kLeafTriangles) {
            node.first = task.lo, node.count = task.hi - task.lo;
            std::fill(bvh.leaf.begin() + task.lo, bvh.leaf.begin() + task.hi, task.node);
            continue;
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (node.hi[k] - node.lo[k] > node.hi[axis] - node.lo[axis]) axis = k;
        const uint32_t mid = task.lo + (task.hi - task.lo) / 2;
        std::nth_element(items.begin() + task.lo, items.begin() + mid, items.begin() + task.hi,
                         [axis](const Item& a, const Item& b) { return a.centroid[axis] < b.centroid[axis]; });
        const uint32_t left = static_cast<uint32_t>(bvh.nodes.size());
        node.first = left, node.count = 0;  // `node` is not used past here: push_back may move it
        bvh.nodes.push_back({}), bvh.nodes.push_back({});
        bvh.parent.push_back(task.node), bvh.parent.push_back(task.node);
        stack.push_back({left, task.lo, mid}), stack.push_back({left + 1, mid, task.hi});
    }
    bvh.corners.resize(corners.size());
    for (uint32_t i = 0; i < count; ++i) std::copy_n(corners.begin() + 9 * size_t(items[i].index), 9, bvh.corners.begin() + 9 * size_t(i));
    std::vector<double>().swap(corners);  // freed before the boxes: one triangle array less at the peak
    bvh.input.resize(count);
    for (uint32_t i = 0; i < count; ++i) bvh.input[i] = input[items[i].index];
    bvh.boxes.resize(6 * size_t(count));
    for (uint32_t i = 0; i < count; ++i)
        std::copy_n(items[i].lo, 3, bvh.boxes.begin() + 6 * size_t(i)), std::copy_n(items[i].hi, 3, bvh.boxes.begin() + 6 * size_t(i) + 3);
    return bvh;
}

double squaredDistance(const TriangleBvh& bvh, const double p[3], uint32_t& hint) {
    double best = std::numeric_limits<double>::infinity();
    const size_t triangles = bvh.corners.size() / 9;
    if (triangles == 0) return best;
    struct Entry {
        double boxD;
        uint32_t index;
    };
    Entry stack[64];  // not value-initialised (a pair's constructor zeroed 1 KB per query)
    uint32_t known = kNoTriangle;  // the hint, whose distance is already `best`
    auto search = [&](uint32_t from, double fromD) {  // the subtree of node `from`, nearer children first
        int top = 0;
        stack[top++] = {fromD, from};
        while (top > 0) {
            const auto [boxD, index] = stack[--top];
            if (boxD >= best) continue;
            const TriangleBvh::Node& n = bvh.nodes[index];
            if (n.count > 0) {
                for (uint32_t t = n.first; t < n.first + n.count; ++t) {
                    const float* box = &bvh.boxes[6 * size_t(t)];
                    if (t == known || boxDistance2(box, box + 3, p) >= best) continue;  // its box first: ~3 x cheaper
                    if (const double d = triangleDistance2(&bvh.corners[9 * size_t(t)], p); d < best) best = d, hint = t;
                }
                continue;
            }
            const double dl = boxDistance2(bvh.nodes[n.first], p), dr = boxDistance2(bvh.nodes[n.first + 1], p);
            const bool leftFirst = dl <= dr;  // the nearer child on top of the stack
            if ((leftFirst ? dr : dl) < best) stack[top++] = {leftFirst ? dr : dl, leftFirst ? n.first + 1 : n.first};
            if ((leftFirst ? dl : dr) < best) stack[top++] = {leftFirst ? dl : dr, leftFirst ? n.first : n.first + 1};
        }
    };
    if (hint >= triangles) {
        search(0, boxDistance2(bvh.nodes[0], p));
        return best;
    }
    // From the hint's leaf up to the root, each sibling's subtree: every triangle not in the hint's
    // leaf lies in exactly one of them, and the siblings nearest in the tree, searched first, are
    // the ones likely near p (half the box tests of a descent from the root, whose every level
    // tests both children).
    best = triangleDistance2(&bvh.corners[9 * size_t(hint)], p), known = hint;
    uint32_t node = bvh.leaf[hint];
    search(node, 0);
    for (; node != 0; node = bvh.parent[node]) {
        const uint32_t sibling = node % 2 ? node + 1 : node - 1;  // children are pairs (odd, odd + 1)
        if (const double d = boxDistance2(bvh.nodes[sibling], p); d < best) search(sibling, d);
    }
    return best;
}

double firstHit(const TriangleBvh& bvh, const double origin[3], const double direction[3], double maxT, const double facing[3],
                uint32_t& hit) {
    double best = maxT;  // only hits nearer than this count
    bool found = false;
    if (bvh.empty()) return std::numeric_limits<double>::infinity();
    // Where the ray enters the box, or infinity when it misses it within [0, best]: the slab test
    // (Kay & Kajiya 1986; Ericson §5.3.3), the exit scaled by 1 + 2 gamma_3 (Ize 2013, §3) so that
    // rounding cannot make a box the ray meets look missed. An axis the ray is parallel to
    // bounds nothing, the origin must lie in its slab.
    constexpr double kExitMargin = 1 + 4 * std::numeric_limits<double>::epsilon();
    auto enter = [&](const float lo[3], const float hi[3]) {
        double tEnter = 0, tExit = best;
        for (int k = 0; k < 3; ++k) {
            if (direction[k] == 0) {
                if (origin[k] < lo[k] || origin[k] > hi[k]) return std::numeric_limits<double>::infinity();
                continue;
            }
            const double inverse = 1 / direction[k];
            double t0 = (lo[k] - origin[k]) * inverse, t1 = (hi[k] - origin[k]) * inverse;
            if (t0 > t1) std::swap(t0, t1);
            tEnter = std::max(tEnter, t0), tExit = std::min(tExit, t1 * kExitMargin);
        }
        return tEnter <= tExit ? tEnter : std::numeric_limits<double>::infinity();
    };
    auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
    auto cross = [](const double* u, const double* v, double* out) {
        out[0] = u[1] * v[2] - u[2] * v[1], out[1] = u[2] * v[0] - u[0] * v[2], out[2] = u[0] * v[1] - u[1] * v[0];
    };
    struct Entry {
        double t;
        uint32_t index;
    };
    Entry stack[64];
    int top = 0;
    if (const double t = enter(bvh.nodes[0].lo, bvh.nodes[0].hi); t < best) stack[top++] = {t, 0};
    while (top > 0) {
        const auto [t, index] = stack[--top];
        if (t >= best) continue;
        const TriangleBvh::Node& n = bvh.nodes[index];
        if (n.count > 0) {
            for (uint32_t i = n.first; i < n.first + n.count; ++i) {
                const double* a = &bvh.corners[9 * size_t(i)];
                double e1[3], e2[3], normal[3];
                for (int k = 0; k < 3; ++k) e1[k] = a[3 + k] - a[k], e2[k] = a[6 + k] - a[k];
                cross(e1, e2, normal);
                if (dot(normal, facing) <= 0) continue;
                // Möller & Trumbore 1997: barycentric u, v and the distance t by Cramer's rule.
                double pv[3], tv[3], qv[3];
                cross(direction, e2, pv);
                const double det = dot(e1, pv);
                if (det == 0) continue;  // the ray is parallel to the triangle's plane
                const double inverse = 1 / det;
                for (int k = 0; k < 3; ++k) tv[k] = origin[k] - a[k];
                const double u = dot(tv, pv) * inverse;
                if (u < 0 || u > 1) continue;
                cross(tv, e1, qv);
                const double v = dot(direction, qv) * inverse;
                if (v < 0 || u + v > 1) continue;
                if (const double th = dot(e2, qv) * inverse; th >= 0 && th < best) best = th, hit = i, found = true;
            }
            continue;
        }
        const double tl = enter(bvh.nodes[n.first].lo, bvh.nodes[n.first].hi), tr = enter(bvh.nodes[n.first + 1].lo, bvh.nodes[n.first + 1].hi);
        const bool leftFirst = tl <= tr;  // the nearer child on top of the stack
        if ((leftFirst ? tr : tl) < best) stack[top++] = {leftFirst ? tr : tl, leftFirst ? n.first + 1 : n.first};
        if ((leftFirst ? tl : tr) < best) stack[top++] = {leftFirst ? tl : tr, leftFirst ? n.first : n.first + 1};
    }
    return found ? best : std::numeric_limits<double>::infinity();
}

double largestDistance(const TriangleBvh& bvh, const std::vector<double>& points, double& sum) {
    const uint32_t n = static_cast<uint32_t>(points.size() / 3);
    if (n == 0 || bvh.empty()) return 0;
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    uint32_t hint = 0;
    double worst = 0;
    auto distance = [&](const double p[3]) { return std::sqrt(squaredDistance(bvh, p, hint)); };
    struct Group {
        double bound, d, r;  // d < 0: the representative not queried yet (bound: the parent's)
        const double* rep;
        uint32_t lo, hi;
        int axis;
        bool operator<(const Group& o) const { return bound < o.bound; }
    };
    std::priority_queue<Group> queue;
    auto add = [&](uint32_t lo, uint32_t hi, double parentBound) {
        if (hi - lo <= kLeafPoints) {
            for (uint32_t i = lo; i < hi; ++i) {
                const double d = distance(&points[3 * size_t(order[i])]);
                worst = std::max(worst, d), sum += d;
            }
            return;
        }
        double lo3[3], hi3[3];
        for (int k = 0; k < 3; ++k) lo3[k] = std::numeric_limits<double>::max(), hi3[k] = -lo3[k];
        for (uint32_t i = lo; i < hi; ++i)
            for (int k = 0; k < 3; ++k) {
                const double x = points[3 * size_t(order[i]) + k];
                lo3[k] = std::min(lo3[k], x), hi3[k] = std::max(hi3[k], x);
            }
        // The group's representative: its point nearest the centre of its box, within r of all.
        const double c[3] = {0.5 * (lo3[0] + hi3[0]), 0.5 * (lo3[1] + hi3[1]), 0.5 * (lo3[2] + hi3[2])};
        const double* rep = nullptr;
        double repOff = std::numeric_limits<double>::infinity();
        for (uint32_t i = lo; i < hi; ++i) {
            const double* q = &points[3 * size_t(order[i])];
            if (const double off = sq(q[0] - c[0]) + sq(q[1] - c[1]) + sq(q[2] - c[2]); off < repOff) repOff = off, rep = q;
        }
        const double r = std::sqrt(repOff) + 0.5 * std::sqrt(sq(hi3[0] - lo3[0]) + sq(hi3[1] - lo3[1]) + sq(hi3[2] - lo3[2]));
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (hi3[k] - lo3[k] > hi3[axis] - lo3[axis]) axis = k;
        // A group wider than the largest distance found cannot be pruned by its own bound (d + r
        // > r >= worst): its representative is queried only if that changes (fine levels, whose
        // distances are below the sample spacing, skip most of these queries).
        if (r >= worst) return queue.push({parentBound, -1, r, rep, lo, hi, axis});
        const double d = distance(rep);
        worst = std::max(worst, d);
        queue.push({std::min(parentBound, d + r), d, r, rep, lo, hi, axis});
    };
    add(0, n, std::numeric_limits<double>::infinity());
    while (!queue.empty()) {
        Group g = queue.top();
        queue.pop();
        if (g.bound <= worst || (g.d < 0 && g.r < worst)) {
            if (g.d < 0) {
                g.d = distance(g.rep);
                worst = std::max(worst, g.d);
                g.bound = std::min(g.bound, g.d + g.r);
            }
            if (g.bound <= worst) {  // no point of this or any later group is farther than `worst`
                sum += g.d * (g.hi - g.lo);
                continue;
            }
            queue.push(g);  // queried, and its own bound is still above `worst`
            continue;
        }
        const uint32_t mid = g.lo + (g.hi - g.lo) / 2;
        std::nth_element(order.begin() + g.lo, order.begin() + mid, order.begin() + g.hi,
                         [&](uint32_t a, uint32_t b) { return points[3 * size_t(a) + g.axis] < points[3 * size_t(b) + g.axis]; });
        add(g.lo, mid, g.bound), add(mid, g.hi, g.bound);
    }
    return worst;
}

}  // namespace hlod
