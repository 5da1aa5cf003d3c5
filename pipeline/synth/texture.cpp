// Photo-like, unique, non-tiled block textures (thesis §1.1, Fig. 1.2: "none of the texture is
// tiled"; even uniformly coloured buildings carry full texture). Every texel is a pure function
// of (block seed, position), so rows are painted in parallel and the result is identical on any
// thread count: wall colour with low-frequency variation and weathering streaks, window grids
// with frames and per-window glass (reflections, curtains, lit rooms), storefronts and signs,
// floor ledges and cornices, sidewalk, street with lane marks, roofs with AC units, sky above
// the roof line, and per-texel sensor grain.
#include "pipeline/synth/synth.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace hlod::synth {

namespace {

using Rgb = std::array<double, 3>;

Rgb mix(const Rgb& a, const Rgb& b, double t) {
    return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}
Rgb scaled(const Rgb& a, double f) { return {a[0] * f, a[1] * f, a[2] * f}; }

// Smooth value noise in [0, 1) on a unit lattice.
double valueNoise(uint64_t seed, int64_t key, double u, double v) {
    double fu = std::floor(u), fv = std::floor(v);
    double tu = u - fu, tv = v - fv;
    tu = tu * tu * (3 - 2 * tu);
    tv = tv * tv * (3 - 2 * tv);
    auto iu = int64_t(fu), iv = int64_t(fv);
    double a = hash01(seed, key * 7919 + iu, iv), b = hash01(seed, key * 7919 + iu + 1, iv);
    double c = hash01(seed, key * 7919 + iu, iv + 1), d = hash01(seed, key * 7919 + iu + 1, iv + 1);
    return (a + (b - a) * tu) * (1 - tv) + (c + (d - c) * tu) * tv;
}

Rgb glass(const BlockPlan& b, const Building& bld, double s, double h) {
    bool store = h < bld.groundFloor;
    double u = s - bld.s0;
    int64_t floor = store ? -1 : int64_t((h - bld.groundFloor) / bld.floorHeight);
    int64_t col = store ? int64_t(u / 1.6) : int64_t((u + bld.windowPhase) / bld.windowPitch);
    double r = hash01(b.seed, 90, int64_t(bld.id) * 4096 + floor, col);
    Rgb c{0.16, 0.20, 0.26};
    if (r < 0.1) c = {0.75, 0.62, 0.40};  // lit room
    else if (r < 0.3) c = scaled({hash01(b.seed, 91, floor, col), hash01(b.seed, 92, floor, col), 0.5}, 0.6);
    double top = store ? bld.groundFloor - 0.9 : 0.9 + bld.windowHeight;
    double inPane = store ? h : std::fmod(h - bld.groundFloor, bld.floorHeight);
    return mix(c, {0.62, 0.72, 0.84}, 0.35 * std::clamp(inPane / top, 0.0, 1.0));  // sky reflection
}

Rgb facadeTexel(const BlockPlan& b, const Building& bld, double s, double h, double hTop) {
    if (h < 0) {
        double g = (h < -1.35 ? 0.50 : 0.60) + 0.08 * valueNoise(b.seed, 1, s * 2, h * 2);
        return {g, g, g * 0.97};
    }
    if (h > hTop) {
        double t = std::clamp((h - hTop) / 15, 0.0, 1.0);
        double cloud = 0.08 * valueNoise(b.seed, 2, s / 4, h / 2);
        return mix({0.74 + cloud, 0.81 + cloud, 0.90 + cloud}, {0.50, 0.64, 0.86}, t);
    }
    if (isWindow(bld, s, h, hTop)) {
        bool frame = !(isWindow(bld, s - 0.07, h, hTop) && isWindow(bld, s + 0.07, h, hTop) &&
                       isWindow(bld, s, h - 0.07, hTop) && isWindow(bld, s, h + 0.07, hTop));
        return frame ? Rgb{0.82, 0.81, 0.78} : glass(b, bld, s, h);
    }
    Rgb wall{bld.wall[0], bld.wall[1], bld.wall[2]};
    double variation = 0.88 + 0.24 * valueNoise(b.seed, 3, s / 1.5, h / 1.5);
    double streak = 1 - 0.12 * valueNoise(b.seed, 4, s * 3, h / 8);
    Rgb c = scaled(wall, variation * streak);
    if (h >= bld.groundFloor && std::fmod(h - bld.groundFloor, bld.floorHeight) < 0.18) c = scaled(c, 0.85);
    if (hTop - h < 0.45) c = mix(c, {0.85, 0.84, 0.80}, 0.6);  // cornice
    if (h < bld.groundFloor - 0.2 && h > bld.groundFloor - 0.85)  // shop sign
        c = mix({hash01(b.seed, 93, bld.id), hash01(b.seed, 94, bld.id), hash01(b.seed, 95, bld.id)}, {0.5, 0.5, 0.5}, 0.35);
    return scaled(c, 0.78 + 0.22 * std::min(1.0, h / 2.5));  // darker at the foot
}

Rgb aerialTexel(const BlockPlan& b, const Building& bld, double s, double w) {
    double n = valueNoise(b.seed, 5, s / 2, w / 2);
    if (w < 0) {
        if (w > -2.5) return scaled({0.62, 0.62, 0.60}, 0.9 + 0.15 * n);  // sidewalk
        if (std::abs(w + b.streetHalf) < 0.08 && std::fmod(s, 6.0) < 3) return {0.85, 0.75, 0.22};
        return scaled({0.30, 0.30, 0.31}, 0.85 + 0.3 * n);  // asphalt
    }
    if (w < bld.setback) return scaled({0.30, 0.45, 0.22}, 0.8 + 0.4 * n);  // front yard
    if (w < bld.setback + bld.depth) {
        double edge = std::min({s - bld.s0, bld.s1 - s, w - bld.setback, bld.setback + bld.depth - w});
        if (edge < 0.3) return {0.70, 0.69, 0.66};  // parapet
        int64_t cu = int64_t(s / 3), cv = int64_t(w / 3);
        if (hash01(b.seed, 96, cu, cv) < 0.08 && std::fmod(s, 3.0) < 1.2 && std::fmod(w, 3.0) < 1.2)
            return {0.78, 0.78, 0.76};  // air-conditioning unit
        double grey = 0.35 + 0.25 * hash01(b.seed, 97, bld.id);
        return scaled({grey, grey, grey * 0.95}, 0.85 + 0.3 * n);
    }
    return scaled({0.40, 0.42, 0.28}, 0.8 + 0.4 * n);  // back yard
}

uint8_t toByte(double v) { return uint8_t(std::clamp(v, 0.0, 1.0) * 255 + 0.5); }

}  // namespace

