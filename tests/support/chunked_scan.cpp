#include "tests/support/chunked_scan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <vector>

namespace hlod {
namespace {

struct Grid {
    float lo[3], size[3];
    uint32_t cells[3];
    std::array<uint32_t, 3> cellOf(const float* p) const {
        std::array<uint32_t, 3> c{};
        for (int a = 0; a < 3; ++a)
            c[a] = std::min(cells[a] - 1, static_cast<uint32_t>(std::max(0.0f, (p[a] - lo[a]) / size[a])));
        return c;
    }
};

// About `count` cells of equal side over [lo, hi].
Grid gridOver(const float lo[3], const float hi[3], uint32_t count) {
    double volume = 1, extent[3];
    for (int a = 0; a < 3; ++a) extent[a] = std::max(1e-6, double(hi[a]) - lo[a]);
    const double longest = std::max({extent[0], extent[1], extent[2]});
    for (int a = 0; a < 3; ++a) volume *= std::max(extent[a], longest / 16);
    const double side = std::cbrt(volume / std::max(1u, count));
    Grid g{};
    for (int a = 0; a < 3; ++a) {
        g.lo[a] = lo[a];
        g.cells[a] = std::max(1u, static_cast<uint32_t>(std::lround(extent[a] / side)));
        g.size[a] = static_cast<float>(extent[a] / g.cells[a]) * 1.0001f;
    }
    return g;
}

void bounds(const MeshData& m, const std::vector<uint32_t>& triangles, float lo[3], float hi[3]) {
    std::fill(lo, lo + 3, 1e30f), std::fill(hi, hi + 3, -1e30f);
    for (uint32_t t : triangles)
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) {
                const float v = m.positions[3 * m.indices[3 * t + k] + a];
                lo[a] = std::min(lo[a], v), hi[a] = std::max(hi[a], v);
            }
}

void centroid(const MeshData& m, uint32_t t, float out[3]) {
    for (int a = 0; a < 3; ++a)
        out[a] = (m.positions[3 * m.indices[3 * t] + a] + m.positions[3 * m.indices[3 * t + 1] + a] +
                  m.positions[3 * m.indices[3 * t + 2] + a]) / 3;
}

Image chunkTexture(uint32_t chunk, uint32_t size) {
    Image img{size, size, 3, {}};
    img.pixels.reserve(size_t{size} * size * 3);
    const double hue = chunk * 0.61803398875;
    std::vector<double> column(size_t{size} * 3), row(size);  // the texel function's factors (a 4K atlas in ~0.1 s)
    for (uint32_t x = 0; x < size; ++x)
        for (int c = 0; c < 3; ++c) column[3 * x + c] = std::sin(0.2 * x + c);
    for (uint32_t y = 0; y < size; ++y) row[y] = std::cos(0.17 * y);
    double base[3];
    for (int c = 0; c < 3; ++c) base[c] = 100 * std::sin(6.2831853 * (hue + c / 3.0)) * 0.6;
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c)
                img.pixels.push_back(static_cast<uint8_t>(127.5 + base[c] + 40 * column[3 * x + c] * row[y]));
    return img;
}

}  // namespace

