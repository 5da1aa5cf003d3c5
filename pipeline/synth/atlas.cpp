// Texture atlas of one block (thesis §1.1: "triangular meshes with large texture maps", one
// unique, non-tiled texture per block). The facade strip (street length x height) is cut into
// `bands` pieces stacked vertically so that the image is roughly square; ground and roofs follow
// below at a third of the facade resolution, as from aerial photographs. Resolution is chosen so
// that the atlas has the block's texel target.
#include "pipeline/synth/synth.h"

#include <algorithm>
#include <cmath>

namespace hlod::synth {

namespace {
constexpr double kAerialResolution = 1.0 / 3.0;  // aerial texels per metre / facade texels per metre
}

TextureLayout layoutTexture(const BlockPlan& b) {
    TextureLayout t;
    double top = 0, far = 0;
    for (const Building& bld : b.buildings) {
        double ground = 1e300;
        for (double f = 0; f <= 1.0; f += 0.125) {
            double s = bld.s0 + (bld.s1 - bld.s0) * f;
            ground = std::min(ground, terrainHeight({b.origin.x + b.dir.x * s, b.origin.y + b.dir.y * s}));
        }
        top = std::max(top, bld.roofZ - ground);
        far = std::max(far, bld.setback + bld.depth);
    }
    t.facadeTop = top + 0.5;
    t.aerialNear = -b.streetHalf;
    t.aerialFar = far;
    double facadeSpan = t.facadeTop - t.facadeBottom;
    double aerialSpan = t.aerialFar - t.aerialNear;
    double q = kAerialResolution;
    double r = std::sqrt(double(std::max<uint64_t>(b.targetTexels, 64)) /
                         (b.length * (facadeSpan + aerialSpan * q * q)));
    t.bands = uint32_t(std::max(1L, std::lround(std::sqrt(b.length / (facadeSpan + aerialSpan * q)))));
    t.aerialBands = uint32_t(std::max(1.0, std::ceil(t.bands * q)));
    // Rounding of bands and pixels changes the texel count: correct the resolution once.
    for (int pass = 0; pass < 2; ++pass) {
        t.width = uint32_t(std::max(8L, std::lround(r * b.length / t.bands)));
        t.pxPerMetre = r;
        t.bandHeight = uint32_t(std::max(2.0, std::ceil(r * facadeSpan)));
        t.aerialPxPerMetre = r * q;
        t.aerialBandHeight = uint32_t(std::max(2.0, std::ceil(r * q * aerialSpan)));
        t.height = t.bands * t.bandHeight + t.aerialBands * t.aerialBandHeight;
        r *= std::sqrt(double(std::max<uint64_t>(b.targetTexels, 64)) / (double(t.width) * t.height));
    }
    return t;
}

std::array<float, 2> facadeUv(const TextureLayout& t, const BlockPlan& b, uint32_t band, double s, double h) {
    double bandLength = b.length / t.bands;
    double x = (s - band * bandLength) / bandLength * t.width;
    double hc = std::clamp(h, t.facadeBottom, t.facadeTop);
    double y = band * double(t.bandHeight) + (t.facadeTop - hc) * t.pxPerMetre;
    return {float(std::clamp(x / t.width, 0.0, 1.0)), float(1.0 - y / t.height)};
}

std::array<float, 2> aerialUv(const TextureLayout& t, const BlockPlan& b, uint32_t band, double s, double w) {
    double bandLength = b.length / t.aerialBands;
    double x = (s - band * bandLength) / bandLength * t.width;
    double wc = std::clamp(w, t.aerialNear, t.aerialFar);
    double y = t.bands * double(t.bandHeight) + band * double(t.aerialBandHeight) +
               (wc - t.aerialNear) * t.aerialPxPerMetre;
    return {float(std::clamp(x / t.width, 0.0, 1.0)), float(1.0 - y / t.height)};
}

}  // namespace hlod::synth