std::vector<uint8_t> paintTexture(const BlockPlan& b, const TextureLayout& t) {
    std::vector<uint8_t> pixels(size_t(t.width) * t.height * 3);
    uint32_t facadeRows = t.bands * t.bandHeight;
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, t.height, 16), [&](const tbb::blocked_range<uint32_t>& rows) {
        for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
            bool facade = y < facadeRows;
            uint32_t band = facade ? y / t.bandHeight : (y - facadeRows) / t.aerialBandHeight;
            band = std::min(band, (facade ? t.bands : t.aerialBands) - 1);
            double bandLength = b.length / (facade ? t.bands : t.aerialBands);
            double inBand = facade ? y - band * t.bandHeight + 0.5
                                   : y - facadeRows - band * t.aerialBandHeight + 0.5;
            uint8_t* row = pixels.data() + size_t(y) * t.width * 3;
            for (uint32_t x = 0; x < t.width; ++x) {
                double s = band * bandLength + (x + 0.5) / t.width * bandLength;
                const Building& bld = *buildingAt(b, s);
                Rgb c;
                if (facade) {
                    double ground = terrainHeight({b.origin.x + b.dir.x * s, b.origin.y + b.dir.y * s});
                    c = facadeTexel(b, bld, s, t.facadeTop - inBand / t.pxPerMetre, bld.roofZ - ground);
                } else {
                    c = aerialTexel(b, bld, s, t.aerialNear + inBand / t.aerialPxPerMetre);
                }
                double grain = 0.035 * (hash01(b.seed, 98, x, y) - 0.5);
                for (int k = 0; k < 3; ++k) row[x * 3 + k] = toByte(c[k] + grain);
            }
        }
    });
    return pixels;
}

}  // namespace hlod::synth
