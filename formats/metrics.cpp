// Per-node attributes of thesis §3.3: bounding box, static benefit
// (staticBenefit_n = sqrt(numTriangles_n * sum of triangle areas)) and the area-weighted,
// normalised average normal, computed over all the node's sub-meshes.
#include "formats/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hlod {

SurfaceMetrics surfaceMetrics(std::span<const MeshData> meshes) {
    SurfaceMetrics out;
    constexpr float inf = std::numeric_limits<float>::infinity();
    Box3f box{{inf, inf, inf}, {-inf, -inf, -inf}};
    double nx = 0, ny = 0, nz = 0;
    bool any = false;
    for (const MeshData& m : meshes) {
        const float* p = m.positions.data();
        for (size_t v = 0; v < m.vertexCount(); ++v, any = true) {
            box.min = {std::min(box.min.x, p[3 * v]), std::min(box.min.y, p[3 * v + 1]), std::min(box.min.z, p[3 * v + 2])};
            box.max = {std::max(box.max.x, p[3 * v]), std::max(box.max.y, p[3 * v + 1]), std::max(box.max.z, p[3 * v + 2])};
        }
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            const float* a = p + 3 * m.indices[3 * t];
            const float* b = p + 3 * m.indices[3 * t + 1];
            const float* c = p + 3 * m.indices[3 * t + 2];
            double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
            double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
            double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
            // |cross| = 2 * area, so summing cross products weights unit normals by area.
            out.area += 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
            nx += cx, ny += cy, nz += cz;
        }
        out.triangles += m.triangleCount();
    }
    if (any) out.bounds = box;
    double len = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (len > 0) out.avgNormal = {float(nx / len), float(ny / len), float(nz / len)};
    out.staticBenefit = float(std::sqrt(double(out.triangles) * out.area));
    return out;
}

double psnrDb(double squaredError, uint64_t samples) {
    if (samples == 0) return 0;  // nothing measured
    const double mse = squaredError / double(samples);
    return 10 * std::log10(255.0 * 255.0 / std::max(mse, 255.0 * 255.0 * 1e-10));
}

}  // namespace hlod
