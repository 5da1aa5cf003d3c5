// Welding a block before the §3.2 recursion (issue #16): real scans arrive as many chunks, one
// material (atlas) per chunk, each chunk with its own copy of its border vertices. Left apart,
// a chunk border is an open border of the surface: the simplifier either locks it (the chunk
// can never simplify below its outline) or pulls its two sides apart (holes). Welding makes it
// an interior edge whose two sides differ only in their attributes, an attribute seam
// (simplify.cpp).
//
// Rule (the input's precision as the database stores it): vertices closer than `epsilon` (half
// the block's position-lattice step, FORMAT.md §Geometry blobs: positions that close are at most
// one lattice step apart once encoded) move onto one position. A vertex on a face of the block's
// bounding box (where the block grid cut it, and where the neighbouring block has the same
// vertex) never moves, so blocks keep sharing their borders exactly; an interior vertex moves
// onto the first vertex within epsilon in index order (face vertices first), searched over the
// 27 hash cells of side epsilon around it. Triangles that become degenerate are dropped.
// Vertices are then split per material (a vertex serves one material), the normals dropped
// (packNode never stores them, and a normal seam would constrain the simplifier as a UV seam
// does), and identical vertices (position, UV, colour, material) merged.
#include "pipeline/pipeline.h"

#include <cmath>
#include <cstring>
#include <unordered_map>

namespace hlod {
namespace {

struct CellKey {
    int64_t x, y, z;
    bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
    size_t operator()(const CellKey& k) const {
        return size_t(k.x * 73856093) ^ size_t(k.y * 19349663) ^ size_t(k.z * 83492791);
    }
};

}  // namespace

Piece weldPiece(const Piece& piece, double epsilon) {
    const MeshData& m = piece.mesh;
    const size_t vc = m.vertexCount();
    std::vector<float> positions = m.positions;
    if (epsilon > 0) {
        const Box3f box = pieceBounds(m);
        const float lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
        auto onFace = [&](size_t i) {
            const float* p = &m.positions[3 * i];
            for (int a = 0; a < 3; ++a)
                if (p[a] == lo[a] || p[a] == hi[a]) return true;
            return false;
        };
        auto cell = [&](const float* p) {
            return CellKey{int64_t(std::floor(p[0] / epsilon)), int64_t(std::floor(p[1] / epsilon)),
                           int64_t(std::floor(p[2] / epsilon))};
        };
        std::unordered_map<CellKey, std::vector<uint32_t>, CellHash> grid;  // representatives per cell
        const double eps2 = epsilon * epsilon;
        for (int pass = 0; pass < 2; ++pass)  // face vertices first: they never move
            for (uint32_t i = 0; i < vc; ++i) {
                if (onFace(i) != (pass == 0)) continue;
                float* p = &positions[3 * i];
                const CellKey c = cell(p);
                uint32_t found = kNone;
                for (int64_t dx = -1; dx <= 1 && found == kNone; ++dx)
                    for (int64_t dy = -1; dy <= 1 && found == kNone; ++dy)
                        for (int64_t dz = -1; dz <= 1 && found == kNone; ++dz) {
                            auto it = grid.find({c.x + dx, c.y + dy, c.z + dz});
                            if (it == grid.end()) continue;
                            for (uint32_t r : it->second) {
                                const float* q = &positions[3 * r];
                                const double d = std::hypot(double(p[0]) - q[0], double(p[1]) - q[1], double(p[2]) - q[2]);
                                if (d * d < eps2 && (pass == 1 || std::memcmp(p, q, 3 * sizeof(float)) == 0)) {
                                    found = r;
                                    break;
                                }
                            }
                        }
                if (found == kNone) grid[c].push_back(i);
                else std::copy_n(&positions[3 * found], 3, p);
            }
    }
    // Corners keyed by (position, UV, colour, material): one vertex per key, first-use order.
    struct Key {
        float p[3], uv[2];
        uint8_t color[4];
        uint32_t material;
        bool operator==(const Key& o) const { return std::memcmp(this, &o, sizeof(Key)) == 0; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = 1469598103934665603ull;
            const auto* b = reinterpret_cast<const uint8_t*>(&k);
            for (size_t i = 0; i < sizeof(Key); ++i) h = (h ^ b[i]) * 1099511628211ull;
            return size_t(h);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> ids;
    Piece out;
    const bool uv = !m.texcoords.empty(), colors = !m.colors.empty();
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t* tri = &m.indices[3 * t];
        const float* a = &positions[3 * tri[0]];
        const float* b = &positions[3 * tri[1]];
        const float* c = &positions[3 * tri[2]];
        if (zeroArea(a, b, c)) continue;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = tri[k];
            Key key;
            std::memset(&key, 0, sizeof key);
            std::copy_n(&positions[3 * v], 3, key.p);
            if (uv) std::copy_n(&m.texcoords[2 * v], 2, key.uv);
            if (colors) std::copy_n(&m.colors[4 * v], 4, key.color);
            key.material = piece.materials[t];
            auto [it, fresh] = ids.try_emplace(key, static_cast<uint32_t>(out.mesh.vertexCount()));
            if (fresh) {
                out.mesh.positions.insert(out.mesh.positions.end(), key.p, key.p + 3);
                if (uv) out.mesh.texcoords.insert(out.mesh.texcoords.end(), key.uv, key.uv + 2);
                if (colors) out.mesh.colors.insert(out.mesh.colors.end(), key.color, key.color + 4);
            }
            out.mesh.indices.push_back(it->second);
        }
        out.materials.push_back(piece.materials[t]);
    }
    return out;
}

}  // namespace hlod
