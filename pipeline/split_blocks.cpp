// Splitting one large mesh into blocks (thesis §3.2: the acquired city "is split up into
// blocks"): a grid over the two longest axes of the input bounds (the horizontal ones for a scan
// of terrain or a city), cut with the Fig. 3.2 plane cut so blocks tile the input exactly and
// share their border vertices. splitByGrid is the in-memory form (glTF input, which tinygltf
// reads whole); split_stream.cpp is the out-of-core form for PLY and OBJ. Each block goes to its
// own temporary file (appendPiece) so the per-block stages never hold more than one block.
#include "pipeline/pipeline.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

namespace hlod {
namespace {

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

template <class T>
void put(std::FILE* f, const std::vector<T>& v, const std::string& file) {
    if (!v.empty() && std::fwrite(v.data(), sizeof(T), v.size(), f) != v.size())
        throw std::runtime_error(file + ": write failed (" + std::strerror(errno) + ")");
}

template <class T>
bool get(std::FILE* f, std::vector<T>& v, size_t n) {
    v.resize(n);
    return n == 0 || std::fread(v.data(), sizeof(T), n, f) == n;
}

// Joins identical vertices (all attributes equal) so chunk borders are not open borders.
void weld(Piece& piece) {
    MeshData& m = piece.mesh;
    const size_t vc = m.vertexCount();
    const size_t floats = 3 + (m.texcoords.empty() ? 0 : 2) + (m.normals.empty() ? 0 : 3) + (m.colors.empty() ? 0 : 1);
    std::vector<float> interleaved(vc * floats);
    for (size_t i = 0; i < vc; ++i) {
        float* o = &interleaved[i * floats];
        std::memcpy(o, &m.positions[3 * i], 12), o += 3;
        if (!m.texcoords.empty()) std::memcpy(o, &m.texcoords[2 * i], 8), o += 2;
        if (!m.normals.empty()) std::memcpy(o, &m.normals[3 * i], 12), o += 3;
        if (!m.colors.empty()) std::memcpy(o, &m.colors[4 * i], 4);
    }
    std::vector<unsigned int> remap(vc);
    const size_t unique = meshopt_generateVertexRemap(remap.data(), m.indices.data(), m.indices.size(), interleaved.data(),
                                                      vc, floats * sizeof(float));
    meshopt_remapIndexBuffer(m.indices.data(), m.indices.data(), m.indices.size(), remap.data());
    auto compact = [&](auto& v, size_t n) {  // an absent attribute stays absent
        if (v.empty()) return;
        auto out = v;
        out.resize(unique * n);
        for (size_t i = 0; i < vc; ++i) std::copy_n(v.begin() + n * i, n, out.begin() + n * remap[i]);
        v = std::move(out);
    };
    compact(m.positions, 3), compact(m.texcoords, 2), compact(m.normals, 3), compact(m.colors, 4);
}

}  // namespace

GridSpec chooseGrid(const Box3f& bounds, uint64_t triangles, uint64_t targetTrianglesPerBlock, double blockSize) {
    const double extent[3] = {bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y, bounds.max.z - bounds.min.z};
    const float mins[3] = {bounds.min.x, bounds.min.y, bounds.min.z};
    int order[3] = {0, 1, 2};
    std::stable_sort(order, order + 3, [&](int a, int b) { return extent[a] > extent[b]; });
    GridSpec g;
    g.axisU = std::min(order[0], order[1]);
    g.axisV = std::max(order[0], order[1]);
    const double floor = std::max(extent[order[0]] * 1e-9, 1e-300);  // a flat model: a thin cell, its lattice the model's
    const double eu = std::max(extent[g.axisU], floor), ev = std::max(extent[g.axisV], floor);
    if (blockSize > 0) {
        g.cellsU = static_cast<uint32_t>(std::clamp(std::ceil(eu / blockSize), 1.0, 4096.0));
        g.cellsV = static_cast<uint32_t>(std::clamp(std::ceil(ev / blockSize), 1.0, 4096.0));
    } else {
        const double blocks = std::ceil(static_cast<double>(triangles) / std::max<uint64_t>(targetTrianglesPerBlock, 1));
        g.cellsU = static_cast<uint32_t>(std::clamp(std::round(std::sqrt(blocks * eu / ev)), 1.0, std::min(blocks, 4096.0)));
        g.cellsV = static_cast<uint32_t>(std::clamp(std::ceil(blocks / g.cellsU), 1.0, 4096.0));
    }
    if (uint64_t(g.cellsU) * g.cellsV > kMaxGridBlocks)
        throw std::invalid_argument("a grid of " + std::to_string(g.cellsU) + " x " + std::to_string(g.cellsV) +
                                    " blocks is too fine (at most " + std::to_string(kMaxGridBlocks) +
                                    "): raise --block-size, --block-triangles or --memory-limit");
    g.minU = mins[g.axisU], g.minV = mins[g.axisV];
    g.sizeU = static_cast<float>(eu / g.cellsU), g.sizeV = static_cast<float>(ev / g.cellsV);
    return g;
}

std::vector<Piece> splitByGrid(const Piece& piece, const GridSpec& grid) {
    std::vector<Piece> cells(static_cast<size_t>(grid.cellsU) * grid.cellsV);
    Piece rest = piece;
    for (uint32_t u = 0; u < grid.cellsU; ++u) {
        Piece column;
        if (u + 1 < grid.cellsU) {
            CutResult cut = cutPiece(rest, grid.axisU, gridPlane(grid, false, u + 1));
            column = std::move(cut.below), rest = std::move(cut.above);
        } else {
            column = std::move(rest);
        }
        for (uint32_t v = 0; v < grid.cellsV; ++v) {
            Piece& cell = cells[static_cast<size_t>(v) * grid.cellsU + u];
            if (v + 1 < grid.cellsV) {
                CutResult cut = cutPiece(column, grid.axisV, gridPlane(grid, true, v + 1));
                cell = std::move(cut.below), column = std::move(cut.above);
            } else {
                cell = std::move(column);
            }
        }
    }
    return cells;
}

Sides blockSides(const Box3f& block, const GridSpec& grid) {
    const float lo[3] = {block.min.x, block.min.y, block.min.z}, hi[3] = {block.max.x, block.max.y, block.max.z};
    Sides shared = 0;
    for (const bool alongV : {false, true}) {
        const int axis = alongV ? grid.axisV : grid.axisU;
        for (uint32_t k = 1; k < (alongV ? grid.cellsV : grid.cellsU); ++k) {
            const float plane = gridPlane(grid, alongV, k);  // the value both splits cut at, exactly
            if (lo[axis] == plane) shared |= sideBit(axis, false);
            if (hi[axis] == plane) shared |= sideBit(axis, true);
        }
    }
    return shared;
}

void appendPiece(const std::string& file, const Piece& piece) {
    File f(std::fopen(file.c_str(), "ab"), &std::fclose);
    if (!f) throw std::runtime_error(file + ": cannot write (" + std::strerror(errno) + ")");
    const MeshData& m = piece.mesh;
    const uint64_t header[5] = {m.vertexCount(), m.triangleCount(), m.texcoords.size(), m.normals.size(), m.colors.size()};
    if (std::fwrite(header, sizeof header, 1, f.get()) != 1) throw std::runtime_error(file + ": write failed");
    put(f.get(), m.positions, file), put(f.get(), m.texcoords, file), put(f.get(), m.normals, file);
    put(f.get(), m.colors, file), put(f.get(), m.indices, file), put(f.get(), piece.materials, file);
    if (std::fflush(f.get()) != 0) throw std::runtime_error(file + ": write failed (" + std::strerror(errno) + ")");
}

Piece loadPiece(const std::string& file) {
    File f(std::fopen(file.c_str(), "rb"), &std::fclose);
    if (!f) throw std::runtime_error(file + ": cannot read (" + std::strerror(errno) + ")");
    Piece out;
    uint64_t h[5];
    while (std::fread(h, sizeof h, 1, f.get()) == 1) {
        Piece c;
        if (!get(f.get(), c.mesh.positions, 3 * h[0]) || !get(f.get(), c.mesh.texcoords, h[2]) ||
            !get(f.get(), c.mesh.normals, h[3]) || !get(f.get(), c.mesh.colors, h[4]) ||
            !get(f.get(), c.mesh.indices, 3 * h[1]) || !get(f.get(), c.materials, h[1]))
            throw std::runtime_error(file + ": truncated temporary block file");
        // A block's corners are numbered in 32 bits before the weld (they wrapped without a word until stop 47).
        if (out.mesh.vertexCount() + c.mesh.vertexCount() > std::numeric_limits<uint32_t>::max())
            throw InputError("a block of more than " + std::to_string(std::numeric_limits<uint32_t>::max()) +
                             " corners; choose smaller blocks (--block-triangles, --block-size)");
        const uint32_t base = static_cast<uint32_t>(out.mesh.vertexCount());
        for (uint32_t& i : c.mesh.indices) i += base;
        auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
        append(out.mesh.positions, c.mesh.positions), append(out.mesh.texcoords, c.mesh.texcoords);
        append(out.mesh.normals, c.mesh.normals), append(out.mesh.colors, c.mesh.colors);
        append(out.mesh.indices, c.mesh.indices), append(out.materials, c.materials);
    }
    if (out.mesh.vertexCount() > 0) weld(out);
    return out;
}

}  // namespace hlod
