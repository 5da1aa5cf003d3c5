// Plane cut of thesis §3.2 / Fig. 3.2: triangles crossing a cutting plane are split into three,
// with two new vertices where the plane meets the crossing edges; every attribute is linearly
// interpolated, so area and UVs are kept exactly. A new vertex is made once per cut edge and
// shared by both neighbours, so pieces stay welded and both sides of the cut get identical
// border vertices (no cracks). Hand-written: CGAL's PMP::split drops UVs (see dependencies.md).
//
// dividePiece places its c_levelFactor - 1 planes along the longest axis to balance triangle
// counts (plane k near the k/c_levelFactor quantile of the centroids: children then carry about
// 1/c_levelFactor of the parent's triangles, as the factor recursion of §3.2 assumes, and uneven
// scan density cannot produce empty or overfull pieces) while crossing few triangles: a plane at
// the quantile itself often runs inside a dense surface nearly parallel to it (a noisy facade
// when the piece is deeper than it is wide), slicing every triangle of that surface into three
// and leaving all the new vertices locked on the border. Each plane minimises
// 3 x crossing triangles + |triangles below - k/c x triangles| over 63 positions evenly spread
// across the extent and the quantile itself.
// Planes::Even (`hlod build --planes even`) reads §3.2 literally instead: the planes "run from
// one end of the bounding box to the other end", evenly spaced along the longest side, so a
// piece of uneven density gives unequal or empty pieces; empty pieces are dropped (a node may
// then have fewer than c_levelFactor children; pipeline/TREE.md).
#include "pipeline/pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace hlod {
namespace {

// Source vertices followed by the vertices created on cut edges.
struct Extended {
    const MeshData& source;
    MeshData added;
    std::unordered_map<uint64_t, uint32_t> byEdge;
};

uint32_t edgeVertex(Extended& ex, uint32_t a, uint32_t b, const std::vector<float>& d, int axis, float position) {
    const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    if (auto it = ex.byEdge.find(key); it != ex.byEdge.end()) return it->second;
    // Interpolate from the endpoint below the plane: the result depends on the edge alone, not
    // on vertex numbering, so two pieces holding the same edge (neighbouring blocks of the
    // streamed split) create the same vertex.
    if (d[a] > d[b]) std::swap(a, b);
    const float t = d[a] / (d[a] - d[b]);
    const MeshData& s = ex.source;
    auto lerp = [&](const std::vector<float>& v, std::vector<float>& out, int n) {
        for (int i = 0; i < n; ++i) out.push_back(v[n * a + i] + t * (v[n * b + i] - v[n * a + i]));
    };
    lerp(s.positions, ex.added.positions, 3);
    ex.added.positions[ex.added.positions.size() - 3 + axis] = position;
    if (!s.texcoords.empty()) lerp(s.texcoords, ex.added.texcoords, 2);
    if (!s.normals.empty()) lerp(s.normals, ex.added.normals, 3);
    for (size_t i = 0; i < 4 && !s.colors.empty(); ++i)
        ex.added.colors.push_back(static_cast<uint8_t>(s.colors[4 * a + i] + t * (s.colors[4 * b + i] - s.colors[4 * a + i]) + 0.5f));
    const uint32_t id = static_cast<uint32_t>(s.vertexCount() + ex.added.vertexCount() - 1);
    ex.byEdge.emplace(key, id);
    return id;
}

// Collects triangles of one side (indices into Extended) and compacts them into a Piece.
struct SideBuilder {
    std::vector<uint32_t> indices, materials;

    Piece finish(const Extended& ex) const {
        Piece out;
        std::vector<uint32_t> remap(ex.source.vertexCount() + ex.added.vertexCount(), kNone);
        auto copy = [](const std::vector<float>& v, std::vector<float>& o, size_t i, int n) {
            o.insert(o.end(), v.begin() + n * i, v.begin() + n * (i + 1));
        };
        for (uint32_t i : indices) {
            if (remap[i] == kNone) {
                remap[i] = static_cast<uint32_t>(out.mesh.vertexCount());
                const bool src = i < ex.source.vertexCount();
                const MeshData& m = src ? ex.source : ex.added;
                const size_t j = src ? i : i - ex.source.vertexCount();
                copy(m.positions, out.mesh.positions, j, 3);
                if (!m.texcoords.empty()) copy(m.texcoords, out.mesh.texcoords, j, 2);
                if (!m.normals.empty()) copy(m.normals, out.mesh.normals, j, 3);
                if (!m.colors.empty()) out.mesh.colors.insert(out.mesh.colors.end(), m.colors.begin() + 4 * j, m.colors.begin() + 4 * j + 4);
            }
            out.mesh.indices.push_back(remap[i]);
        }
        out.materials = materials;
        return out;
    }

