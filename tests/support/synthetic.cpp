// Test fixture (synthetic.h): a grid of blocks over a wavy terrain; in each block level L has
// levelFactor^L grid patches that tile their parent (cut along the longest axis, as thesis
// §3.2). Cost/benefit/normal come from metrics.h and eq. 3.1 (the Writer), bounds enclose the
// subtree, and the geometric error is the linear-interpolation bound h^2/8 * |f''| (capped by
// the terrain's height range).
#include "tests/support/synthetic.h"

#include "formats/codec.h"
#include "formats/constants.h"
#include "formats/db.h"
#include "formats/metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hlod {

namespace {

struct Rect {
    float x0, y0, x1, y1;
};

struct Terrain {
    float amplitude, fx, fy, phase;
    float height(float x, float y) const {
        return amplitude * (std::sin(x * fx + phase) * std::cos(y * fy) + 0.3f * std::sin((x + y) * fx * 2.3f));
    }
    float maxDeviation() const { return 2 * 1.3f * amplitude; }  // height range: no error exceeds it
    float maxCurvature() const {  // bound on |second derivative| along any direction
        return amplitude * (fx * fx + fy * fy + 0.3f * 2 * (fx * 2.3f) * (fx * 2.3f));
    }
};

struct Patch {
    Rect rect;
    uint32_t level;
    MeshData mesh;
    Box3f bounds;
    std::vector<Patch> children;
};

// Splits a rectangle into k pieces: halves along the longest axis while k is even, else k strips.
void split(const Rect& r, uint32_t k, std::vector<Rect>& out) {
    bool alongX = r.x1 - r.x0 >= r.y1 - r.y0;
    uint32_t pieces = k % 2 == 0 ? 2 : k;
    for (uint32_t i = 0; i < pieces; ++i) {
        float a = float(i) / float(pieces), b = float(i + 1) / float(pieces);
        Rect c = alongX ? Rect{r.x0 + (r.x1 - r.x0) * a, r.y0, r.x0 + (r.x1 - r.x0) * b, r.y1}
                        : Rect{r.x0, r.y0 + (r.y1 - r.y0) * a, r.x1, r.y0 + (r.y1 - r.y0) * b};
        if (pieces == k) out.push_back(c);
        else split(c, k / 2, out);
    }
}

MeshData gridMesh(const Rect& r, uint32_t cells, const Terrain& t, bool colours) {
    MeshData m;
    for (uint32_t j = 0; j <= cells; ++j)
        for (uint32_t i = 0; i <= cells; ++i) {
            float u = float(i) / float(cells), v = float(j) / float(cells);
            float x = r.x0 + (r.x1 - r.x0) * u, y = r.y0 + (r.y1 - r.y0) * v, z = t.height(x, y);
            m.positions.insert(m.positions.end(), {x, y, z});
            m.texcoords.insert(m.texcoords.end(), {u, v});
            if (colours) {
                auto shade = uint8_t(std::clamp(128.0f + 127.0f * z / t.amplitude / 1.3f, 0.0f, 255.0f));
                m.colors.insert(m.colors.end(), {shade, uint8_t(160), uint8_t(255 - shade), uint8_t(255)});
            }
        }
    for (uint32_t j = 0; j < cells; ++j)
        for (uint32_t i = 0; i < cells; ++i) {
            uint32_t a = j * (cells + 1) + i, b = a + 1, c = a + cells + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    if (colours) m.texcoords.clear();
    return m;
}

// Procedural texture in world coordinates (seamless across patches): height bands + a grid.
Image patchImage(const Rect& r, uint32_t size, const Terrain& t) {
    Image img{size, size, 3, std::vector<uint8_t>(size_t(size) * size * 3)};
    for (uint32_t j = 0; j < size; ++j)
        for (uint32_t i = 0; i < size; ++i) {
            float x = r.x0 + (r.x1 - r.x0) * (i + 0.5f) / float(size);
            float y = r.y0 + (r.y1 - r.y0) * (j + 0.5f) / float(size);
            float h = t.height(x, y) / t.amplitude;
            bool line = std::fmod(std::abs(x), 10.0f) < 0.4f || std::fmod(std::abs(y), 10.0f) < 0.4f;
            uint8_t* p = &img.pixels[(size_t(j) * size + i) * 3];
            p[0] = uint8_t(line ? 240 : 90 + 50 * h);
            p[1] = uint8_t(line ? 240 : 140 + 60 * h);
            p[2] = uint8_t(line ? 240 : 70 - 30 * h);
        }
    return img;
}

Box3f unite(Box3f a, const Box3f& b) {
    a.min = {std::min(a.min.x, b.min.x), std::min(a.min.y, b.min.y), std::min(a.min.z, b.min.z)};
    a.max = {std::max(a.max.x, b.max.x), std::max(a.max.y, b.max.y), std::max(a.max.z, b.max.z)};
    return a;
}

// Builds the patch tree; a patch's bounds enclose its own mesh and all its descendants.
Patch buildPatch(const Rect& r, uint32_t level, const SyntheticOptions& o, const Terrain& t, uint32_t cells) {
    Patch p{r, level, gridMesh(r, cells, t, o.textureSize == 0), {}, {}};
    p.bounds = surfaceMetrics(std::span(&p.mesh, 1)).bounds;
    if (level + 1 < o.levels) {
        std::vector<Rect> rects;
        split(r, o.levelFactor, rects);
        for (const Rect& c : rects) {
            p.children.push_back(buildPatch(c, level + 1, o, t, cells));
            p.bounds = unite(p.bounds, p.children.back().bounds);
        }
    }
    return p;
}

void writePatch(Writer& w, const Patch& p, uint32_t parent, uint32_t block, const SyntheticOptions& o,
                const Terrain& t, uint32_t cells) {
    NodeInput in;
    in.parent = parent;
    in.level = p.level;
    in.block = block;
    in.bounds = p.bounds;
    SurfaceMetrics sm = surfaceMetrics(std::span(&p.mesh, 1));
    in.staticBenefit = sm.staticBenefit;
    in.avgNormal = sm.avgNormal;
    float h = std::max(p.rect.x1 - p.rect.x0, p.rect.y1 - p.rect.y0) / float(cells);
    in.geometricError = p.level + 1 == o.levels ? 0.0f : std::min(h * h / 8 * t.maxCurvature(), t.maxDeviation());
    if (o.textureSize > 0) {
        in.blobs.push_back(encodeTexture(patchImage(p.rect, o.textureSize, t), Codec::Jpeg, 85));
        in.blobs.push_back(encodeGeometry(p.mesh, DracoOptions{}));
        in.blobs.back().textureSlot = 0;
    } else {
        in.blobs.push_back(encodeGeometry(p.mesh, DracoOptions{}));
    }
    uint32_t id = w.addNode(std::move(in));
    for (const Patch& c : p.children) writePatch(w, c, id, block, o, t, cells);
}

}  // namespace

void writeSyntheticDatabase(const std::string& path, const SyntheticOptions& o) {
    if (o.blocksX == 0 || o.blocksY == 0 || o.levels == 0 || o.levels > 12 || o.levelFactor < 2 ||
        o.trianglesPerNode < 2 || !(o.blockSize > 0))
        throw std::runtime_error("writeSyntheticDatabase: bad options");
    const auto cells = std::max<uint32_t>(1, uint32_t(std::lround(std::sqrt(o.trianglesPerNode / 2.0))));
    const Terrain terrain{o.blockSize * 0.05f, 6.2831853f / (o.blockSize * 0.7f), 6.2831853f / (o.blockSize * 0.9f),
                          float(o.seed) * 0.7f};
    Constants c;
    c.desiredTris = 2.0 * cells * cells;
    c.levelFactor = o.levelFactor;
    Writer w(path, c.textured);
    w.setMeta("tool", "hlod writeSyntheticDatabase");
    w.setMeta("input", "synthetic wavy terrain, seed " + std::to_string(o.seed));
    for (const auto& [name, value] : constantsAsPairs(c)) w.setMeta(name, value);
    for (uint32_t by = 0; by < o.blocksY; ++by)
        for (uint32_t bx = 0; bx < o.blocksX; ++bx) {
            Rect r{bx * o.blockSize, by * o.blockSize, (bx + 1) * o.blockSize, (by + 1) * o.blockSize};
            writePatch(w, buildPatch(r, 0, o, terrain, cells), kNone, by * o.blocksX + bx, o, terrain, cells);
        }
    w.finish();
}

Image smoothTexture(uint32_t size, int seed) {
    Image img{size, size, 3, {}};
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const double u = double(x) / size, v = double(y) / size;
            img.pixels.push_back(static_cast<uint8_t>(127.5 + 120 * std::sin(6.0 * u + seed)));
            img.pixels.push_back(static_cast<uint8_t>(127.5 + 120 * std::cos(5.0 * v - seed)));
            img.pixels.push_back(static_cast<uint8_t>(127.5 + 120 * std::sin(4.0 * (u + v) + 2 * seed)));
        }
    return img;
}

}  // namespace hlod
