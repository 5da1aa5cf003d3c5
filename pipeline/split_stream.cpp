// Out-of-core block split: the input is streamed once into per-block temporary storage and not
// held whole beyond the parse's budget. One pass over the parsed triangles (in memory, or read
// from the RawMesh spill files) copies
// each triangle to every grid cell its bounds reach, through per-cell buffers of bounded total
// size flushed to one file per cell. Each cell is then welded and clipped to its rectangle by the
// same Fig. 3.2 plane cuts, in the same order, as splitByGrid, so the blocks are those of the
// in-memory split: the cut vertices depend only on the edge, so neighbouring cells share them.
#include "pipeline/pipeline.h"

#include <algorithm>
#include <filesystem>

namespace hlod {
namespace {

namespace fs = std::filesystem;

// Every 2^20 triangles the attribute arrays' mapped pages are dropped (issue #14: a 17 M
// triangle input's positions stayed resident, 80 MiB over a 215 MiB --memory-limit); those still
// needed come back from the page cache.
constexpr size_t kAttributeRelease = (size_t{1} << 20) - 1;

struct Layout {
    bool texcoords, normals, colors;
    size_t bytesPerTriangle() const {
        return 3 * (12 + (texcoords ? 8 : 0) + (normals ? 12 : 0) + (colors ? 4 : 0) + 4) + 4;
    }
};

std::vector<float> planes(const GridSpec& g, bool alongV) {
    std::vector<float> out;
    for (uint32_t k = 1; k < (alongV ? g.cellsV : g.cellsU); ++k) out.push_back(gridPlane(g, alongV, k));
    return out;
}

void addCorner(Piece& soup, const Corner& c, const Layout& layout) {
    MeshData& m = soup.mesh;
    m.indices.push_back(static_cast<uint32_t>(m.vertexCount()));
    m.positions.insert(m.positions.end(), c.position, c.position + 3);
    if (layout.texcoords) m.texcoords.insert(m.texcoords.end(), c.texcoord, c.texcoord + 2);
    if (layout.normals) m.normals.insert(m.normals.end(), c.normal, c.normal + 3);
    if (layout.colors) m.colors.insert(m.colors.end(), c.color, c.color + 4);
}

// The cells [first, last] along one axis whose slab can receive part of [lo, hi] under
// cutPiece's rule (x <= plane goes below).
std::pair<uint32_t, uint32_t> cellRange(const std::vector<float>& planes, float lo, float hi) {
    const auto first = std::lower_bound(planes.begin(), planes.end(), lo) - planes.begin();
    const auto last = std::lower_bound(planes.begin(), planes.end(), hi) - planes.begin();
    return {static_cast<uint32_t>(first), static_cast<uint32_t>(last)};
}

Piece clipToCell(Piece piece, const GridSpec& g, const std::vector<float>& pu, const std::vector<float>& pv, uint32_t u,
                 uint32_t v) {
    if (u > 0) piece = std::move(cutPiece(piece, g.axisU, pu[u - 1]).above);
    if (u + 1 < g.cellsU) piece = std::move(cutPiece(piece, g.axisU, pu[u]).below);
    if (v > 0) piece = std::move(cutPiece(piece, g.axisV, pv[v - 1]).above);
    if (v + 1 < g.cellsV) piece = std::move(cutPiece(piece, g.axisV, pv[v]).below);
    return piece;
}

}  // namespace

std::vector<CellFile> streamSplit(const RawMesh& raw, const GridSpec& grid, const std::string& dir, uint64_t bufferBytes,
                                  const std::string& name, ReadStats& stats, Progress* progress) {
    const Layout layout{raw.hasTexcoords, raw.hasNormals, raw.colors.size() == 4 * raw.positionCount()};
    const std::vector<float> pu = planes(grid, false), pv = planes(grid, true);
    const size_t cells = static_cast<size_t>(grid.cellsU) * grid.cellsV;
    const size_t flushAt = std::max<uint64_t>(bufferBytes / cells, 64 << 10) / layout.bytesPerTriangle() + 1;
    auto soupFile = [&](size_t c) { return (fs::path(dir) / ("cell_" + std::to_string(c) + ".soup")).string(); };
    for (size_t c = 0; c < cells; ++c) fs::remove(soupFile(c));
    std::vector<Piece> buffers(cells);
    std::vector<uint64_t> routed(cells);
    auto flush = [&](size_t c) {
        appendPiece(soupFile(c), buffers[c]);
        buffers[c] = {};
    };
    Corner corner[3];
    uint64_t kept = 0;
    for (size_t t = 0; t < raw.triangles.size(); ++t) {
        if ((t & 0xFFFF) == 0xFFFF) {
            if (raw.texcoordsPerCorner)  // a PLY's face UVs are read once, in order, too
                raw.texcoords.release(2 * size_t(raw.triangles[t - 0xFFFF].texcoord[0]), 2 * size_t(raw.triangles[t].texcoord[0]));
            raw.triangles.release(t - 0xFFFF, t + 1);  // read once, in order: keep them out of the RSS
            if (progress) progress->advance(0x10000);
        }
        if ((t & kAttributeRelease) == kAttributeRelease) {  // read at random: pages touched so far leave the RSS
            raw.positions.release(0, raw.positions.size()), raw.texcoords.release(0, raw.texcoords.size());
            raw.normals.release(0, raw.normals.size()), raw.colors.release(0, raw.colors.size());
        }
        if (!rawCorners(raw, t, corner, name)) {
            ++stats.degenerateDropped;
            continue;
        }
        ++kept;
        auto extent = [&](int axis) {
            const float a = corner[0].position[axis], b = corner[1].position[axis], c = corner[2].position[axis];
            return std::pair{std::min({a, b, c}), std::max({a, b, c})};
        };
        const auto [u0, u1] = extent(grid.axisU);
        const auto [v0, v1] = extent(grid.axisV);
        const auto [ufirst, ulast] = cellRange(pu, u0, u1);
        const auto [vfirst, vlast] = cellRange(pv, v0, v1);
        for (uint32_t v = vfirst; v <= vlast; ++v)
            for (uint32_t u = ufirst; u <= ulast; ++u) {
                const size_t c = static_cast<size_t>(v) * grid.cellsU + u;
                for (const Corner& k : corner) addCorner(buffers[c], k, layout);
                buffers[c].materials.push_back(raw.triangles[t].material == kNone
                                                   ? static_cast<uint32_t>(raw.materials.size() - 1)
                                                   : raw.triangles[t].material);
                if (++routed[c] % flushAt == 0) flush(c);
            }
    }
    if (progress) progress->advance(raw.triangles.size() & 0xFFFF);  // the last, partial chunk
    if (kept == 0) throw InputError(name + ": empty mesh (no valid triangles)");
    std::vector<CellFile> out;
    for (size_t c = 0; c < cells; ++c) {
        if (routed[c] == 0) continue;
        if (!buffers[c].materials.empty()) flush(c);
        Piece cell = clipToCell(loadPiece(soupFile(c)), grid, pu, pv, static_cast<uint32_t>(c % grid.cellsU),
                                static_cast<uint32_t>(c / grid.cellsU));
        fs::remove(soupFile(c));
        if (cell.mesh.triangleCount() == 0) continue;
        const std::string file = (fs::path(dir) / ("cell_" + std::to_string(c) + ".piece")).string();
        fs::remove(file);
        appendPiece(file, cell);
        out.push_back({static_cast<uint32_t>(c), file, cell.mesh.triangleCount()});
    }
    return out;
}

}  // namespace hlod