    void addPolygon(const uint32_t* poly, size_t n, uint32_t material) {
        for (size_t k = 2; k < n; ++k) {
            indices.insert(indices.end(), {poly[0], poly[k - 1], poly[k]});
            materials.push_back(material);
        }
    }
};

// Sutherland-Hodgman clip of one triangle to the side sign * d >= 0.
size_t clipTriangle(Extended& ex, const uint32_t* tri, const std::vector<float>& d, float sign, int axis,
                    float position, uint32_t* poly) {
    size_t n = 0;
    for (int k = 0; k < 3; ++k) {
        const uint32_t i = tri[k], j = tri[(k + 1) % 3];
        const float di = sign * d[i], dj = sign * d[j];
        if (di >= 0) poly[n++] = i;
        if ((di > 0 && dj < 0) || (di < 0 && dj > 0)) poly[n++] = edgeVertex(ex, i, j, d, axis, position);
    }
    return n;
}

}  // namespace

Box3f pieceBounds(const MeshData& mesh) {
    Box3f b{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    for (size_t i = 0; i < mesh.vertexCount(); ++i) {
        const float* p = &mesh.positions[3 * i];
        b.min = {std::min(b.min.x, p[0]), std::min(b.min.y, p[1]), std::min(b.min.z, p[2])};
        b.max = {std::max(b.max.x, p[0]), std::max(b.max.y, p[1]), std::max(b.max.z, p[2])};
    }
    return b;
}

CutResult cutPiece(const Piece& piece, int axis, float position) {
    const MeshData& m = piece.mesh;
    std::vector<float> d(m.vertexCount());
    for (size_t i = 0; i < d.size(); ++i) d[i] = m.positions[3 * i + axis] - position;
    Extended ex{m, {}, {}};
    SideBuilder below, above;
    uint32_t poly[4];
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t* tri = &m.indices[3 * t];
        const float d0 = d[tri[0]], d1 = d[tri[1]], d2 = d[tri[2]];
        if (d0 <= 0 && d1 <= 0 && d2 <= 0) {
            below.addPolygon(tri, 3, piece.materials[t]);
        } else if (d0 >= 0 && d1 >= 0 && d2 >= 0) {
            above.addPolygon(tri, 3, piece.materials[t]);
        } else {
            below.addPolygon(poly, clipTriangle(ex, tri, d, -1, axis, position, poly), piece.materials[t]);
            above.addPolygon(poly, clipTriangle(ex, tri, d, 1, axis, position, poly), piece.materials[t]);
        }
    }
    return {below.finish(ex), above.finish(ex)};
}

