// Ground and roofs "at lower density as from aerial data" (thesis §1.1: far-range Digital
// Surface Map and aerial imagery merged with the ground-based facades): regular height-field
// grids over the street in front of the block and over each flat roof, with DSM noise. They
// take the share of the block's triangles that the facades leave.
#include "pipeline/synth/synth.h"

#include <algorithm>
#include <cmath>

namespace hlod::synth {

namespace {

constexpr double kAerialShare = 0.15;

struct Patch {
    double s0, s1, w0, w1;
    double roofZ;  // NaN: ground following the terrain
    uint32_t band;
};

void gridPatch(const BlockPlan& b, const TextureLayout& t, const Patch& p, double spacing, uint32_t key,
               BlockMesh& mesh) {
    uint32_t nu = uint32_t(std::max(1.0, std::ceil((p.s1 - p.s0) / spacing)));
    uint32_t nv = uint32_t(std::max(1.0, std::ceil((p.w1 - p.w0) / spacing)));
    uint32_t first = uint32_t(mesh.positions.size());
    for (uint32_t i = 0; i <= nu; ++i) {
        for (uint32_t j = 0; j <= nv; ++j) {
            double s = p.s0 + (p.s1 - p.s0) * i / nu, w = p.w0 + (p.w1 - p.w0) * j / nv;
            double x = b.origin.x + b.dir.x * s - b.normal.x * w, y = b.origin.y + b.dir.y * s - b.normal.y * w;
            double noise = 0.04 * (hash01(b.seed, 1000 + int64_t(key), i, j) - 0.5);
            double z = (std::isnan(p.roofZ) ? terrainHeight({x, y}) : p.roofZ) + noise;
            mesh.positions.push_back({float(x), float(y), float(z)});
            mesh.texcoords.push_back(aerialUv(t, b, p.band, s, w));
        }
    }
    // Counter-clockwise in (s, w) with w inward is counter-clockwise seen from above.
    for (uint32_t i = 0; i < nu; ++i) {
        for (uint32_t j = 0; j < nv; ++j) {
            uint32_t a = first + i * (nv + 1) + j, c = a + nv + 1;
            mesh.triangles.push_back({a, c, c + 1});
            mesh.triangles.push_back({a, c + 1, a + 1});
            mesh.aerialTriangles += 2;
        }
    }
}

}  // namespace

void sampleAerial(const BlockPlan& b, const TextureLayout& t, BlockMesh& mesh) {
    std::vector<Patch> patches;
    double area = 0;
    double bandLength = b.length / t.aerialBands;
    for (uint32_t band = 0; band < t.aerialBands; ++band) {
        double lo = band * bandLength, hi = (band + 1) * bandLength;
        for (const Building& bld : b.buildings) {
            double s0 = std::max(lo, bld.s0), s1 = std::min(hi, bld.s1);
            if (s1 - s0 < 1e-6) continue;
            patches.push_back({s0, s1, -b.streetHalf, bld.setback, std::nan(""), band});
            patches.push_back({s0, s1, bld.setback, bld.setback + bld.depth, bld.roofZ, band});
            area += (s1 - s0) * (b.streetHalf + bld.setback + bld.depth);
        }
    }
    double wanted = std::max(2.0 * double(patches.size()), kAerialShare * double(b.targetTriangles));
    double spacing = std::sqrt(2 * area / wanted);
    for (int pass = 0; pass < 3; ++pass) {  // grids round up: correct the spacing
        double count = 0;
        for (const Patch& p : patches)
            count += 2 * std::max(1.0, std::ceil((p.s1 - p.s0) / spacing)) * std::max(1.0, std::ceil((p.w1 - p.w0) / spacing));
        spacing *= std::sqrt(count / wanted);
    }
    for (size_t k = 0; k < patches.size(); ++k) gridPatch(b, t, patches[k], spacing, uint32_t(k), mesh);
}

}  // namespace hlod::synth
