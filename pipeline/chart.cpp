// Charts of a simplified node for texture baking (bake.cpp), after Sander, Snyder, Gortler &
// Hoppe 2001, "Texture mapping progressive meshes" (charts grown over the mesh's faces, each
// flattened and packed into one atlas). Region growing: the largest unassigned face seeds a chart
// and breadth-first growth over edge-adjacent faces (edges shared by position, so the source's UV
// seams do not cut charts) accepts every face whose normal lies within kChartConeDegrees of the
// seed's normal. The chart is then projected orthographically on the seed's normal: every face
// keeps its orientation (normal . axis >= cos(cone) > 0) and its texel density is stretched by
// at most 1 / cos(cone) across the tilt, never compressed to zero. An orthographic projection is
// used instead of CGAL's LSCM (Lévy et al. 2002) because it is exact, needs no disk topology
// (scan pieces have holes and several borders) and costs microseconds per chart; the one failure
// it has, a chart folding over itself (a spiral ramp, a curled leaf), is detected exactly
// (separating axes on every pair of triangles whose boxes meet) and that chart is grown again
// with half the cone, down to single triangles, which never overlap. Each chart is turned to its
// minimum-area bounding rectangle, which packing uses.
#include "pipeline/chart.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace hlod {
namespace {

using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec cross(const Vec& a, const Vec& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

constexpr double kMinConeDegrees = 3;  // below: single-triangle charts

struct Faces {
    std::vector<Vec> normal;        // unit, or zero for a degenerate face
    std::vector<double> area;
    std::vector<uint32_t> start, adjacent;  // CSR: faces sharing an edge (by position)
};

Vec position(const MeshData& m, uint32_t v) { return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]}; }

Faces faceGraph(const MeshData& mesh) {
    const size_t nt = mesh.triangleCount(), nv = mesh.vertexCount();
    // Vertices welded by exact position.
    std::vector<uint32_t> order(nv), weld(nv);
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&](uint32_t a, uint32_t b) {
        return std::lexicographical_compare(&mesh.positions[3 * a], &mesh.positions[3 * a + 3], &mesh.positions[3 * b],
                                            &mesh.positions[3 * b + 3]);
    };
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return less(a, b) || (!less(b, a) && a < b); });
    for (size_t i = 0, id = 0; i < nv; ++i) {
        if (i > 0 && less(order[i - 1], order[i])) ++id;
        weld[order[i]] = static_cast<uint32_t>(id);
    }
    Faces f;
    f.normal.resize(nt), f.area.resize(nt);
    std::vector<std::pair<uint64_t, uint32_t>> edges;
    edges.reserve(3 * nt);
    for (uint32_t t = 0; t < nt; ++t) {
        const uint32_t* i = &mesh.indices[3 * t];
        const Vec n = cross(sub(position(mesh, i[1]), position(mesh, i[0])), sub(position(mesh, i[2]), position(mesh, i[0])));
        const double len = std::sqrt(dot(n, n));
        f.area[t] = 0.5 * len;
        f.normal[t] = len > 0 ? Vec{n[0] / len, n[1] / len, n[2] / len} : Vec{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = weld[i[k]], b = weld[i[(k + 1) % 3]];
            if (a != b) edges.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), t});
        }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<uint32_t, uint32_t>> pairs;  // (face, neighbour), both ways
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].first == edges[i].first) ++j;
        for (size_t a = i; a < j; ++a)
            for (size_t b = i; b < j; ++b)
                if (edges[a].second != edges[b].second) pairs.push_back({edges[a].second, edges[b].second});
        i = j;
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    f.start.assign(nt + 1, 0);
    for (const auto& p : pairs) ++f.start[p.first + 1];
    for (size_t t = 0; t < nt; ++t) f.start[t + 1] += f.start[t];
    f.adjacent.resize(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) f.adjacent[i] = pairs[i].second;  // pairs are sorted by face
    return f;
}

