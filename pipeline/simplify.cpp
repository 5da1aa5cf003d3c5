// Simplification of thesis §3.2 ("Qslim ... with a metric such that the number of triangles
// decrease by a factor"): quadric error metrics down to triangleCount / factor. A node is
// simplified as ONE mesh (simplifyNode), welded by position first (weld.cpp), so that chunk and
// material borders are interior edges: a change of texture coordinates or material is an
// attribute seam, not a topological border (issue #16: simplifying each material apart, with its
// seam vertices locked, kept coarse levels of chunked multi-atlas scans at 40-55 % of the input).
// The vertices a neighbouring node shares are locked, so pieces of any level meet without
// cracks: open-border vertices on the piece's bounding-box faces of its shared sides (every cut
// plane, of the block grid or of §3.2's division, is such a face; a folder input's block has
// unknown neighbours, so all its sides are shared). Other open borders (scan holes, occlusion
// gaps, the edge of the scanned area, also where it lies on the input's bounding box: stop 40)
// simplify freely: locking every border, as
// meshopt_SimplifyLockBorder does, keeps a hole-riddled scan from ever reaching its target. Both
// simplifiers only collapse edges onto existing vertices, so texture coordinates stay exact.
// meshoptimizer (default, ~1.4 M tri/s) or OpenMesh's Decimater with ModQuadric (~50 k tri/s,
// selectable with --simplifier openmesh; it has no seams, so seam vertices are locked for it).
// Two passes (simplifyNode):
//   1. seam-preserving: all vertices, seams kept (a seam vertex collapses only along its seam);
//   2. when pass 1 ends above kTargetSlack x the target (fragmented photogrammetry UVs: every
//      chart outline is a seam) and the piece has seams at all, geometry only: one vertex per position, no texture
//      coordinates, cut-plane borders still locked; build_tree.cpp gives such a node a new
//      texture (baked) instead of cropping the source atlases.
// Neither simplifier closes a hole, so a mesh with many scan holes stops far above its target.
// Fallback in both passes: when the result exceeds kTargetSlack x the target, the closable holes
// of the result (no locked vertex, not a surface's outline: fill_holes.cpp) are triangulated and
// the result simplified again, up to kFillRounds times. Locked vertices never move, so borders
// stay crack-free.
// Error ceiling (simplifyNode's `ceiling`, --error-cap on, pipeline/TREE.md): the pass kept
// (pass 1 when its capped run ends within the slack, else chosen by its uncapped run) stops
// there, its rounds sharing the ceiling through meshoptimizer's target_error (each gets what the
// earlier ones left), before the target where the factor would make the node too coarse.
#include "pipeline/pipeline.h"

