// Closest-point queries on a triangle set and the largest point-to-surface distance of a point
// set (closest_point.h): Ericson, "Real-Time Collision Detection" (2005), §6.2 (top-down BVH,
// median split), §6.6 (closest-point traversal) and §5.1.5 (closest point on a triangle); the
// branch and bound over points is the Lipschitz bound of the header. The ray query: Möller &
// Trumbore 1997 at the leaves, the slab test (Ericson §5.3.3) with Ize 2013's margin for boxes.
#include "pipeline/closest_point.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <limits>
#include <queue>

namespace hlod {
namespace {

constexpr uint32_t kLeafTriangles = 4;
constexpr uint32_t kLeafPoints = 8;  // a group this small is queried point by point
constexpr uint32_t kNoTriangle = ~0u;

double sq(double v) { return v * v; }

// Ericson §5.1.5 ClosestPtPointTriangle, returning the squared distance.
double triangleDistance2(const float* t, const double p[3]) {
    const double a[3] = {t[0], t[1], t[2]}, b[3] = {t[3], t[4], t[5]}, c[3] = {t[6], t[7], t[8]};
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

// Both nodes' boxDistance2 at once, one per lane (GCC's vector extensions, also clang's): the
// same operations in the same order, so the same doubles (max(max(a, 0), b) is the value of
// std::max({a, 0, b}) up to the sign of a zero, which squaring drops).
using Double2 = double __attribute__((vector_size(16)));
// Two floats as two doubles (one cvtps2pd; GCC 12 converts a two-float vector lane by lane).
Double2 widen(const float v[2]) {
#if defined(__SSE2__)
    double bits;
    std::memcpy(&bits, v, sizeof bits);
    return Double2(_mm_cvtps_pd(_mm_castpd_ps(_mm_load_sd(&bits))));
#else
    return Double2{v[0], v[1]};
#endif
}
Double2 boxDistance2(const TriangleBvh::Pair& pair, const double p[3]) {
    Double2 d = {0, 0};
    const Double2 zero = {0, 0};
    for (int k = 0; k < 3; ++k) {
        const Double2 below = widen(pair.lo[k]) - p[k], above = p[k] - widen(pair.hi[k]);
        Double2 m = below > zero ? below : zero;
        m = m > above ? m : above;
        d += m * m;
    }
    return d;
}

}  // namespace

TriangleBvh buildTriangleBvh(const std::vector<float>& positions, const std::vector<uint32_t>& indices) {
    TriangleBvh bvh;
    // Per kept triangle its centroid (x 3), its box and its index in the input, partitioned in
    // place (the same order as partitioning indices into separate arrays, without the random reads).
    struct Item {
        float centroid[3], lo[3], hi[3];
        uint32_t index;
    };
    auto corners = [&](size_t t, float f[9]) {  // the corners as given
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) f[3 * j + k] = positions[3 * size_t(indices[3 * t + j]) + k];
    };
    std::vector<Item> items;
    items.reserve(indices.size() / 3);
    for (size_t t = 0; t < indices.size() / 3; ++t) {
        float f[9];
        corners(t, f);
        const double v[9] = {f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8]};  // their area in doubles
        const double u[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]}, w[3] = {v[6] - v[0], v[7] - v[1], v[8] - v[2]};
        const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        if (n[0] == 0 && n[1] == 0 && n[2] == 0) continue;  // zero area
        Item& item = items.emplace_back();
        item.index = static_cast<uint32_t>(t);
        for (int k = 0; k < 3; ++k) {
            item.centroid[k] = float(double(f[k]) + double(f[3 + k]) + double(f[6 + k]));
            item.lo[k] = std::min({f[k], f[3 + k], f[6 + k]}), item.hi[k] = std::max({f[k], f[3 + k], f[6 + k]});
        }
    }
    const uint32_t count = static_cast<uint32_t>(items.size());
    if (count == 0) return bvh;
    struct Task { uint32_t node, lo, hi; };
    std::vector<Task> stack{{0, 0, count}};
    bvh.pairs.push_back({});  // the root, lane 0 (lane 1 unused)
    bvh.parent.push_back(0);
    bvh.leaf.resize(count);
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        TriangleBvh::Pair& pair = bvh.pairs[task.node / 2];  // not used past a push_back, which may move it
        const int lane = task.node % 2;
        float lo[3], hi[3];
        for (int k = 0; k < 3; ++k) lo[k] = std::numeric_limits<float>::max(), hi[k] = -lo[k];
        for (uint32_t i = task.lo; i < task.hi; ++i)  // the box holds its triangles
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], items[i].lo[k]), hi[k] = std::max(hi[k], items[i].hi[k]);
        for (int k = 0; k < 3; ++k) pair.lo[k][lane] = lo[k], pair.hi[k][lane] = hi[k];
        if (task.hi - task.lo <= kLeafTriangles) {
            pair.first[lane] = task.lo, pair.count[lane] = task.hi - task.lo;
            std::fill(bvh.leaf.begin() + task.lo, bvh.leaf.begin() + task.hi, task.node);
            continue;
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
        const uint32_t mid = task.lo + (task.hi - task.lo) / 2;
        std::nth_element(items.begin() + task.lo, items.begin() + mid, items.begin() + task.hi,
                         [axis](const Item& a, const Item& b) { return a.centroid[axis] < b.centroid[axis]; });
        const uint32_t left = static_cast<uint32_t>(2 * bvh.pairs.size());
        pair.first[lane] = left, pair.count[lane] = 0;
        bvh.pairs.push_back({});
        bvh.parent.push_back(task.node);
        stack.push_back({left, task.lo, mid}), stack.push_back({left + 1, mid, task.hi});
    }
    bvh.triangles.resize(count);
    bvh.input.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
        TriangleBvh::Triangle& t = bvh.triangles[i];
        std::copy_n(items[i].lo, 3, t.lo), std::copy_n(items[i].hi, 3, t.hi);
        corners(items[i].index, t.corners);
        bvh.input[i] = items[i].index;
    }
    return bvh;
}