ChunkedScan writeChunkedScan(const std::string& dir, const std::string& name, const MeshData& mesh,
                             const ChunkedScanOptions& options) {
    std::vector<uint32_t> all(mesh.triangleCount());
    for (uint32_t t = 0; t < all.size(); ++t) all[t] = t;
    float lo[3], hi[3];
    bounds(mesh, all, lo, hi);
    const Grid grid = gridOver(lo, hi, options.chunks);
    const double shift = options.jitter * std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    std::map<std::array<uint32_t, 3>, std::vector<uint32_t>> chunks;  // cell -> triangles, ordered
    for (uint32_t t : all) {
        float c[3];
        centroid(mesh, t, c);
        chunks[grid.cellOf(c)].push_back(t);
    }
    std::vector<uint32_t> firstChunk(mesh.vertexCount(), UINT32_MAX);  // vertices on a chunk border are shared
    std::vector<uint8_t> shared(mesh.vertexCount());
    uint32_t index = 0;
    for (const auto& [cell, triangles] : chunks) {
        for (uint32_t t : triangles)
            for (int k = 0; k < 3; ++k) {
                uint32_t& first = firstChunk[mesh.indices[3 * t + k]];
                if (first == UINT32_MAX) first = index;
                else if (first != index) shared[mesh.indices[3 * t + k]] = 1;
            }
        ++index;
    }
    ChunkedScan out;
    out.obj = (std::filesystem::path(dir) / (name + ".obj")).string();
    std::ofstream obj(out.obj), mtl((std::filesystem::path(dir) / (name + ".mtl")).string());
    obj << "mtllib " << name << ".mtl\n";
    char line[160];
    uint64_t vertexBase = 1;
    std::vector<uint32_t> uses(mesh.vertexCount());
    for (const auto& [cell, triangles] : chunks) {
        const uint32_t chunk = out.chunks++;
        const std::string texture = "chunk_" + std::to_string(chunk) + (options.jpeg ? ".jpg" : ".png");
        const EncodedBlob image = encodeTexture(chunkTexture(chunk, options.textureSize), options.jpeg ? Codec::Jpeg : Codec::Png,
                                                options.jpegQuality, options.jpegChroma420);
        std::ofstream(std::filesystem::path(dir) / texture, std::ios::binary)
            .write(reinterpret_cast<const char*>(image.bytes.data()), static_cast<std::streamsize>(image.bytes.size()));
        mtl << "newmtl chunk" << chunk << "\nKd 1 1 1\nmap_Kd " << texture << "\n";
        obj << "usemtl chunk" << chunk << "\n";
        float clo[3], chi[3];
        bounds(mesh, triangles, clo, chi);
        int axes[3] = {0, 1, 2};  // the chunk's two longest axes carry u and v
        std::sort(axes, axes + 3, [&](int a, int b) { return chi[a] - clo[a] > chi[b] - clo[b]; });
        const Grid charts = gridOver(clo, chi, options.chartCells * options.chartCells * options.chartCells);
        std::map<std::array<uint32_t, 3>, std::vector<uint32_t>> chartTriangles;
        for (uint32_t t : triangles) {
            float c[3];
            centroid(mesh, t, c);
            chartTriangles[charts.cellOf(c)].push_back(t);
        }
        const uint32_t tiles = static_cast<uint32_t>(std::ceil(std::sqrt(double(chartTriangles.size()))));
        uint32_t tile = 0;
        for (const auto& [chartCell, chartTris] : chartTriangles) {
            ++out.charts;
            float tlo[3], thi[3];
            bounds(mesh, chartTris, tlo, thi);
            const float tu = float(tile % tiles) / tiles, tv = float(tile / tiles) / tiles;
            ++tile;
            std::map<uint32_t, uint64_t> local;  // source vertex -> OBJ index
            std::string faces;
            for (uint32_t t : chartTris) {
                faces += "f";
                for (int k = 0; k < 3; ++k) {
                    const uint32_t v = mesh.indices[3 * t + k];
                    auto [it, fresh] = local.try_emplace(v, vertexBase + local.size());
                    if (fresh) {
                        const float* p = &mesh.positions[3 * v];
                        float q[3];  // a chunk border's copies: a deterministic offset in [-shift, shift] each
                        for (int a = 0; a < 3; ++a)
                            q[a] = shared[v] ? static_cast<float>(p[a] + shift * std::sin(12.9898 * chunk + 78.233 * v + 37.719 * a)) : p[a];
                        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", q[0], q[1], q[2]);
                        obj << line;
                        float uv[2];
                        for (int a = 0; a < 2; ++a)  // inside the tile, half a texel of margin
                            uv[a] = (a == 0 ? tu : tv) + (0.5f / options.textureSize) +
                                    (1.0f / tiles - 1.0f / options.textureSize) * (q[axes[a]] - tlo[axes[a]]) /
                                        std::max(1e-9f, thi[axes[a]] - tlo[axes[a]]);
                        std::snprintf(line, sizeof line, "vt %.9g %.9g\n", uv[0], uv[1]);
                        obj << line;
                        if (uses[v]++ == 1) ++out.duplicatedVertices;
                    }
                    std::snprintf(line, sizeof line, " %llu/%llu", (unsigned long long)it->second, (unsigned long long)it->second);
                    faces += line;
                }
                faces += "\n";
            }
            obj << faces;
            vertexBase += local.size();
            out.triangles += chartTris.size();
        }
    }
    if (!obj.flush() || !mtl.flush()) throw std::runtime_error(out.obj + ": cannot write");
    return out;
}

MeshData facadeMesh(uint32_t n, float width, float height) {
    MeshData m;
    const uint32_t rows = std::max(1u, static_cast<uint32_t>(std::lround(n * height / width)));
    for (uint32_t j = 0; j <= rows; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            const float x = width * i / n, z = height * j / rows;
            // windows: 1.2 x 1.6 m every 3 x 3.5 m, recessed 0.3 m
            const float wx = std::fmod(x, 3.0f), wz = std::fmod(z, 3.5f);
            const bool window = wx > 0.9f && wx < 2.1f && wz > 1.0f && wz < 2.6f;
            m.positions.insert(m.positions.end(), {x, 2.0f * std::sin(x * 0.08f) + (window ? 0.3f : 0.0f), z});
        }
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}

}  // namespace hlod