#include <meshoptimizer.h>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace hlod {
namespace {

constexpr int kFillRounds = 16;  // hole filling + simplification rounds of the fallback

// Keeps only the vertices `indices` use, in first-use order; `kept` (optional) receives, per
// new vertex, its index in `mesh`.
MeshData compact(const MeshData& mesh, const std::vector<uint32_t>& indices, std::vector<uint32_t>* kept = nullptr) {
    MeshData out;
    std::vector<uint32_t> remap(mesh.vertexCount(), kNone);
    for (uint32_t i : indices) {
        if (remap[i] == kNone) {
            remap[i] = static_cast<uint32_t>(out.vertexCount());
            if (kept) kept->push_back(i);
            out.positions.insert(out.positions.end(), mesh.positions.begin() + 3 * i, mesh.positions.begin() + 3 * i + 3);
            if (!mesh.texcoords.empty())
                out.texcoords.insert(out.texcoords.end(), mesh.texcoords.begin() + 2 * i, mesh.texcoords.begin() + 2 * i + 2);
            if (!mesh.normals.empty())
                out.normals.insert(out.normals.end(), mesh.normals.begin() + 3 * i, mesh.normals.begin() + 3 * i + 3);
            if (!mesh.colors.empty())
                out.colors.insert(out.colors.end(), mesh.colors.begin() + 4 * i, mesh.colors.begin() + 4 * i + 4);
        }
        out.indices.push_back(remap[i]);
    }
    return out;
}

// meshoptimizer 0.18 has no per-vertex lock (0.21's vertex_lock). A vertex that shares its
// position with an unreferenced twin is classified Kind_Locked by its simplifier (a two-way
// wedge whose twin has no open edge is not a seam), so it is never collapsed; the twins are
// appended after the real vertices and never appear in the result.
// `error` (when given) receives meshoptimizer's own error of the result: 0.18 returns the square
// root of the largest quadric error of its collapses (each an area-weighted mean of squared
// distances to the planes of the triangles merged into the vertex) on positions scaled to the
// unit cube, so it is multiplied by meshopt_simplifyScale of the same positions (its header).
std::vector<uint32_t> simplifyMeshopt(const MeshData& mesh, const std::vector<uint32_t>& indices, size_t targetTriangles,
                                      const std::vector<uint8_t>& locked, double* error, double ceiling = HUGE_VAL) {
    std::vector<float> positions = mesh.positions;
    for (size_t i = 0; i < locked.size(); ++i)
        if (locked[i]) positions.insert(positions.end(), mesh.positions.begin() + 3 * i, mesh.positions.begin() + 3 * i + 3);
    std::vector<uint32_t> out(indices.size());
    float relative = 0;
    const double scale = meshopt_simplifyScale(positions.data(), positions.size() / 3, 3 * sizeof(float));
    const float targetError = std::isfinite(ceiling) && scale > 0 ? static_cast<float>(ceiling / scale) : FLT_MAX;
    const size_t n = meshopt_simplify(out.data(), indices.data(), indices.size(), positions.data(),
                                      positions.size() / 3, 3 * sizeof(float), targetTriangles * 3, targetError, 0, &relative);
    out.resize(n);
    if (error) *error = double(relative) * scale;
    return out;
}

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

std::vector<uint32_t> simplifyOpenMesh(const MeshData& mesh, const std::vector<uint32_t>& indices, size_t targetTriangles,
                                       const std::vector<uint8_t>& locked) {
    // OpenMesh says each face it refuses on its error stream (`PolyMeshT::add_face: complex edge`,
    // thousands of lines naming no file on a non-manifold scan until stop 51); those faces are kept
    // unsimplified below, so the stream is silenced, once for the process.
    static const bool quiet = (omerr().disable(), true);
    (void)quiet;
    OMesh om;
    om.request_vertex_status(), om.request_edge_status(), om.request_face_status();
    std::vector<OMesh::VertexHandle> handles(mesh.vertexCount());
    for (size_t i = 0; i < handles.size(); ++i)
        handles[i] = om.add_vertex({mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]});
    std::vector<uint32_t> out;  // faces OpenMesh refuses (non-manifold) are kept unsimplified
    for (size_t t = 0; t < indices.size() / 3; ++t) {
        const uint32_t* tri = &indices[3 * t];
        if (!om.add_face(handles[tri[0]], handles[tri[1]], handles[tri[2]]).is_valid())
            out.insert(out.end(), tri, tri + 3);
    }
    for (size_t i = 0; i < locked.size(); ++i)
        if (locked[i]) om.status(handles[i]).set_locked(true);
    OpenMesh::Decimater::DecimaterT<OMesh> decimater(om);
    OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
    decimater.add(quadric);
    decimater.initialize();
    const size_t kept = out.size() / 3;
    decimater.decimate_to_faces(0, targetTriangles > kept ? targetTriangles - kept : 1);
    for (auto fh : om.faces()) {
        if (om.status(fh).deleted()) continue;
        for (auto vh : om.fv_range(fh)) out.push_back(static_cast<uint32_t>(vh.idx()));
    }
    return out;
}

}  // namespace

std::vector<uint8_t> sharedVertices(const Piece& piece, Sides shared) {
    const MeshData& m = piece.mesh;
    const size_t vc = m.vertexCount();
    std::vector<uint32_t> position(vc);  // vertices with equal positions share an id
    const size_t positions = meshopt_generateVertexRemap(position.data(), nullptr, vc, m.positions.data(), vc, 3 * sizeof(float));
    // An edge used once is a border. The edges bucketed by their smaller end (a counting sort),
    // each bucket sorted: ~3 x faster than sorting all the edges (~5 x a hash map's speed).
    auto edge = [&](size_t corner) {
        const size_t t = corner / 3, k = corner % 3;
        const uint32_t a = position[m.indices[3 * t + k]], b = position[m.indices[3 * t + (k + 1) % 3]];
        return std::pair<uint32_t, uint32_t>(std::min(a, b), std::max(a, b));
    };
    std::vector<uint32_t> start(positions + 1), other(m.indices.size());
    for (size_t c = 0; c < m.indices.size(); ++c) ++start[edge(c).first + 1];
    for (size_t p = 0; p < positions; ++p) start[p + 1] += start[p];
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t c = 0; c < m.indices.size(); ++c) {
        const auto [a, b] = edge(c);
        other[fill[a]++] = b;
    }
    std::vector<uint8_t> border(vc);
    for (uint32_t a = 0; a < positions; ++a) {
        const auto first = other.begin() + start[a], last = other.begin() + start[a + 1];
        std::sort(first, last);
        for (auto i = first; i != last;) {
            auto j = i + 1;
            while (j != last && *j == *i) ++j;
            if (j - i == 1) border[a] = border[*i] = 1;
            i = j;
        }
    }
    const Box3f box = pieceBounds(m);
    const float lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
    std::vector<uint8_t> locked(vc);
    for (size_t i = 0; i < vc; ++i) {
        const float* p = &m.positions[3 * i];
        bool onFace = false;
        for (int a = 0; a < 3; ++a)
            onFace = onFace || (p[a] == lo[a] && (shared & sideBit(a, false))) || (p[a] == hi[a] && (shared & sideBit(a, true)));
        locked[i] = border[position[i]] && onFace;
    }
    return locked;
}

