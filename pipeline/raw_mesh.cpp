// The parsed-but-not-welded mesh shared by the PLY and OBJ readers: attributes
// are checked as they arrive, triangles keep their per-corner attribute indices, and the whole
// thing either becomes an indexed SourceMesh (a block file) or is streamed to the block grid
// from memory or, beyond a budget, from its spill files (split_stream.cpp), so a large input is
// never held whole.
#include "pipeline/pipeline.h"

#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <unordered_map>

namespace hlod {
namespace {

void checkFinite(const float* v, int n, size_t index, const char* what, const std::string& name) {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) throw InputError(name + ": vertex " + std::to_string(index) + " has a NaN/Inf " + what);
}

void checkCoordinates(const float* p, size_t index, const std::string& name) {
    checkFinite(p, 3, index, "coordinate", name);
    for (int i = 0; i < 3; ++i)
        if (std::abs(p[i]) > kMaxCoordinate) throw InputError(name + ": vertex " + std::to_string(index) + " has a coordinate beyond 1e15 (the limit)");
}

[[noreturn]] void outOfRange(size_t t, const char* what, uint32_t index, size_t count, const std::string& name) {
    throw InputError(name + ": triangle " + std::to_string(t) + " uses " + what + " " + std::to_string(index) +
                     " but there are only " + std::to_string(count));
}

// A corner's position and normal indices and its texture coordinate: its index (u; v = 0), or
// with texcoordsPerCorner its value's bits.
struct CornerKey {
    uint32_t p, u, v, n;
    bool operator==(const CornerKey&) const = default;
};
struct CornerHash {
    size_t operator()(const CornerKey& k) const {
        return (static_cast<size_t>(k.p) * 73856093u) ^ (static_cast<size_t>(k.u) * 19349663u) ^
               (static_cast<size_t>(k.v) * 2654435761u) ^ (static_cast<size_t>(k.n) * 83492791u);
    }
};
uint32_t materialOf(const RawMesh& raw, const RawTriangle& t) {
    return t.material == kNone ? static_cast<uint32_t>(raw.materials.size() - 1) : t.material;
}

// The triangle's material when it moves texture coordinates (Material::uvScale, uvOffset), else null.
const Material* movingUvs(const RawMesh& raw, const RawTriangle& t) {
    if (!raw.hasTexcoords || raw.texcoordsPerCorner || raw.materials.empty()) return nullptr;
    const Material& m = raw.materials[materialOf(raw, t)];
    return m.movesUvs() ? &m : nullptr;
}

CornerKey cornerKey(const RawMesh& raw, const RawTriangle& tri, const Corner& corner, int c) {
    CornerKey key{tri.position[c], 0, 0, raw.hasNormals ? tri.normal[c] : 0};
    if (raw.texcoordsPerCorner && raw.hasTexcoords) key.u = std::bit_cast<uint32_t>(corner.texcoord[0]), key.v = std::bit_cast<uint32_t>(corner.texcoord[1]);
    else if (raw.hasTexcoords) key.u = tri.texcoord[c];
    // A vt that two materials move apart (map_Kd -s/-o) is two texture coordinates.
    if (movingUvs(raw, tri)) key.v = materialOf(raw, tri) + 1;
    return key;
}

// A PLY: the vertex arrays are already indexed by the triangles.
void copyIndexed(const RawMesh& raw, SourceMesh& out) {
    MeshData& m = out.piece.mesh;
    m.positions.assign(raw.positions.data(), raw.positions.data() + raw.positions.size());
    if (raw.hasTexcoords) m.texcoords.assign(raw.texcoords.data(), raw.texcoords.data() + raw.texcoords.size());
    if (raw.hasNormals) m.normals.assign(raw.normals.data(), raw.normals.data() + raw.normals.size());
    m.colors.assign(raw.colors.data(), raw.colors.data() + raw.colors.size());
    for (size_t t = 0; t < raw.triangles.size(); ++t) {
        const RawTriangle& tri = raw.triangles[t];
        m.indices.insert(m.indices.end(), tri.position, tri.position + 3);
        out.piece.materials.push_back(materialOf(raw, tri));
    }
}

// An OBJ, or a PLY with per-face texture coordinates: corners welded by their (position,
// texcoord, normal) index triple (the PLY's: by the texcoord's value), in first-use order;
// colours are the positions'.
void weldCorners(const RawMesh& raw, SourceMesh& out, const std::string& name) {
    MeshData& m = out.piece.mesh;
    const bool colors = raw.colors.size() == 4 * raw.positionCount() && raw.positionCount() > 0;
    std::unordered_map<CornerKey, uint32_t, CornerHash> ids;
    Corner corner[3];
    for (size_t t = 0; t < raw.triangles.size(); ++t) {
        const RawTriangle& tri = raw.triangles[t];
        rawCorners(raw, t, corner, name);  // range checks; degenerate ones are dropped by sanitize
        for (int c = 0; c < 3; ++c) {
            auto [it, added] = ids.try_emplace(cornerKey(raw, tri, corner[c], c), static_cast<uint32_t>(m.vertexCount()));
            if (added) {
                m.positions.insert(m.positions.end(), corner[c].position, corner[c].position + 3);
                if (raw.hasTexcoords) m.texcoords.insert(m.texcoords.end(), corner[c].texcoord, corner[c].texcoord + 2);
                if (raw.hasNormals) m.normals.insert(m.normals.end(), corner[c].normal, corner[c].normal + 3);
                if (colors) m.colors.insert(m.colors.end(), corner[c].color, corner[c].color + 4);
            }
            m.indices.push_back(it->second);
        }
        out.piece.materials.push_back(materialOf(raw, tri));
    }
}

}  // namespace