namespace {

constexpr int kCandidates = 64;
constexpr double kCrossingWeight = 3;  // a crossing triangle becomes three, with two locked vertices

// For every candidate position (sorted, unique), how many of `values` lie below it: strictly
// (std::lower_bound's count on the sorted values) or not (std::upper_bound's). One pass and a
// histogram over the candidates instead of a sort of the values (the sorts were 5 % of a build).
// The search is branchless (the candidates' prefix satisfying `before`, halved with a conditional
// move: values fall at random among the candidates, and a mispredicted branch per halving made
// std::upper_bound most of a division's cost), the same index as std::upper_bound / lower_bound.
template <class Before>
size_t prefixLength(const std::vector<float>& sorted, Before before) {
    if (sorted.empty()) return 0;
    const float* base = sorted.data();
    for (size_t length = sorted.size(); length > 1;) {
        const size_t half = length / 2;
        base += half * static_cast<size_t>(before(base[half - 1]));  // a multiply: GCC 12 branched on `? :`
        length -= half;
    }
    return static_cast<size_t>(base - sorted.data()) + (before(*base) ? 1 : 0);
}

std::vector<double> countsBelow(const std::vector<float>& values, const std::vector<float>& candidates, bool strictly) {
    std::vector<double> counts(candidates.size() + 1);
    for (float v : values)  // v < p for candidates from upper_bound(v) on; v <= p from lower_bound(v) on
        ++counts[strictly ? prefixLength(candidates, [v](float p) { return p <= v; }) : prefixLength(candidates, [v](float p) { return p < v; })];
    for (size_t i = 1; i < counts.size(); ++i) counts[i] += counts[i - 1];
    counts.pop_back();
    return counts;
}

std::vector<float> divisionPlanes(const MeshData& m, int axis, uint32_t count) {
    const size_t n = m.triangleCount();
    if (n == 0) return {};
    std::vector<float> lows(n), highs(n), centroids(n);
    for (size_t t = 0; t < n; ++t) {
        const float a = m.positions[3 * m.indices[3 * t] + axis], b = m.positions[3 * m.indices[3 * t + 1] + axis],
                    c = m.positions[3 * m.indices[3 * t + 2] + axis];
        lows[t] = std::min({a, b, c}), highs[t] = std::max({a, b, c}), centroids[t] = (a + b + c) / 3.0f;
    }
    const auto [lowest, highest] = std::minmax_element(centroids.begin(), centroids.end());
    const float lo = *lowest, hi = *highest;
    // The candidates: per plane the quantile centroid, then through a vertex (no sliver beside a
    // vertex on the plane): the smallest vertex coordinate >= each of the even positions, the
    // largest coordinate when none is.
    std::vector<float> quantiles, evens, through(kCandidates, -std::numeric_limits<float>::infinity());
    std::vector<float> copy = centroids;  // each quantile selected among those above the last one
    size_t from = 0;
    for (uint32_t k = 1; k < count; ++k) {
        const size_t at = static_cast<size_t>(double(n) * k / count);
        std::nth_element(copy.begin() + from, copy.begin() + at, copy.end());
        quantiles.push_back(copy[at] + 0.0f), from = at;  // + 0: a tie of -0 and +0 gives +0, whichever nth_element puts there
    }
    for (int i = 1; i < kCandidates; ++i) evens.push_back(lo + (hi - lo) * static_cast<float>(i) / kCandidates);
    std::vector<float> smallestFrom(kCandidates, std::numeric_limits<float>::infinity());  // by the evens below it
    float largest = -std::numeric_limits<float>::infinity();
    for (size_t v = 0; v < m.vertexCount(); ++v) {
        const float x = m.positions[3 * v + axis];
        largest = std::max(largest, x);
        float& slot = smallestFrom[prefixLength(evens, [x](float p) { return p <= x; })];  // std::upper_bound's index
        slot = std::min(slot, x);
    }
    for (int i = kCandidates - 2; i >= 0; --i) smallestFrom[i] = std::min(smallestFrom[i], smallestFrom[i + 1]);
    for (int i = 1; i < kCandidates; ++i)  // evens[i - 1] <= x from slot i on
        through[i] = std::isinf(smallestFrom[i]) ? largest : smallestFrom[i];
    std::vector<float> candidates(quantiles);
    candidates.insert(candidates.end(), through.begin() + 1, through.end());
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    const std::vector<double> lowsBelow = countsBelow(lows, candidates, true), highsBelow = countsBelow(highs, candidates, false),
                              centroidsBelow = countsBelow(centroids, candidates, false);
    auto cost = [&](float p, double wanted) {
        const size_t i = std::lower_bound(candidates.begin(), candidates.end(), p) - candidates.begin();
        const double crossing = lowsBelow[i] - highsBelow[i];
        return (kCrossingWeight * crossing + std::abs(centroidsBelow[i] - wanted)) / double(n);
    };
    std::vector<float> planes;
    for (uint32_t k = 1; k < count; ++k) {
        const double wanted = double(n) * k / count;
        float best = quantiles[k - 1];
        double bestCost = cost(best, wanted);
        for (int i = 1; i < kCandidates; ++i)
            if (const double c = cost(through[i], wanted); c < bestCost) best = through[i], bestCost = c;
        planes.push_back(best);
    }
    std::sort(planes.begin(), planes.end());
    planes.erase(std::unique(planes.begin(), planes.end()), planes.end());
    return planes;
}

std::vector<float> evenPlanes(float lo, float hi, uint32_t count) {
    std::vector<float> planes;
    for (uint32_t k = 1; k < count; ++k) planes.push_back(lo + (hi - lo) * static_cast<float>(k) / static_cast<float>(count));
    return planes;
}

}  // namespace

std::vector<Piece> dividePiece(const Piece& piece, uint32_t count, Planes placement, Sides shared, std::vector<Sides>* childSides) {
    const Box3f b = pieceBounds(piece.mesh);
    const float lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z};
    const float extent[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const int axis = static_cast<int>(std::max_element(extent, extent + 3) - extent);
    const std::vector<float> planes = placement == Planes::Even ? evenPlanes(lo[axis], hi[axis], count)
                                                                : divisionPlanes(piece.mesh, axis, count);
    std::vector<Piece> pieces;
    std::vector<Sides> sides;  // a slab's: the piece's, and the planes below and above it
    Piece rest;
    const Piece* above = &piece;  // the part above the planes so far (the piece itself: not copied)
    for (size_t k = 0; k < planes.size(); ++k) {
        CutResult cut = cutPiece(*above, axis, planes[k]);
        if (cut.below.mesh.triangleCount() > 0)
            pieces.push_back(std::move(cut.below)), sides.push_back(shared | sideBit(axis, true) | (k > 0 ? sideBit(axis, false) : 0));
        rest = std::move(cut.above), above = &rest;
    }
    if (above->mesh.triangleCount() > 0) {
        if (above == &piece) pieces.push_back(piece), sides.push_back(shared);  // no plane: the piece whole
        else pieces.push_back(std::move(rest)), sides.push_back(shared | sideBit(axis, false));
    }
    if (childSides) *childSides = std::move(sides);
    return pieces;
}

}  // namespace hlod