std::vector<SubMesh> splitByMaterial(const Piece& piece, bool withLocked) {
    const std::vector<uint8_t> locked = withLocked ? sharedVertices(piece) : std::vector<uint8_t>{};
    std::vector<SubMesh> parts;
    std::vector<uint32_t> slot;
    std::vector<std::vector<uint32_t>> indices;
    for (size_t t = 0; t < piece.materials.size(); ++t) {
        const uint32_t m = piece.materials[t];
        if (m >= slot.size()) slot.resize(m + 1, kNone);
        if (slot[m] == kNone) slot[m] = static_cast<uint32_t>(indices.size()), indices.emplace_back();
        auto& list = indices[slot[m]];
        list.insert(list.end(), piece.mesh.indices.begin() + 3 * t, piece.mesh.indices.begin() + 3 * t + 3);
    }
    for (uint32_t m = 0; m < slot.size(); ++m) {
        if (slot[m] == kNone) continue;
        std::vector<uint32_t> kept;
        SubMesh part{m, compact(piece.mesh, indices[slot[m]], withLocked ? &kept : nullptr), {}};
        for (uint32_t i : kept) part.locked.push_back(locked[i]);
        parts.push_back(std::move(part));
    }
    return parts;
}

namespace {

// A finite ceiling binds meshoptimizer only (OpenMesh's decimater reports no error).
bool capping(double ceiling, Simplifier simplifier) { return std::isfinite(ceiling) && simplifier == Simplifier::Meshopt; }

bool withinSlack(const std::vector<uint32_t>& indices, size_t target) {
    return double(indices.size() / 3) <= kTargetSlack * double(target);
}

// Simplifies `indices` (into `mesh`) to about `target` triangles; when the result exceeds
// kTargetSlack x target, the hole-filling fallback of the header comment. `error` (when given)
// receives the sum of meshoptimizer's errors over the rounds (each round's is measured from the
// previous round's result; 0 for OpenMesh, which reports none). With a finite `ceiling` the
// rounds share it: each stops at what the earlier ones left, and the rounds end when none is left
// or a round no longer lowers the count (its patches then stay as they were).
std::vector<uint32_t> simplifyToTarget(const MeshData& mesh, const std::vector<uint32_t>& indices, size_t target,
                                       const std::vector<uint8_t>& lock, Simplifier simplifier, double* error = nullptr,
                                       double ceiling = HUGE_VAL) {
    const bool capped = capping(ceiling, simplifier);
    double sum = 0;  // the rounds' errors so far
    auto simplify = [&](const std::vector<uint32_t>& in) {
        double roundError = 0;
        std::vector<uint32_t> out = simplifier == Simplifier::Meshopt
                                        ? simplifyMeshopt(mesh, in, target, lock, &roundError, capped ? ceiling - sum : HUGE_VAL)
                                        : simplifyOpenMesh(mesh, in, target, lock);
        sum += roundError;
        return out;
    };
    std::vector<uint32_t> result = simplify(indices);
    for (int round = 0; round < kFillRounds && !withinSlack(result, target); ++round) {
        if (capped && sum >= ceiling) break;
        std::vector<uint32_t> patches = holePatches(mesh, result, lock);
        if (patches.empty()) break;
        patches.insert(patches.begin(), result.begin(), result.end());
        const double before = sum;
        std::vector<uint32_t> next = simplify(patches);
        if (capped && next.size() >= result.size()) {
            sum = before;
            break;
        }
        result = std::move(next);
    }
    if (error) *error = sum;
    return result;
}

size_t targetOf(size_t triangles, double factor) {
    return std::max<size_t>(1, static_cast<size_t>(std::llround(triangles / factor)));
}

}  // namespace