size_t readBufferBytes(std::FILE* file) {
    constexpr size_t kMax = size_t(1) << 20, kMin = 4096;
    struct stat st {};
    if (fstat(fileno(file), &st) != 0 || !S_ISREG(st.st_mode)) return kMax;
    return std::clamp(static_cast<size_t>(st.st_size) + 1, kMin, kMax);
}

void RawMesh::spillTo(const std::string& dir) {
    const std::filesystem::path d(dir);
    positions.spillTo((d / "positions.raw").string());
    texcoords.spillTo((d / "texcoords.raw").string());
    normals.spillTo((d / "normals.raw").string());
    colors.spillTo((d / "colors.raw").string());
    triangles.spillTo((d / "triangles.raw").string());
}

namespace {
// spillBeyond: the arrays go to files once their capacity passes half the budget (checked as
// positions and triangles arrive; colours grow with positions, texture coordinates and normals at
// most so). Half: an array that doubles holds its old and its new storage for a moment, so the
// memory touched stays within the budget (the whole budget let the 17 M terrain's parse peak
// 19 MiB above its split; pipeline/MEMORY.md).
void spillWhenOver(RawMesh& raw) {
    if (raw.spillDir.empty() || raw.positions.spilled()) return;
    const uint64_t held = raw.positions.heldBytes() + raw.texcoords.heldBytes() + raw.normals.heldBytes() +
                          raw.colors.heldBytes() + raw.triangles.heldBytes();
    if (held > raw.spillBudget / 2) raw.spillTo(raw.spillDir);
}
}  // namespace

void RawMesh::addTriangle(const RawTriangle& t) {
    triangles.push(&t, 1);
    spillWhenOver(*this);
}

void RawMesh::addPosition(const double q[3], const std::string& name) {
    const float p[3] = {static_cast<float>(q[0] - offset[0]), static_cast<float>(q[1] - offset[1]), static_cast<float>(q[2] - offset[2])};
    checkCoordinates(p, positionCount(), name);
    positions.push(p, 3);
    spillWhenOver(*this);
    bounds.min = {std::min(bounds.min.x, p[0]), std::min(bounds.min.y, p[1]), std::min(bounds.min.z, p[2])};
    bounds.max = {std::max(bounds.max.x, p[0]), std::max(bounds.max.y, p[1]), std::max(bounds.max.z, p[2])};
}

