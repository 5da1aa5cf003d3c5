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
// 27 hash cells of side epsilon around it. Triangles that become degenerate are dropped, and so
// are coincident copies of a triangle (firstOfCoincident).
// Vertices are then split per material (a vertex serves one material), the normals dropped
// (packNode never stores them, and a normal seam would constrain the simplifier as a UV seam
// does), and identical vertices (position, UV, colour, material) merged.
#include "pipeline/pipeline.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace hlod {
namespace {

// Per triangle: 1 unless it has no area or repeats an earlier one's three positions in the same
// winding (whatever its UVs or material). Coincident copies add nothing to draw, and each pile
// of them is a knot no bounding volume can split: 16,384 copies of one face took 24 s to build.
// Opposite windings (a two-sided wall) are kept.
std::vector<uint8_t> firstOfCoincident(const std::vector<float>& positions, const std::vector<uint32_t>& indices) {
    const size_t count = indices.size() / 3;
    std::vector<uint8_t> keep(count, 0);
    std::vector<std::array<float, 9>> keys;  // corners from the least (x, y, z) on, the winding kept
    std::vector<size_t> kept;
    keys.reserve(count), kept.reserve(count);
    for (size_t t = 0; t < count; ++t) {
        const float* c[3] = {&positions[3 * indices[3 * t]], &positions[3 * indices[3 * t + 1]], &positions[3 * indices[3 * t + 2]]};
        if (zeroArea(c[0], c[1], c[2])) continue;
        int first = 0;
        for (int k = 1; k < 3; ++k)
            if (std::lexicographical_compare(c[k], c[k] + 3, c[first], c[first] + 3)) first = k;
        std::array<float, 9>& key = keys.emplace_back();
        for (int k = 0; k < 3; ++k) std::copy_n(c[(first + k) % 3], 3, &key[3 * size_t(k)]);
        for (float& x : key) x += 0.0f;  // -0 as +0: the same position
        kept.push_back(t);
    }
    std::vector<uint32_t> remap(keys.size());  // first-use order: a new number marks the first of its kind
    meshopt_generateVertexRemap(remap.data(), nullptr, keys.size(), keys.data(), keys.size(), sizeof(keys[0]));
    for (uint32_t i = 0, next = 0; i < remap.size(); ++i)
        if (remap[i] == next) keep[kept[i]] = 1, ++next;
    return keep;
}

struct CellKey {
    int64_t x, y, z;
    bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

// The representatives of each occupied cell, in insertion order: an open-addressing table of
// cells (linear probing), each the head of a list threaded through `next` (std::unordered_map of
// vectors was a tenth of a bottom-up build). Cells are epsilon wide, far below the spacing of
// vertices, so nearly every one of the 27 cells searched is empty; a bit per cell hash in a
// table of 32-64 bits per vertex (a Bloom filter with one hash, Bloom 1970) answers most of them
// without touching the slots, whose random reads were ~90 % of the weld (pipeline/BUILD_SPEED.md).
class CellGrid {
public:
    // For vertices numbered below `vertices`, at most `cells` of them added.
    CellGrid(size_t vertices, size_t cells) : next_(vertices, kNone) {
        size_t capacity = 16;
        while (capacity < 2 * cells) capacity *= 2;
        slots_.resize(capacity);
        occupied_.resize(capacity / 4);  // 16 x capacity bits: 32 to 64 per vertex
    }
    // The first representative of cell c (kNone when empty); follow with next().
    uint32_t first(const CellKey& c) const {
        if (!(occupied_[filterBit(c) / 64] >> (filterBit(c) % 64) & 1)) return kNone;  // certainly empty
        for (size_t i = hash(c);; i = (i + 1) & (slots_.size() - 1)) {
            const Slot& s = slots_[i];
            if (s.head == kNone) return kNone;
            if (s.key == c) return s.head;
        }
    }
    uint32_t next(uint32_t r) const { return next_[r]; }
    void add(const CellKey& c, uint32_t r) {
        occupied_[filterBit(c) / 64] |= uint64_t{1} << (filterBit(c) % 64);
        for (size_t i = hash(c);; i = (i + 1) & (slots_.size() - 1)) {
            Slot& s = slots_[i];
            if (s.head == kNone) {
                s = {c, r, r};
                return;
            }
            if (s.key == c) {
                next_[s.tail] = r, s.tail = r;
                return;
            }
        }
    }

private:
    struct Slot {
        CellKey key{};
        uint32_t head = kNone, tail = kNone;
    };
    size_t hash(const CellKey& k) const {
        const uint64_t h = uint64_t(k.x) * 0x9E3779B97F4A7C15ull ^ uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full ^ uint64_t(k.z) * 0x165667B19E3779F9ull;
        return size_t(h ^ (h >> 29)) & (slots_.size() - 1);
    }
    size_t filterBit(const CellKey& k) const {  // another mix than hash(): independent of the slot
        const uint64_t h = (uint64_t(k.x) * 0xD6E8FEB86659FD93ull + uint64_t(k.y)) * 0xA0761D6478BD642Full + uint64_t(k.z);
        const uint64_t m = h * 0xE7037ED1A0B428DBull;
        return size_t(m ^ (m >> 32)) & (64 * occupied_.size() - 1);
    }
    std::vector<Slot> slots_;
    std::vector<uint64_t> occupied_;
    std::vector<uint32_t> next_;
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
        auto cell = [&](const float* p) {  // clamped: far from the origin a tiny epsilon would overflow int64
            auto index = [&](float x) { return int64_t(std::clamp(std::floor(x / epsilon), -0x1p62, 0x1p62)); };
            return CellKey{index(p[0]), index(p[1]), index(p[2])};
        };
        CellGrid grid(vc, vc);  // representatives per cell
        // Face vertices merge with exact copies only: looked up by their bits, not by scanning the
        // cells around them, which on a flat model coarser than its lattice hold thousands of face
        // vertices (a unit grid beside a triangle 10^6 away: 125,000 vertices in 11 CPU-s, quadratic).
        std::vector<uint8_t> face(vc);
        size_t faces = 0;
        for (uint32_t i = 0; i < vc; ++i) faces += face[i] = onFace(i);
        CellGrid copies(vc, faces);
        auto bits = [](const float* p) {
            uint32_t b[3];
            std::memcpy(b, p, sizeof b);
            return CellKey{b[0], b[1], b[2]};
        };
        const double eps2 = epsilon * epsilon;
        for (int pass = 0; pass < 2; ++pass)  // face vertices first: they never move
            for (uint32_t i = 0; i < vc; ++i) {
                if (face[i] != (pass == 0)) continue;
                float* p = &positions[3 * i];
                const CellKey c = cell(p);
                if (pass == 0) {
                    if (copies.first(bits(p)) == kNone) copies.add(bits(p), i), grid.add(c, i);
                    continue;
                }
                uint32_t found = kNone;
                for (int64_t dx = -1; dx <= 1 && found == kNone; ++dx)
                    for (int64_t dy = -1; dy <= 1 && found == kNone; ++dy)
                        for (int64_t dz = -1; dz <= 1 && found == kNone; ++dz)
                            for (uint32_t r = grid.first({c.x + dx, c.y + dy, c.z + dz}); r != kNone; r = grid.next(r)) {
                                const float* q = &positions[3 * r];
                                const double d = std::hypot(double(p[0]) - q[0], double(p[1]) - q[1], double(p[2]) - q[2]);
                                if (d * d < eps2) {
                                    found = r;
                                    break;
                                }
                            }
                if (found == kNone) grid.add(c, i);
                else std::copy_n(&positions[3 * found], 3, p);
            }
    }
    // Corners keyed by (position, UV, colour, material): one vertex per key, first-use order (the
    // order meshoptimizer's remap numbers the corners in).
    struct Key {
        float p[3], uv[2];
        uint8_t color[4];
        uint32_t material;
    };
    static_assert(sizeof(Key) == 28, "compared as bytes: no padding");
    const bool uv = !m.texcoords.empty(), colors = !m.colors.empty();
    const std::vector<uint8_t> keep = firstOfCoincident(positions, m.indices);
    std::vector<Key> corners;
    corners.reserve(m.indices.size());
    Piece out;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t* tri = &m.indices[3 * t];
        if (!keep[t]) continue;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = tri[k];
            Key key;
            std::memset(&key, 0, sizeof key);
            std::copy_n(&positions[3 * v], 3, key.p);
            if (uv) std::copy_n(&m.texcoords[2 * v], 2, key.uv);
            if (colors) std::copy_n(&m.colors[4 * v], 4, key.color);
            key.material = piece.materials[t];
            corners.push_back(key);
        }
        out.materials.push_back(piece.materials[t]);
    }
    out.mesh.indices.resize(corners.size());
    const size_t unique = meshopt_generateVertexRemap(out.mesh.indices.data(), nullptr, corners.size(), corners.data(), corners.size(), sizeof(Key));
    std::vector<Key> vertices(unique);
    meshopt_remapVertexBuffer(vertices.data(), corners.data(), corners.size(), sizeof(Key), out.mesh.indices.data());
    for (const Key& key : vertices) {
        out.mesh.positions.insert(out.mesh.positions.end(), key.p, key.p + 3);
        if (uv) out.mesh.texcoords.insert(out.mesh.texcoords.end(), key.uv, key.uv + 2);
        if (colors) out.mesh.colors.insert(out.mesh.colors.end(), key.color, key.color + 4);
    }
    return out;
}

}  // namespace hlod
