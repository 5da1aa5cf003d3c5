// Texture fidelity of a stored node texture against its source (issue #14: "PSNR of the finest
// level's textures against the source over the texels triangles use"; pipeline/TEXTURE_SIZE.md).
// A leaf's atlas copies whole JPEG blocks of the source (texture.cpp), so each stored texel has one
// source texel: the one under the same point of the same triangle. Every texel of the stored
// atlas whose centre a triangle covers (edge functions, each texel counted once; a triangle too
// small to cover a centre contributes nothing) is mapped through the triangle's barycentric
// coordinates from its stored UVs to its source UVs, and compared with the source texel there.
// The source is read by chart (uvCharts: the rectangle its source UVs cover), not whole.
#include "pipeline/texture_charts.h"

#include <algorithm>
#include <cmath>

namespace hlod {

namespace {

struct Rect {
    uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The source texels [x0, x1) x [y0, y1) under `triangles`' source UVs.
Rect sourceRect(const MeshData& mesh, const std::vector<uint32_t>& triangles, const TextureSource& source) {
    double lo[2] = {1, 1}, hi[2] = {0, 0};
    for (uint32_t t : triangles)
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 2; ++a) {
                const double c = std::clamp(double(mesh.texcoords[2 * mesh.indices[3 * t + k] + a]), 0.0, 1.0);
                lo[a] = std::min(lo[a], c), hi[a] = std::max(hi[a], c);
            }
    const auto range = [](double l, double h, uint32_t size, uint32_t& first, uint32_t& last) {
        first = std::min(size - 1, static_cast<uint32_t>(std::floor(l * size)));
        last = std::clamp(static_cast<uint32_t>(std::ceil(h * size)), first + 1, size);
    };
    Rect r;
    range(lo[0], hi[0], source.width, r.x0, r.x1);
    range(lo[1], hi[1], source.height, r.y0, r.y1);
    return r;
}

}  // namespace

TextureFidelity textureFidelity(const MeshData& sourceMesh, const TextureSource& source, const MeshData& storedMesh, const Image& stored) {
    TextureFidelity out;
    if (stored.width == 0 || source.width == 0 || stored.channels != source.channels) return out;
    uint32_t count = 0;
    const std::vector<uint32_t> chart = uvCharts(sourceMesh, count);
    std::vector<std::vector<uint32_t>> trianglesOf(count);
    for (uint32_t t = 0; t < sourceMesh.triangleCount(); ++t) trianglesOf[chart[sourceMesh.indices[3 * t]]].push_back(t);
    const uint32_t nc = stored.channels;
    std::vector<uint8_t> counted(size_t(stored.width) * stored.height, 0);
    std::vector<uint8_t> texels;
    for (const std::vector<uint32_t>& triangles : trianglesOf) {
        if (triangles.empty()) continue;
        const Rect r = sourceRect(sourceMesh, triangles, source);
        texels.resize(size_t(r.x1 - r.x0) * (r.y1 - r.y0) * nc);
        source.rows(r.y0, r.y1, r.x0, r.x1, texels.data());
        for (uint32_t t : triangles) {
            double p[3][2], s[3][2];  // stored and source texel coordinates of the corners
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = sourceMesh.indices[3 * t + k];
                p[k][0] = double(storedMesh.texcoords[2 * v]) * stored.width, p[k][1] = double(storedMesh.texcoords[2 * v + 1]) * stored.height;
                s[k][0] = double(sourceMesh.texcoords[2 * v]) * source.width, s[k][1] = double(sourceMesh.texcoords[2 * v + 1]) * source.height;
            }
            const double area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
            if (area == 0) continue;
            const auto clampTo = [](double v, uint32_t size) { return static_cast<uint32_t>(std::clamp(v, 0.0, double(size))); };
            const uint32_t bx0 = clampTo(std::floor(std::min({p[0][0], p[1][0], p[2][0]})), stored.width);
            const uint32_t bx1 = clampTo(std::ceil(std::max({p[0][0], p[1][0], p[2][0]})), stored.width);
            const uint32_t by0 = clampTo(std::floor(std::min({p[0][1], p[1][1], p[2][1]})), stored.height);
            const uint32_t by1 = clampTo(std::ceil(std::max({p[0][1], p[1][1], p[2][1]})), stored.height);
            for (uint32_t y = by0; y < by1; ++y)
                for (uint32_t x = bx0; x < bx1; ++x) {
                    const double cx = x + 0.5, cy = y + 0.5;
                    double b[3];
                    for (int k = 0; k < 3; ++k) {
                        const double* e0 = p[(k + 1) % 3];
                        const double* e1 = p[(k + 2) % 3];
                        b[k] = ((e1[0] - e0[0]) * (cy - e0[1]) - (cx - e0[0]) * (e1[1] - e0[1])) / area;
                    }
                    if (b[0] < 0 || b[1] < 0 || b[2] < 0 || counted[size_t(y) * stored.width + x]) continue;
                    counted[size_t(y) * stored.width + x] = 1;
                    const double sx = b[0] * s[0][0] + b[1] * s[1][0] + b[2] * s[2][0];
                    const double sy = b[0] * s[0][1] + b[1] * s[1][1] + b[2] * s[2][1];
                    const uint32_t ix = std::clamp(static_cast<uint32_t>(std::max(0.0, std::floor(sx))), r.x0, r.x1 - 1);
                    const uint32_t iy = std::clamp(static_cast<uint32_t>(std::max(0.0, std::floor(sy))), r.y0, r.y1 - 1);
                    const uint8_t* a = &stored.pixels[(size_t(y) * stored.width + x) * nc];
                    const uint8_t* o = &texels[(size_t(iy - r.y0) * (r.x1 - r.x0) + (ix - r.x0)) * nc];
                    for (uint32_t c = 0; c < nc; ++c) out.squaredError += double(int(a[c]) - int(o[c])) * (int(a[c]) - int(o[c]));
                    ++out.texels;
                }
        }
    }
    out.samples = out.texels * nc;
    return out;
}

}  // namespace hlod
