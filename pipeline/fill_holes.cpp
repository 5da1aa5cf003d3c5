// Scan-hole closing for the simplification fallback (simplify.cpp): meshoptimizer 0.18, like any
// edge collapse that keeps the topology, never closes a hole (each hole loop keeps >= 3 border
// vertices), so a hole-riddled facade cannot reach its triangle target. Each closable hole loop
// is triangulated by CGAL's Polygon_mesh_processing::triangulate_hole_polyline (Liepa's
// minimum-weight triangulation searched over a 3D Delaunay, "Filling holes in meshes", SGP 2003),
// adding no vertex: the patch reuses the loop's own vertices, so its texture coordinates are
// those of the hole's boundary, and a loop is closed only when it runs through one UV chart (its
// vertices are the same welded vertices all around), so the patch samples the texels the chart
// has between them. A loop is closable when it is
//   - closed and simple (every vertex on it has exactly one border edge in and one out),
//   - free of locked vertices (cut-plane borders stay: no cracks, §3.2),
//   - not the outline of its connected surface (the longest loop of the component: filling that
//     would lay a second surface over the first),
//   - at most kMaxHoleVertices long (the search is cubic in the worst case).
// Borders are found on positions (welded by position only), so UV seams are not borders.
#include "pipeline/pipeline.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <meshoptimizer.h>

#include <cmath>
#include <numeric>
#include <unordered_map>

namespace hlod {
namespace {

constexpr size_t kMaxHoleVertices = 64;

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

struct BorderEdge {
    uint32_t from, to;  // real vertices, in the direction of the one triangle that has the edge
    uint32_t next = kNone;
    bool visited = false;
};

struct Loop {
    std::vector<uint32_t> edges;
    double perimeter = 0;
    bool closable = true;
};

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

}  // namespace

std::vector<uint32_t> holePatches(const MeshData& mesh, const std::vector<uint32_t>& indices,
                                  const std::vector<uint8_t>& locked) {
    const size_t vc = mesh.vertexCount();
    std::vector<uint32_t> pos(vc);  // vertices with equal positions share an id
    meshopt_generateVertexRemap(pos.data(), nullptr, vc, mesh.positions.data(), vc, 3 * sizeof(float));
    std::unordered_map<uint64_t, uint32_t> uses;  // position edge -> triangles having it
    std::vector<uint32_t> component(vc);
    std::iota(component.begin(), component.end(), 0u);
    for (size_t e = 0; e < indices.size(); ++e) {
        const uint32_t a = pos[indices[e]], b = pos[indices[e - e % 3 + (e + 1) % 3]];
        ++uses[(uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
        component[findRoot(component, a)] = findRoot(component, b);
    }
    std::vector<BorderEdge> border;
    std::unordered_map<uint32_t, uint32_t> outgoing, incoming;  // position -> border edge, or kNone when several
    for (size_t e = 0; e < indices.size(); ++e) {  // in triangle order: the result is deterministic
        const uint32_t from = indices[e], to = indices[e - e % 3 + (e + 1) % 3];
        const uint32_t a = pos[from], b = pos[to];
        if (uses.at((uint64_t(std::min(a, b)) << 32) | std::max(a, b)) != 1) continue;
        const uint32_t id = static_cast<uint32_t>(border.size());
        border.push_back({from, to});
        for (auto [map, p] : {std::pair{&outgoing, pos[from]}, std::pair{&incoming, pos[to]}}) {
            auto [it, fresh] = map->try_emplace(p, id);
            if (!fresh) it->second = kNone;
        }
    }
    std::vector<Loop> loops;
    std::unordered_map<uint32_t, size_t> outline;  // component -> its longest loop
    auto length = [&](const BorderEdge& e) {
        const float* a = &mesh.positions[3 * e.from];
        const float* b = &mesh.positions[3 * e.to];
        return std::hypot(double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]);
    };
    for (uint32_t start = 0; start < border.size(); ++start) {
        if (border[start].visited) continue;
        Loop loop;
        uint32_t e = start;
        while (e != kNone && !border[e].visited) {
            BorderEdge& edge = border[e];
            edge.visited = true;
            loop.edges.push_back(e);
            loop.perimeter += length(edge);
            const auto in = incoming.find(pos[edge.from]);
            loop.closable = loop.closable && !locked[edge.from] && in != incoming.end() && in->second != kNone;
            const auto out = outgoing.find(pos[edge.to]);
            e = out == outgoing.end() ? kNone : out->second;
            if (e != kNone && border[e].from != edge.to) loop.closable = false;  // crosses a UV seam
        }
        loop.closable = loop.closable && e == start && loop.edges.size() >= 3 && loop.edges.size() <= kMaxHoleVertices;
        const uint32_t c = findRoot(component, pos[border[start].from]);
        auto [it, fresh] = outline.try_emplace(c, loops.size());
        if (!fresh && loops[it->second].perimeter < loop.perimeter) it->second = loops.size();
        loops.push_back(std::move(loop));
    }
    for (const auto& [c, longest] : outline) loops[longest].closable = false;

    std::vector<uint32_t> patches;
    for (const Loop& loop : loops) {
        if (!loop.closable) continue;
        // The patch must run each border edge the other way: walk the loop backwards, and
        // CGAL's triangles (i < j < k) then follow the polyline's direction.
        std::vector<uint32_t> ring;
        for (size_t i = loop.edges.size(); i-- > 0;) ring.push_back(border[loop.edges[i]].from);
        std::vector<Point> polyline;
        for (uint32_t v : ring) polyline.emplace_back(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
        std::vector<CGAL::Triple<int, int, int>> patch;
        CGAL::Polygon_mesh_processing::triangulate_hole_polyline(polyline, std::back_inserter(patch));
        if (patch.size() + 2 != ring.size()) continue;  // CGAL found no complete triangulation
        for (const auto& t : patch) patches.insert(patches.end(), {ring[t.first], ring[t.second], ring[t.third]});
    }
    return patches;
}

}  // namespace hlod
