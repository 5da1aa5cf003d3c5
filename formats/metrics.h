// Per-node attributes of thesis §3.3 computed from triangles: bounds, static benefit,
// area-weighted average normal; and eq. 3.1 cost is nodeCost() in db.h. Also the PSNR of textures
// (the baked nodes' and the leaves' against the source, pipeline/BAKE.md, pipeline/TEXTURE_SIZE.md).
#pragma once

#include "formats/codec.h"
#include "formats/db.h"

#include <span>

namespace hlod {

struct SurfaceMetrics {
    Box3f bounds{};
    double area = 0;           // sum of triangle areas
    Vec3f avgNormal{};         // sum(normal_t * area_t) / |...| (§3.3); zero when area is 0
    float staticBenefit = 0;   // sqrt(numTriangles * area) (§3.3)
    uint64_t triangles = 0;
};

// Metrics over all triangles of all the meshes (a node's sub-meshes).
SurfaceMetrics surfaceMetrics(std::span<const MeshData> meshes);

// 10 log10(255^2 / MSE) with MSE = squaredError / samples (8-bit channels): 100 when the error is
// 0, 0 with no samples.
double psnrDb(double squaredError, uint64_t samples);

}  // namespace hlod
