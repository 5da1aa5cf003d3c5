// The scanned surfaces under a generated walk (player/CAMERA_PATH.md "Eye height", "Indoors"):
// triangles decoded from a cut of the database, bucketed by their footprint on the horizontal
// plane in a uniform grid, so that the heights of the surfaces above or below a horizontal point
// (a vertical line through it, against each triangle of its cell) and the triangles a short
// segment crosses (Möller and Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection",
// JGT 1997) are found without scanning them all.
#include "player/camera_path.h"

#include <algorithm>
#include <cmath>

namespace hlod {

SurfaceHeights::SurfaceHeights(int upAxis) : up_(upAxis), a_(upAxis == 1 ? 2 : 0), b_(upAxis == 1 ? 0 : 1) {}

void SurfaceHeights::add(const MeshData& mesh) {
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        Triangle tri{};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) tri.p[k][i] = mesh.positions[3 * size_t(mesh.indices[3 * t + k]) + size_t(i)];
        triangles_.push_back(tri);
    }
    grid_.clear();  // rebuilt on the next query
}

void SurfaceHeights::index() const {
    if (!grid_.empty() || triangles_.empty()) return;
    double hi[2] = {-INFINITY, -INFINITY};
    lo_[0] = lo_[1] = INFINITY;
    for (const Triangle& t : triangles_)
        for (const auto& p : t.p) {
            lo_[0] = std::min(lo_[0], double(p[a_])), hi[0] = std::max(hi[0], double(p[a_]));
            lo_[1] = std::min(lo_[1], double(p[b_])), hi[1] = std::max(hi[1], double(p[b_]));
        }
    cells_ = std::clamp<uint32_t>(uint32_t(std::sqrt(double(triangles_.size()) / 4)), 1, 4096);
    for (int i = 0; i < 2; ++i) size_[i] = std::max((hi[i] - lo_[i]) / cells_, 1e-9);
    grid_.assign(size_t(cells_) * cells_, {});
    for (uint32_t k = 0; k < triangles_.size(); ++k) {
        const Triangle& t = triangles_[k];
        const auto [x0, y0] = cell(std::min({t.p[0][a_], t.p[1][a_], t.p[2][a_]}), std::min({t.p[0][b_], t.p[1][b_], t.p[2][b_]}));
        const auto [x1, y1] = cell(std::max({t.p[0][a_], t.p[1][a_], t.p[2][a_]}), std::max({t.p[0][b_], t.p[1][b_], t.p[2][b_]}));
        for (uint32_t y = y0; y <= y1; ++y)
            for (uint32_t x = x0; x <= x1; ++x) grid_[size_t(y) * cells_ + x].push_back(k);
    }
}

std::pair<uint32_t, uint32_t> SurfaceHeights::cell(double x, double y) const {
    auto c = [&](double v, int i) { return uint32_t(std::clamp((v - lo_[i]) / size_[i], 0.0, double(cells_ - 1))); };
    return {c(x, 0), c(y, 1)};
}

double SurfaceHeights::lowest(double x, double y) const {
    index();
    if (grid_.empty()) return NAN;
    const auto [cx, cy] = cell(x, y);
    double best = INFINITY;
    for (uint32_t k : grid_[size_t(cy) * cells_ + cx]) {
        const Triangle& t = triangles_[k];
        // Barycentric coordinates of (x, y) in the triangle's horizontal projection.
        const double ax = t.p[0][a_], ay = t.p[0][b_];
        const double ux = t.p[1][a_] - ax, uy = t.p[1][b_] - ay, vx = t.p[2][a_] - ax, vy = t.p[2][b_] - ay;
        const double det = ux * vy - uy * vx;
        if (std::abs(det) < 1e-12) continue;  // vertical (a wall): no height of its own at a point
        const double s = ((x - ax) * vy - (y - ay) * vx) / det, r = (ux * (y - ay) - uy * (x - ax)) / det;
        if (s < 0 || r < 0 || s + r > 1) continue;
        best = std::min(best, t.p[0][up_] + s * (t.p[1][up_] - t.p[0][up_]) + r * (t.p[2][up_] - t.p[0][up_]));
    }
    return std::isfinite(best) ? best : NAN;
}

bool SurfaceHeights::crosses(const double from[3], const double to[3]) const {
    index();
    if (grid_.empty()) return false;
    const auto [x0, y0] = cell(std::min(from[a_], to[a_]), std::min(from[b_], to[b_]));
    const auto [x1, y1] = cell(std::max(from[a_], to[a_]), std::max(from[b_], to[b_]));
    const double d[3] = {to[0] - from[0], to[1] - from[1], to[2] - from[2]};
    for (uint32_t y = y0; y <= y1; ++y)
        for (uint32_t x = x0; x <= x1; ++x)
            for (uint32_t k : grid_[size_t(y) * cells_ + x]) {
                const Triangle& t = triangles_[k];
                double e1[3], e2[3], s[3];
                for (int i = 0; i < 3; ++i) e1[i] = t.p[1][i] - t.p[0][i], e2[i] = t.p[2][i] - t.p[0][i], s[i] = from[i] - t.p[0][i];
                const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
                const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
                if (std::abs(det) < 1e-12) continue;
                const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
                if (u < 0 || u > 1) continue;
                const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
                const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
                if (v < 0 || u + v > 1) continue;
                const double along = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
                if (along >= 0 && along <= 1) return true;
            }
    return false;
}

}  // namespace hlod
