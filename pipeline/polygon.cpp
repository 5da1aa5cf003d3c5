// Polygons cut into triangles: ear clipping (Meisters 1975, "Polygons have ears": every simple
// polygon of four or more corners has two ears, corners whose triangle with its neighbours lies
// inside the polygon; cutting one off leaves a simple polygon), in the plane that drops the largest
// component of the polygon's Newell normal (Newell's method, Sutherland, Sproull & Schumacker 1974),
// the way O'Rourke's "Computational Geometry in C" (1998, §1.6) presents it. A convex polygon keeps
// the fan (0, k - 1, k), so databases of convex polygons keep their bytes; a polygon that crosses
// itself has no ear at some step and its remaining corners are fanned.
#include "pipeline/polygon.h"

#include <cmath>

namespace hlod {

namespace {

struct Point {
    double x, y;
};

// Twice the signed area of (a, b, c), positive counter-clockwise.
double cross(const Point& a, const Point& b, const Point& c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

void fan(std::span<const uint32_t> corners, std::vector<std::array<uint32_t, 3>>& triangles) {
    for (size_t k = 2; k < corners.size(); ++k) triangles.push_back({corners[0], corners[k - 1], corners[k]});
}

// p inside or on the triangle (a, b, c), which is counter-clockwise.
bool inside(const Point& p, const Point& a, const Point& b, const Point& c) {
    return cross(a, b, p) >= 0 && cross(b, c, p) >= 0 && cross(c, a, p) >= 0;
}

}  // namespace

void triangulatePolygon(std::span<const std::array<double, 3>> corners, std::vector<std::array<uint32_t, 3>>& triangles) {
    const size_t n = corners.size();
    std::vector<uint32_t> left(n);
    for (size_t i = 0; i < n; ++i) left[i] = static_cast<uint32_t>(i);
    if (n < 4 || n > kMaxEarClippedCorners) return fan(left, triangles);
    double normal[3] = {0, 0, 0};  // Newell
    for (size_t i = 0; i < n; ++i) {
        const std::array<double, 3>&a = corners[i], &b = corners[(i + 1) % n];
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]), normal[1] += (a[2] - b[2]) * (a[0] + b[0]), normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    int drop = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(normal[k]) > std::abs(normal[drop])) drop = k;
    if (normal[drop] == 0) return fan(left, triangles);
    // The two kept axes in the order that makes the polygon counter-clockwise.
    const int u = (drop + 1) % 3, v = (drop + 2) % 3;
    const bool flip = normal[drop] < 0;
    std::vector<Point> p(n);
    for (size_t i = 0; i < n; ++i) p[i] = flip ? Point{corners[i][v], corners[i][u]} : Point{corners[i][u], corners[i][v]};
    bool convex = true;
    for (size_t i = 0; i < n && convex; ++i) convex = cross(p[(i + n - 1) % n], p[i], p[(i + 1) % n]) >= 0;
    if (convex) return fan(left, triangles);
    while (left.size() > 3) {
        const size_t m = left.size();
        size_t ear = m;
        for (size_t i = 0; i < m && ear == m; ++i) {
            const Point &a = p[left[(i + m - 1) % m]], &b = p[left[i]], &c = p[left[(i + 1) % m]];
            if (cross(a, b, c) <= 0) continue;  // reflex or flat: no ear
            bool empty = true;
            for (size_t j = 0; j < m && empty; ++j)
                if (j != i && j != (i + m - 1) % m && j != (i + 1) % m) empty = !inside(p[left[j]], a, b, c);
            if (empty) ear = i;
        }
        if (ear == m) return fan(left, triangles);  // crosses itself: no ear left
        triangles.push_back({left[(ear + m - 1) % m], left[ear], left[(ear + 1) % m]});
        left.erase(left.begin() + static_cast<std::ptrdiff_t>(ear));
    }
    triangles.push_back({left[0], left[1], left[2]});
}

}  // namespace hlod