// (cos, sin) of the direction of the minimum-area rectangle around the points (x, y pairs): one of
// its sides lies on an edge of their convex hull (Freeman & Shapira 1975), so every hull edge
// (Andrew's monotone chain) is tried.
std::pair<double, double> tightestDirection(const std::vector<double>& xy) {
    std::vector<std::pair<double, double>> p(xy.size() / 2), hull(xy.size() + 2);
    for (size_t i = 0; i < p.size(); ++i) p[i] = {xy[2 * i], xy[2 * i + 1]};
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() < 3) return {1, 0};
    auto turn = [](const auto& o, const auto& a, const auto& b) {
        return (a.first - o.first) * (b.second - o.second) - (a.second - o.second) * (b.first - o.first);
    };
    size_t k = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && turn(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
        hull[k++] = p[i];
    }
    for (size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && turn(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
        hull[k++] = p[i];
    }
    hull.resize(k - 1);
    std::pair<double, double> best{1, 0};
    double bestArea = 1e300;
    for (size_t e = 0; e < hull.size(); ++e) {
        const auto& a = hull[e];
        const auto& b = hull[(e + 1) % hull.size()];
        const double len = std::hypot(b.first - a.first, b.second - a.second);
        if (len == 0) continue;
        const double c = (b.first - a.first) / len, s = (b.second - a.second) / len;
        double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
        for (const auto& q : hull) {
            const double x = c * q.first + s * q.second, y = -s * q.first + c * q.second;
            lo[0] = std::min(lo[0], x), hi[0] = std::max(hi[0], x), lo[1] = std::min(lo[1], y), hi[1] = std::max(hi[1], y);
        }
        const double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
        if (area < bestArea * (1 - 1e-9)) bestArea = area, best = {c, s};
    }
    return best;
}

// Projects the chart's faces on `axis`, turns it to its minimum-area rectangle, puts the box at
// the origin.
FlatChart project(const MeshData& mesh, std::vector<uint32_t> triangles, const Vec& axis) {
    const int k = std::fabs(axis[0]) <= std::fabs(axis[1]) && std::fabs(axis[0]) <= std::fabs(axis[2]) ? 0
                  : std::fabs(axis[1]) <= std::fabs(axis[2])                                           ? 1
                                                                                                       : 2;
    Vec helper{0, 0, 0};
    helper[k] = 1;
    Vec t = cross(helper, axis);  // (t, b, axis) right-handed: faces facing the axis stay counter-clockwise
    const double tl = std::sqrt(dot(t, t));
    t = {t[0] / tl, t[1] / tl, t[2] / tl};
    const Vec b = cross(axis, t);
    FlatChart chart;
    chart.triangles = std::move(triangles);
    chart.uv.reserve(6 * chart.triangles.size());
    for (uint32_t tri : chart.triangles)
        for (int c = 0; c < 3; ++c) {
            const Vec p = position(mesh, mesh.indices[3 * tri + c]);
            chart.uv.push_back(dot(p, t)), chart.uv.push_back(dot(p, b));
        }
    const size_t corners = chart.uv.size() / 2;
    const auto [c, s] = tightestDirection(chart.uv);
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (size_t i = 0; i < corners; ++i) {
        const double x = chart.uv[2 * i], y = chart.uv[2 * i + 1];
        chart.uv[2 * i] = c * x + s * y, chart.uv[2 * i + 1] = -s * x + c * y;  // rotation by -angle
        for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], chart.uv[2 * i + a]), hi[a] = std::max(hi[a], chart.uv[2 * i + a]);
    }
    const bool turn = hi[1] - lo[1] > hi[0] - lo[0];  // a quarter turn keeps width >= height
    for (size_t i = 0; i < corners; ++i) {
        const double x = chart.uv[2 * i] - lo[0], y = chart.uv[2 * i + 1] - lo[1];
        chart.uv[2 * i] = turn ? y : x;
        chart.uv[2 * i + 1] = turn ? hi[0] - lo[0] - x : y;
    }
    chart.width = turn ? hi[1] - lo[1] : hi[0] - lo[0];
    chart.height = turn ? hi[0] - lo[0] : hi[1] - lo[1];
    return chart;
}