double squaredDistance(const TriangleBvh& bvh, const double p[3], uint32_t& hint, double enough2) {
    double best = std::numeric_limits<double>::infinity();
    const size_t triangles = bvh.triangles.size();
    if (triangles == 0) return best;
    struct Entry {
        double boxD;
        uint32_t index;
    };
    Entry stack[64];  // not value-initialised (a pair's constructor zeroed 1 KB per query)
    uint32_t known = kNoTriangle;  // the hint, whose distance is already `best`
    // What a node pushed on the stack will read when popped (its children's pair, or its
    // triangles), asked for early: the reads of a query are otherwise mostly waits on memory.
    auto prefetch = [&](const TriangleBvh::Pair& pair, int lane) {
        if (pair.count[lane] > 0) __builtin_prefetch(&bvh.triangles[pair.first[lane]]);
        else __builtin_prefetch(&bvh.pairs[pair.first[lane] / 2]);
    };
    auto search = [&](uint32_t from, double fromD) {  // the subtree of node `from`, nearer children first
        int top = 0;
        stack[top++] = {fromD, from};
        while (top > 0 && best > enough2) {
            const auto [boxD, index] = stack[--top];
            if (boxD >= best) continue;
            const TriangleBvh::Pair& pair = bvh.pairs[index / 2];
            const uint32_t first = pair.first[index % 2], count = pair.count[index % 2];
            if (count > 0) {
                for (uint32_t t = first; t < first + count; ++t) {
                    const TriangleBvh::Triangle& triangle = bvh.triangles[t];
                    if (t == known || boxDistance2(triangle.lo, triangle.hi, p) >= best) continue;  // its box first: ~3 x cheaper
                    if (const double d = triangleDistance2(triangle.corners, p); d < best) best = d, hint = t;
                }
                continue;
            }
            const TriangleBvh::Pair& children = bvh.pairs[first / 2];
            const Double2 d = boxDistance2(children, p);
            const bool leftFirst = d[0] <= d[1];  // the nearer child on top of the stack
            for (const int lane : {leftFirst ? 1 : 0, leftFirst ? 0 : 1})
                if (d[lane] < best) {
                    stack[top++] = {d[lane], first + lane};
                    prefetch(children, lane);
                }
        }
    };
    if (hint >= triangles) {
        search(0, boxDistance2(bvh.pairs[0], p)[0]);
        return best;
    }
    // From the hint's leaf up to the root, each sibling's subtree: every triangle not in the hint's
    // leaf lies in exactly one of them, and the siblings nearest in the tree, searched first, are
    // the ones likely near p (half the box tests of a descent from the root, whose every level
    // tests both children).
    best = triangleDistance2(bvh.triangles[hint].corners, p), known = hint;
    uint32_t node = bvh.leaf[hint];
    search(node, 0);
    for (; node != 0 && best > enough2; node = bvh.parent[node / 2]) {
        const uint32_t sibling = node ^ 1;  // children are pairs (even, even + 1)
        if (const double d = boxDistance2(bvh.pairs[node / 2], p)[sibling % 2]; d < best) search(sibling, d);
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
    auto enter = [&](uint32_t node) {
        const TriangleBvh::Pair& pair = bvh.pairs[node / 2];
        const float lo[3] = {pair.lo[0][node % 2], pair.lo[1][node % 2], pair.lo[2][node % 2]};
        const float hi[3] = {pair.hi[0][node % 2], pair.hi[1][node % 2], pair.hi[2][node % 2]};
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
    if (const double t = enter(0); t < best) stack[top++] = {t, 0};
    while (top > 0) {
        const auto [t, index] = stack[--top];
        if (t >= best) continue;
        const uint32_t first = bvh.pairs[index / 2].first[index % 2], count = bvh.pairs[index / 2].count[index % 2];
        if (count > 0) {
            for (uint32_t i = first; i < first + count; ++i) {
                const float* a = bvh.triangles[i].corners;
                double e1[3], e2[3], normal[3];
                for (int k = 0; k < 3; ++k) e1[k] = double(a[3 + k]) - a[k], e2[k] = double(a[6 + k]) - a[k];
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
        const double tl = enter(first), tr = enter(first + 1);
        const bool leftFirst = tl <= tr;  // the nearer child on top of the stack
        if ((leftFirst ? tr : tl) < best) stack[top++] = {leftFirst ? tr : tl, leftFirst ? first + 1 : first};
        if ((leftFirst ? tl : tr) < best) stack[top++] = {leftFirst ? tl : tr, leftFirst ? first : first + 1};
    }
    return found ? best : std::numeric_limits<double>::infinity();
}

double largestDistance(const TriangleBvh& bvh, std::vector<std::array<double, 3>>& points, double& sum, double enough) {
    const uint32_t n = static_cast<uint32_t>(points.size());
    if (n == 0 || bvh.empty()) return 0;
    uint32_t hint = 0;
    double worst = 0;
    auto distance = [&](const std::array<double, 3>& p) { return std::sqrt(squaredDistance(bvh, p.data(), hint, enough * enough)); };
    struct Group {
        double bound, d, r;  // d < 0: the representative not queried yet (bound: the parent's)
        uint32_t rep;        // in `points`, whose range [lo, hi) is reordered only when the group is split
        uint32_t lo, hi;
        int axis;
        bool operator<(const Group& o) const { return bound < o.bound; }
    };
    std::priority_queue<Group> queue;
    auto add = [&](uint32_t lo, uint32_t hi, double parentBound) {
        if (hi - lo <= kLeafPoints) {
            for (uint32_t i = lo; i < hi; ++i) {
                const double d = distance(points[i]);
                worst = std::max(worst, d), sum += d;
            }
            return;
        }
        double lo3[3], hi3[3];
        for (int k = 0; k < 3; ++k) lo3[k] = std::numeric_limits<double>::max(), hi3[k] = -lo3[k];
        for (uint32_t i = lo; i < hi; ++i)
            for (int k = 0; k < 3; ++k) lo3[k] = std::min(lo3[k], points[i][k]), hi3[k] = std::max(hi3[k], points[i][k]);
        // The group's representative: its point nearest the centre of its box, within r of all.
        const double c[3] = {0.5 * (lo3[0] + hi3[0]), 0.5 * (lo3[1] + hi3[1]), 0.5 * (lo3[2] + hi3[2])};
        uint32_t rep = lo;
        double repOff = std::numeric_limits<double>::infinity();
        for (uint32_t i = lo; i < hi; ++i) {
            const std::array<double, 3>& q = points[i];
            if (const double off = sq(q[0] - c[0]) + sq(q[1] - c[1]) + sq(q[2] - c[2]); off < repOff) repOff = off, rep = i;
        }
        const double r = std::sqrt(repOff) + 0.5 * std::sqrt(sq(hi3[0] - lo3[0]) + sq(hi3[1] - lo3[1]) + sq(hi3[2] - lo3[2]));
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (hi3[k] - lo3[k] > hi3[axis] - lo3[axis]) axis = k;
        // A group wider than the largest distance found cannot be pruned by its own bound (d + r
        // > r >= worst): its representative is queried only if that changes (fine levels, whose
        // distances are below the sample spacing, skip most of these queries).
        if (r >= worst) return queue.push({parentBound, -1, r, rep, lo, hi, axis});
        const double d = distance(points[rep]);
        worst = std::max(worst, d);
        queue.push({std::min(parentBound, d + r), d, r, rep, lo, hi, axis});
    };
    add(0, n, std::numeric_limits<double>::infinity());
    while (!queue.empty()) {
        Group g = queue.top();
        queue.pop();
        if (g.bound <= worst || (g.d < 0 && g.r < worst)) {
            if (g.d < 0) {
                g.d = distance(points[g.rep]);
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
        const int axis = g.axis;
        std::nth_element(points.begin() + g.lo, points.begin() + mid, points.begin() + g.hi,
                         [axis](const std::array<double, 3>& a, const std::array<double, 3>& b) { return a[axis] < b[axis]; });
        add(g.lo, mid, g.bound), add(mid, g.hi, g.bound);
    }
    return worst;
}

}  // namespace hlod
