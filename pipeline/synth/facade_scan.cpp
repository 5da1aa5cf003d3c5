// Facades as acquired by the truck of thesis §1.1 (Frueh & Zakhor): a vertical 2D laser scanner
// sweeps one scan line every ~10 cm along the street (spacing varies with the truck's speed),
// each line sampled at equal angle steps (so density falls with height and distance). Range
// noise moves points along the viewing direction; cars and tree crowns between truck and facade
// and glass (no return) leave holes. Consecutive scan lines are joined into triangle strips, so a
// boxy building is tens of thousands of triangles, never one cube.
#include "pipeline/synth/synth.h"

#include <algorithm>
#include <cmath>

namespace hlod::synth {

namespace {

constexpr double kScannerHeight = 3.0;     // metres above the road
constexpr double kFacadeShare = 0.85;      // of a block's triangles; the rest is aerial
constexpr double kAnisotropy = 4.2;        // vertical sample spacing / scan line spacing
constexpr double kHoleAllowance = 0.06;    // expected share of triangles lost to holes
constexpr double kRecess = 0.12;           // window depth behind the wall
constexpr double kGlassDropout = 0.12;     // chance that glass returns nothing
constexpr double kSidewalk[] = {1.5, 0.75};  // ground samples in front of the facade

struct Column {
    double s = 0;
    uint32_t band = 0;
};

struct Sample {
    std::array<float, 3> position;
    std::array<float, 2> uv;
    bool valid;
};

Vec2 along(const BlockPlan& b, double s, double w) {
    return {b.origin.x + b.dir.x * s - b.normal.x * w, b.origin.y + b.dir.y * s - b.normal.y * w};
}

double facadeArea(const BlockPlan& b) {
    double area = 0;
    for (const Building& bld : b.buildings)
        area += (bld.s1 - bld.s0) * (bld.roofZ - terrainHeight(along(b, (bld.s0 + bld.s1) / 2, 0)) + 1.5);
    return area;
}

// Scan line positions: truck speed varies (traffic), band boundaries are forced columns that
// belong to both bands.
std::vector<Column> scanColumns(const BlockPlan& b, const TextureLayout& t, double spacing) {
    std::vector<double> s;
    double wavelength = 40 + 40 * hash01(b.seed, 60), phase = 6.283 * hash01(b.seed, 61);
    uint32_t k = 0;
    for (double x = 0; x < b.length; ++k) {
        s.push_back(x);
        double speed = (1 + 0.4 * std::sin(6.283 * x / wavelength + phase)) * (0.85 + 0.3 * hash01(b.seed, 62, k));
        x += spacing * speed;
    }
    std::vector<double> boundaries;
    for (uint32_t band = 1; band < t.bands; ++band) boundaries.push_back(b.length * band / t.bands);
    std::erase_if(s, [&](double x) {
        return b.length - x < 0.3 * spacing ||
               std::any_of(boundaries.begin(), boundaries.end(), [&](double y) { return std::abs(x - y) < 0.3 * spacing; });
    });
    s.push_back(b.length);
    std::vector<Column> out;
    size_t next = 0;
    uint32_t band = 0;
    for (double x : s) {
        while (next < boundaries.size() && boundaries[next] < x) {
            out.push_back({boundaries[next], band});
            out.push_back({boundaries[next], ++band});
            ++next;
        }
        out.push_back({x, band});
    }
    return out;
}

bool occluded(const BlockPlan& b, double s, double w, double h) {
    for (const Occluder& o : b.occluders) {
        if (s < o.s0 || s > o.s1) continue;
        double t = (b.streetHalf - o.distance) / (b.streetHalf + w);  // along the ray, truck -> point
        double rayH = kScannerHeight + (h - kScannerHeight) * t;
        if (rayH >= o.hMin && rayH <= o.hMax) return true;
    }
    return false;
}

// One scan line: sidewalk samples, then facade samples from the foot to the roof edge.
std::vector<Sample> scanLine(const BlockPlan& b, const TextureLayout& t, const Column& c, double dTheta,
                             uint32_t line) {
    const Building& bld = *buildingAt(b, c.s);
    double ground = terrainHeight(along(b, c.s, 0));
    double hTop = bld.roofZ - ground;
    double range = b.streetHalf + bld.setback;  // horizontal distance scanner -> facade
    std::vector<Sample> out;
    auto emit = [&](double w, double h, uint32_t k) {
        Vec2 p = along(b, c.s, w);
        bool valid = !occluded(b, c.s, w, h);
        if (h >= 0 && isWindow(bld, c.s, h, hTop) && hash01(b.seed, 70, line, k) < kGlassDropout) valid = false;
        float z = float(h < 0 ? terrainHeight(p) : ground + h);
        out.push_back({{float(p.x), float(p.y), z}, facadeUv(t, b, c.band, c.s, h), valid});
    };
    uint32_t k = 0;
    for (double e : kSidewalk) emit(bld.setback - e, -e, k++);
    double theta0 = std::atan(-kScannerHeight / range), thetaTop = std::atan((hTop - kScannerHeight) / range);
    for (double theta = theta0;; theta += dTheta, ++k) {
        bool last = theta >= thetaTop;
        double h = last ? hTop : kScannerHeight + range * std::tan(theta);
        double noise = 0.015 * (range / 10) * (hash01(b.seed, 71, line, k) + hash01(b.seed, 72, line, k) - 1);
        double w = bld.setback + (isWindow(bld, c.s, h, hTop) ? kRecess : 0) + noise;
        emit(w, h, k);
        if (last) break;
    }
    return out;
}

}  // namespace

bool isWindow(const Building& b, double s, double h, double hTop) {
    double u = s - b.s0;
    if (u < 0.6 || b.s1 - s < 0.6) return false;
    if (h < b.groundFloor) {  // storefront: large panes between mullions
        double m = std::fmod(u, 1.6);
        return h > 0.5 && h < b.groundFloor - 0.9 && m > 0.08 && m < 1.52;
    }
    double inFloor = std::fmod(h - b.groundFloor, b.floorHeight);
    double windowTop = h - inFloor + 0.9 + b.windowHeight;
    if (inFloor < 0.9 || h > windowTop || windowTop > hTop - 0.3) return false;
    double cell = std::floor((u + b.windowPhase) / b.windowPitch);
    double centre = b.s0 + (cell + 0.5) * b.windowPitch - b.windowPhase;
    if (centre - b.windowWidth / 2 < b.s0 + 0.6 || centre + b.windowWidth / 2 > b.s1 - 0.6) return false;
    return std::abs(s - centre) < b.windowWidth / 2;
}

namespace {

// Joins consecutive scan lines of the same texture band into triangles; returns how many.
uint64_t meshFacade(const BlockPlan& b, const TextureLayout& t, const std::vector<Column>& columns,
                    double dTheta, BlockMesh& mesh) {
    uint64_t before = mesh.triangles.size();
    std::vector<Sample> prev, cur;
    std::vector<uint32_t> prevIndex, curIndex;
    auto index = [&](std::vector<Sample>& line, std::vector<uint32_t>& ids, size_t k) {
        if (ids[k] == UINT32_MAX) {
            ids[k] = uint32_t(mesh.positions.size());
            mesh.positions.push_back(line[k].position);
            mesh.texcoords.push_back(line[k].uv);
        }
        return ids[k];
    };
    for (size_t c = 0; c < columns.size(); ++c) {
        cur = scanLine(b, t, columns[c], dTheta, uint32_t(c));
        curIndex.assign(cur.size(), UINT32_MAX);
        if (c > 0 && columns[c - 1].band == columns[c].band) {
            size_t rows = std::min(prev.size(), cur.size());
            for (size_t k = 0; k + 1 < rows; ++k) {
                bool a0 = prev[k].valid, b0 = cur[k].valid, b1 = cur[k + 1].valid, a1 = prev[k + 1].valid;
                if (a0 && b0 && b1)
                    mesh.triangles.push_back({index(prev, prevIndex, k), index(cur, curIndex, k), index(cur, curIndex, k + 1)});
                if (a0 && b1 && a1)
                    mesh.triangles.push_back({index(prev, prevIndex, k), index(cur, curIndex, k + 1), index(prev, prevIndex, k + 1)});
            }
        }
        std::swap(prev, cur);
        std::swap(prevIndex, curIndex);
    }
    return mesh.triangles.size() - before;
}

}  // namespace

void scanFacade(const BlockPlan& b, const TextureLayout& t, BlockMesh& mesh) {
    double wanted = std::max(8.0, kFacadeShare * double(b.targetTriangles));
    double spacing = std::sqrt(2 * facadeArea(b) / (kAnisotropy * wanted / (1 - kHoleAllowance)));
    std::vector<Column> columns = scanColumns(b, t, spacing);
    // Angle step so that the quads of all scan lines add up to the facade's share.
    double span = 0;
    for (const Column& c : columns) {
        const Building& bld = *buildingAt(b, c.s);
        double range = b.streetHalf + bld.setback, hTop = bld.roofZ - terrainHeight(along(b, c.s, 0));
        span += std::atan((hTop - kScannerHeight) / range) + std::atan(kScannerHeight / range);
    }
    double fixed = 2.0 * double(columns.size()) * (std::size(kSidewalk) + 0.5);  // triangles not set by the step
    double dTheta = span / std::max(wanted / (1 - kHoleAllowance) - fixed, 2.0 * double(columns.size())) * 2;
    // Trial passes measure holes and row rounding; the step is corrected after each.
    double fixedGot = fixed * (1 - kHoleAllowance);
    for (int pass = 0; pass < 3; ++pass) {
        BlockMesh trial;
        double got = double(meshFacade(b, t, columns, dTheta, trial));
        if (got > fixedGot && wanted > fixedGot) dTheta *= (got - fixedGot) / (wanted - fixedGot);
    }
    mesh.facadeTriangles = meshFacade(b, t, columns, dTheta, mesh);
    mesh.meanScanSpacing = b.length / double(columns.size() - t.bands);
}

}  // namespace hlod::synth