// Grows charts over `pool` (faces of the mesh) with the given cone; flattened charts that
// overlap themselves are grown again with half the cone. owner[t] is the generation of the call
// to which t is still free (0 once taken), so a regrown chart never takes its neighbours' faces.
void growCharts(const MeshData& mesh, const Faces& f, const std::vector<uint32_t>& pool, double coneDegrees,
                std::vector<uint32_t>& owner, uint32_t& generation, std::vector<FlatChart>& out) {
    const uint32_t self = ++generation;
    for (uint32_t t : pool) owner[t] = self;
    std::vector<uint32_t> seeds = pool;
    std::stable_sort(seeds.begin(), seeds.end(), [&](uint32_t a, uint32_t b) { return f.area[a] > f.area[b]; });
    const double cosCone = std::cos(coneDegrees * M_PI / 180);
    for (uint32_t seed : seeds) {
        if (owner[seed] != self) continue;
        std::vector<uint32_t> chart{seed};
        owner[seed] = 0;
        const Vec& n0 = f.normal[seed];
        const bool single = coneDegrees < kMinConeDegrees || f.area[seed] == 0;
        for (size_t head = 0; head < chart.size() && !single; ++head)
            for (uint32_t e = f.start[chart[head]]; e < f.start[chart[head] + 1]; ++e) {
                const uint32_t g = f.adjacent[e];
                if (owner[g] == self && (f.area[g] == 0 || dot(f.normal[g], n0) >= cosCone)) owner[g] = 0, chart.push_back(g);
            }
        // A degenerate seed (only zero-area faces left) projects along z.
        FlatChart flat = project(mesh, chart, f.area[seed] > 0 ? n0 : Vec{0, 0, 1});
        if (chart.size() > 1 && trianglesOverlap(flat.uv))
            growCharts(mesh, f, chart, coneDegrees / 2, owner, generation, out);
        else
            out.push_back(std::move(flat));
    }
}

// Separating-axis test on the edge normals of both triangles; touching does not count.
bool interiorsMeet(const double* a, const double* b, double tolerance) {
    for (const double* tri : {a, b})
        for (int e = 0; e < 3; ++e) {
            const double* p = tri + 2 * e;
            const double* q = tri + 2 * ((e + 1) % 3);
            double nx = q[1] - p[1], ny = p[0] - q[0];
            const double len = std::hypot(nx, ny);
            if (len == 0) continue;
            nx /= len, ny /= len;
            double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
            for (int s = 0; s < 2; ++s)
                for (int c = 0; c < 3; ++c) {
                    const double d = (s ? b : a)[2 * c] * nx + (s ? b : a)[2 * c + 1] * ny;
                    lo[s] = std::min(lo[s], d), hi[s] = std::max(hi[s], d);
                }
            if (hi[0] <= lo[1] + tolerance || hi[1] <= lo[0] + tolerance) return false;
        }
    return true;
}

}  // namespace

bool trianglesOverlap(const std::vector<double>& uv) {
    const size_t n = uv.size() / 6;
    double extent = 0;
    std::vector<std::array<double, 4>> box(n);  // min x, max x, min y, max y
    std::vector<uint32_t> order;
    for (size_t t = 0; t < n; ++t) {
        const double* p = &uv[6 * t];
        box[t] = {std::min({p[0], p[2], p[4]}), std::max({p[0], p[2], p[4]}), std::min({p[1], p[3], p[5]}),
                  std::max({p[1], p[3], p[5]})};
        extent = std::max({extent, box[t][1] - box[t][0], box[t][3] - box[t][2]});
    }
    const double tolerance = 1e-6 * extent;
    for (size_t t = 0; t < n; ++t) {
        const double* p = &uv[6 * t];
        const double area = (p[2] - p[0]) * (p[5] - p[1]) - (p[4] - p[0]) * (p[3] - p[1]);
        if (std::fabs(area) > tolerance * extent) order.push_back(static_cast<uint32_t>(t));  // no interior otherwise
    }
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return box[a][0] < box[b][0] || (box[a][0] == box[b][0] && a < b); });
    for (size_t i = 0; i < order.size(); ++i)  // sweep along x
        for (size_t j = i + 1; j < order.size() && box[order[j]][0] < box[order[i]][1] - tolerance; ++j) {
            const auto &a = box[order[i]], &b = box[order[j]];
            if (a[2] < b[3] - tolerance && b[2] < a[3] - tolerance && interiorsMeet(&uv[6 * order[i]], &uv[6 * order[j]], tolerance))
                return true;
        }
    return false;
}

std::vector<FlatChart> flattenCharts(const MeshData& mesh, double coneDegrees) {
    const Faces f = faceGraph(mesh);
    std::vector<uint32_t> pool(mesh.triangleCount()), owner(mesh.triangleCount(), 0);
    std::iota(pool.begin(), pool.end(), 0u);
    std::vector<FlatChart> charts;
    uint32_t generation = 0;
    growCharts(mesh, f, pool, coneDegrees, owner, generation, charts);
    return charts;
}

}  // namespace hlod
