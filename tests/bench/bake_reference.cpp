// See bake_reference.h. Its own closest-point weights and bilinear sampling (not bake.cpp's: an
// oracle should not share the code it judges); the closest triangle from closest_point.h's exact
// query (checked against brute force in test_closest_point.cpp). Every source needs a texture,
// and the sources at least one triangle of non-zero area (the bench's always have both).
#include "tests/bench/bake_reference.h"

#include "formats/metrics.h"
#include "pipeline/closest_point.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace hlod::bench {
namespace {

using Vec = std::array<double, 3>;
Vec minus(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Barycentric weights of the point of triangle abc nearest p, by the Voronoi regions of its
// vertices and edges (Ericson 2005, §5.1.5).
std::array<double, 3> nearestWeights(const Vec& a, const Vec& b, const Vec& c, const Vec& p) {
    const Vec ab = minus(b, a), ac = minus(c, a), ap = minus(p, a), bp = minus(p, b), cp = minus(p, c);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap), d3 = dot(ab, bp), d4 = dot(ac, bp), d5 = dot(ab, cp), d6 = dot(ac, cp);
    const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
    if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return {1 - d1 / (d1 - d3), d1 / (d1 - d3), 0};
    if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return {1 - d2 / (d2 - d6), 0, d2 / (d2 - d6)};
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    const double v = vb / (va + vb + vc), w = vc / (va + vb + vc);
    return {1 - v - w, v, w};
}

// RGB at texel coordinates (x, y) (centres at +0.5), bilinear, clamped to the edge.
Vec sample(const Image& image, double x, double y) {
    x = std::clamp(x - 0.5, 0.0, image.width - 1.0), y = std::clamp(y - 0.5, 0.0, image.height - 1.0);
    const uint32_t x0 = static_cast<uint32_t>(x), y0 = static_cast<uint32_t>(y);
    const uint32_t x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
    const double fx = x - x0, fy = y - y0;
    Vec out{};
    for (uint32_t k = 0; k < 3; ++k) {
        const auto at = [&](uint32_t tx, uint32_t ty) {
            return double(image.pixels[(size_t(ty) * image.width + tx) * image.channels + std::min(k, image.channels - 1)]);
        };
        out[k] = (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
    }
    return out;
}

Vec vertex(const MeshData& m, uint32_t v) { return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]}; }

}  // namespace

double referencePsnr(const BakedTexture& baked, const std::vector<BakeSource>& sources) {
    std::vector<float> positions;
    std::vector<uint32_t> indices, sourceOf, triangleOf;  // per triangle of the hierarchy's input
    for (uint32_t s = 0; s < sources.size(); ++s) {
        const MeshData& m = *sources[s].mesh;
        const uint32_t base = static_cast<uint32_t>(positions.size() / 3);
        positions.insert(positions.end(), m.positions.begin(), m.positions.end());
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            for (int k = 0; k < 3; ++k) indices.push_back(base + m.indices[3 * t + k]);
            sourceOf.push_back(s), triangleOf.push_back(t);
        }
    }
    const TriangleBvh bvh = buildTriangleBvh(positions, indices);
    const MeshData& mesh = baked.mesh;
    const Image& atlas = baked.image;
    std::vector<uint8_t> seen(size_t(atlas.width) * atlas.height, 0);
    double squared = 0;
    size_t count = 0;
    uint32_t hint = ~0u;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t* v = &mesh.indices[3 * t];
        double tx[3], ty[3];
        for (int k = 0; k < 3; ++k) tx[k] = mesh.texcoords[2 * v[k]] * atlas.width, ty[k] = mesh.texcoords[2 * v[k] + 1] * atlas.height;
        const double area = (tx[1] - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (ty[1] - ty[0]);
        if (area == 0) continue;
        const Vec p0 = vertex(mesh, v[0]), e1 = minus(vertex(mesh, v[1]), p0), e2 = minus(vertex(mesh, v[2]), p0);
        const auto weights = [&](double x, double y) {  // of corners 1 and 2 at texel coordinates (x, y)
            return std::array<double, 2>{((x - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (y - ty[0])) / area,
                                         ((tx[1] - tx[0]) * (y - ty[0]) - (x - tx[0]) * (ty[1] - ty[0])) / area};
        };
        const int x0 = std::max(0, int(std::floor(std::min({tx[0], tx[1], tx[2]})))), x1 = std::min(int(atlas.width) - 1, int(std::ceil(std::max({tx[0], tx[1], tx[2]}))));
        const int y0 = std::max(0, int(std::floor(std::min({ty[0], ty[1], ty[2]})))), y1 = std::min(int(atlas.height) - 1, int(std::ceil(std::max({ty[0], ty[1], ty[2]}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const auto [b1, b2] = weights(x + 0.5, y + 0.5);
                if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || seen[size_t(y) * atlas.width + x]) continue;  // texel centres inside, once
                seen[size_t(y) * atlas.width + x] = 1;
                for (int sy = 0; sy < 2; ++sy)
                    for (int sx = 0; sx < 2; ++sx) {
                        const double qx = x + 0.25 + 0.5 * sx, qy = y + 0.25 + 0.5 * sy;
                        const auto [c1, c2] = weights(qx, qy);
                        const Vec q = {p0[0] + c1 * e1[0] + c2 * e2[0], p0[1] + c1 * e1[1] + c2 * e2[1], p0[2] + c1 * e1[2] + c2 * e2[2]};
                        squaredDistance(bvh, q.data(), hint);
                        const uint32_t input = bvh.input[hint], s = sourceOf[input];
                        const MeshData& m = *sources[s].mesh;
                        const uint32_t* j = &m.indices[3 * size_t(triangleOf[input])];
                        const std::array<double, 3> w = nearestWeights(vertex(m, j[0]), vertex(m, j[1]), vertex(m, j[2]), q);
                        double u = 0, uv = 0;
                        for (int k = 0; k < 3; ++k) u += w[k] * m.texcoords[2 * j[k]], uv += w[k] * m.texcoords[2 * j[k] + 1];
                        const Image& texture = *sources[s].texture;
                        const Vec truth = sample(texture, u * texture.width, uv * texture.height), shown = sample(atlas, qx, qy);
                        for (int k = 0; k < 3; ++k) squared += (truth[k] - shown[k]) * (truth[k] - shown[k]);
                        count += 3;
                    }
            }
    }
    return psnrDb(squared, count);
}

}  // namespace hlod::bench