MeshData simplifyMesh(const MeshData& mesh, double factor, Simplifier simplifier, const std::vector<uint8_t>& locked) {
    if (factor <= 1 || mesh.triangleCount() < 2) return mesh;
    const std::vector<uint8_t> lock = locked.size() == mesh.vertexCount() ? locked : sharedVertices({mesh, std::vector<uint32_t>(mesh.triangleCount())});
    return compact(mesh, simplifyToTarget(mesh, mesh.indices, targetOf(mesh.triangleCount(), factor), lock, simplifier));
}

SimplifiedNode simplifyNode(const Piece& piece, double factor, Simplifier simplifier, Sides shared, double ceiling) {
    SimplifiedNode out;
    const MeshData& m = piece.mesh;
    if (factor <= 1 || m.triangleCount() < 2) {
        out.piece = piece;
        return out;
    }
    const size_t vc = m.vertexCount(), target = targetOf(m.triangleCount(), factor);
    const std::vector<uint8_t> lock = sharedVertices(piece, shared);
    std::vector<uint32_t> position(vc);  // vertices with equal positions share an id
    const size_t positions = meshopt_generateVertexRemap(position.data(), nullptr, vc, m.positions.data(), vc, 3 * sizeof(float));
    // 1. Seam-preserving: meshoptimizer keeps a seam's two sides together (a seam vertex only
    // collapses along the seam, both sides at once). OpenMesh's decimater has no seams: the
    // vertices of a seam are locked, as a material seam was before.
    std::vector<uint8_t> seamLock = lock;
    if (simplifier == Simplifier::OpenMesh) {
        std::vector<uint32_t> wedges(positions);
        for (uint32_t p : position) ++wedges[p];
        for (size_t i = 0; i < vc; ++i) seamLock[i] = seamLock[i] || wedges[position[i]] > 1;
    }
    // Pass 2 applies when the uncapped pass 1 ends over the slack. With a ceiling the capped pass
    // runs first: when it ends within the slack the uncapped one almost always would too (it
    // collapses as far or further but for meshoptimizer's coarse error buckets and the capped
    // rounds' undo), and the capped result is kept either way (within the slack, the ceiling and
    // the locks); the uncapped one runs only to decide when the capped one ends over the slack.
    // Without seams (one vertex per position) pass 2 would repeat pass 1's collapses and only
    // drop the UVs and materials: pass 1 is kept.
    std::vector<uint32_t> result = simplifyToTarget(m, m.indices, target, seamLock, simplifier, &out.error, ceiling);
    const bool seams = positions < vc;
    const auto uncappedWithinSlack = [&] { return withinSlack(simplifyToTarget(m, m.indices, target, seamLock, simplifier), target); };
    if (withinSlack(result, target) || !seams || (capping(ceiling, simplifier) && uncappedWithinSlack())) {
        std::vector<uint32_t> material(vc);  // weldPiece gives every vertex one material
        for (size_t t = 0; t < m.triangleCount(); ++t)
            for (int k = 0; k < 3; ++k) material[m.indices[3 * t + k]] = piece.materials[t];
        for (size_t t = 0; t < result.size() / 3; ++t) out.piece.materials.push_back(material[result[3 * t]]);
        out.piece.mesh = compact(m, result);
        return out;
    }
    // 2. Geometry only (the charts are too fragmented for the seams to follow): one vertex per
    // position, no texture coordinates; the caller bakes a new texture.
    MeshData geometry;
    geometry.positions.resize(3 * positions);
    meshopt_remapVertexBuffer(geometry.positions.data(), m.positions.data(), vc, 3 * sizeof(float), position.data());
    if (!m.colors.empty()) {
        geometry.colors.resize(4 * positions);
        meshopt_remapVertexBuffer(geometry.colors.data(), m.colors.data(), vc, 4, position.data());
    }
    std::vector<uint8_t> geometryLock(positions);
    for (size_t i = 0; i < vc; ++i) geometryLock[position[i]] |= lock[i];
    std::vector<uint32_t> indices(m.indices.size());
    meshopt_remapIndexBuffer(indices.data(), m.indices.data(), m.indices.size(), position.data());
    result = simplifyToTarget(geometry, indices, target, geometryLock, simplifier, &out.error, ceiling);
    out.piece.mesh = compact(geometry, result);
    out.piece.materials.assign(out.piece.mesh.triangleCount(), 0);
    out.geometryOnly = true;
    return out;
}

}  // namespace hlod