void RawMesh::addTexcoord(float u, float v, const std::string& name) {
    const float uv[2] = {u, v};
    checkFinite(uv, 2, texcoords.size() / 2, "texture coordinate", name);
    texcoords.push(uv, 2);
}

void RawMesh::addNormal(const float n[3], const std::string& name) {
    checkFinite(n, 3, normals.size() / 3, "normal", name);
    normals.push(n, 3);
}

void RawMesh::seal() {
    positions.seal(), texcoords.seal(), normals.seal(), colors.seal(), triangles.seal();
    if (hasTexcoords && texcoords.size() == 0) hasTexcoords = false;
    if (hasNormals && normals.size() == 0) hasNormals = false;
}

// RawMesh::bounds holds every position read. One vertex no triangle used, far off (an outlier a
// cleaning step left unreferenced), set the block grid and the position lattice until stop 47: a
// 1.4 M-triangle grid with one stray vertex at 1e5 became one block, its lattice step as coarse.
// RawMesh::bounds itself when every vertex is used (the bytes of every such database kept).
Box3f usedBounds(const RawMesh& raw) {
    const size_t n = raw.positionCount();
    std::vector<bool> used(n);
    size_t count = 0;
    for (size_t t = 0; t < raw.triangles.size(); ++t)
        for (const uint32_t p : raw.triangles[t].position)
            if (p < n && !used[p]) used[p] = true, ++count;
    if (count == n || count == 0) return raw.bounds;  // none: every index out of range, which rawCorners says
    Box3f b{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    for (size_t v = 0; v < n; ++v) {
        if (!used[v]) continue;
        const float* p = &raw.positions[3 * v];
        b.min = {std::min(b.min.x, p[0]), std::min(b.min.y, p[1]), std::min(b.min.z, p[2])};
        b.max = {std::max(b.max.x, p[0]), std::max(b.max.y, p[1]), std::max(b.max.z, p[2])};
    }
    return b;
}

bool rawCorners(const RawMesh& raw, size_t t, Corner out[3], const std::string& name) {
    const RawTriangle& tri = raw.triangles[t];
    const size_t positions = raw.positionCount(), texcoords = raw.texcoords.size() / 2, normals = raw.normals.size() / 3;
    const bool colors = raw.colors.size() == 4 * positions && positions > 0;
    const Material* moving = movingUvs(raw, tri);
    for (int c = 0; c < 3; ++c) {
        const uint32_t p = tri.position[c];
        if (p >= positions) outOfRange(t, "vertex", p, positions, name);
        std::copy_n(&raw.positions[3 * size_t(p)], 3, out[c].position);
        if (raw.hasTexcoords) {
            if (tri.texcoord[c] == kNone) out[c].texcoord[0] = out[c].texcoord[1] = 0;  // an OBJ face without `vt` (read_obj.cpp)
            else if (tri.texcoord[c] >= texcoords) outOfRange(t, "texture coordinate", tri.texcoord[c], texcoords, name);
            else std::copy_n(&raw.texcoords[2 * size_t(tri.texcoord[c])], 2, out[c].texcoord);
            if (moving)
                for (int a = 0; a < 2; ++a) out[c].texcoord[a] = out[c].texcoord[a] * moving->uvScale[a] + moving->uvOffset[a];
        }
        if (raw.hasNormals) {
            if (tri.normal[c] >= normals) outOfRange(t, "normal", tri.normal[c], normals, name);
            std::copy_n(&raw.normals[3 * size_t(tri.normal[c])], 3, out[c].normal);
        }
        if (colors) std::copy_n(&raw.colors[4 * size_t(p)], 4, out[c].color);
    }
    const uint32_t* p = tri.position;
    return p[0] != p[1] && p[1] != p[2] && p[0] != p[2] && !zeroArea(out[0].position, out[1].position, out[2].position);
}

SourceMesh toSourceMesh(const RawMesh& raw, const std::string& name) {
    SourceMesh out;
    out.materials = raw.materials;
    out.stats = raw.stats;
    if (raw.sharedIndices) copyIndexed(raw, out);
    else weldCorners(raw, out, name);
    sanitize(out, name);
    return out;
}

}  // namespace hlod
