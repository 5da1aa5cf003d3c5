// Simplification of thesis §3.2 ("Qslim ... with a metric such that the number of triangles
// decrease by a factor"): quadric error metrics down to triangleCount / factor, with every open
// border locked so piece cuts and material seams keep their vertices and neighbouring nodes of
// any level meet without cracks. Both simplifiers only collapse edges onto existing vertices, so
// texture coordinates stay exact. meshoptimizer (default, ~1.4 M tri/s) or OpenMesh's Decimater
// with ModQuadric (~50 k tri/s, selectable with --simplifier openmesh).
#include "pipeline/pipeline.h"

#include <meshoptimizer.h>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <cfloat>
#include <cmath>

namespace hlod {
namespace {

// Keeps only the vertices `indices` use, in first-use order.
MeshData compact(const MeshData& mesh, const std::vector<uint32_t>& indices) {
    MeshData out;
    std::vector<uint32_t> remap(mesh.vertexCount(), kNone);
    for (uint32_t i : indices) {
        if (remap[i] == kNone) {
            remap[i] = static_cast<uint32_t>(out.vertexCount());
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

std::vector<uint32_t> simplifyMeshopt(const MeshData& mesh, size_t targetTriangles) {
    std::vector<uint32_t> out(mesh.indices.size());
    const size_t n = meshopt_simplify(out.data(), mesh.indices.data(), mesh.indices.size(), mesh.positions.data(),
                                      mesh.vertexCount(), 3 * sizeof(float), targetTriangles * 3, FLT_MAX,
                                      meshopt_SimplifyLockBorder, nullptr);
    out.resize(n);
    return out;
}

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

std::vector<uint32_t> simplifyOpenMesh(const MeshData& mesh, size_t targetTriangles) {
    OMesh om;
    om.request_vertex_status(), om.request_edge_status(), om.request_face_status();
    std::vector<OMesh::VertexHandle> handles(mesh.vertexCount());
    for (size_t i = 0; i < handles.size(); ++i)
        handles[i] = om.add_vertex({mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]});
    std::vector<uint32_t> out;  // faces OpenMesh refuses (non-manifold) are kept unsimplified
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t* tri = &mesh.indices[3 * t];
        if (!om.add_face(handles[tri[0]], handles[tri[1]], handles[tri[2]]).is_valid())
            out.insert(out.end(), tri, tri + 3);
    }
    for (auto vh : om.vertices())
        if (om.is_boundary(vh)) om.status(vh).set_locked(true);
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

std::vector<SubMesh> splitByMaterial(const Piece& piece) {
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
    for (uint32_t m = 0; m < slot.size(); ++m)
        if (slot[m] != kNone) parts.push_back({m, compact(piece.mesh, indices[slot[m]])});
    return parts;
}

MeshData simplifyMesh(const MeshData& mesh, double factor, Simplifier simplifier) {
    if (factor <= 1 || mesh.triangleCount() < 2) return mesh;
    const size_t target = std::max<size_t>(1, static_cast<size_t>(std::llround(mesh.triangleCount() / factor)));
    return compact(mesh, simplifier == Simplifier::Meshopt ? simplifyMeshopt(mesh, target) : simplifyOpenMesh(mesh, target));
}

}  // namespace hlod
