// City layout (thesis §1.1, §3.2): 25 city blocks on a street grid; each side of a city block,
// seen from the street by the acquisition truck, is one block; the longest 14 % of the sides are
// cut in two, so 25 city blocks give 100 + 14 = 114 blocks as in the thesis. Buildings are boxy
// (flat roofs, window grids), taller downtown. Per-block triangle and texel targets are shares of
// scale * (8.95 M triangles, 937 M texels), weighted by facade and ground area (uneven blocks).
#include "pipeline/synth/synth.h"

#include <xxhash.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace hlod::synth {

namespace {

constexpr double kSplitFraction = 14.0 / 100.0;  // 100 sides -> 114 blocks (§3.2)

struct Side {
    uint32_t cityBlock;
    Vec2 origin, dir, normal;
    double length, streetHalf;
    double downtown;  // 1 at the city centre, 0 at the edge
};

double lerp(double a, double b, double t) { return a + (b - a) * t; }

std::array<float, 3> wallColour(uint64_t seed, uint32_t id) {
    static constexpr std::array<std::array<float, 3>, 8> palette = {{{0.78f, 0.70f, 0.55f},
                                                                     {0.55f, 0.29f, 0.22f},
                                                                     {0.60f, 0.60f, 0.62f},
                                                                     {0.86f, 0.84f, 0.79f},
                                                                     {0.56f, 0.65f, 0.74f},
                                                                     {0.84f, 0.77f, 0.52f},
                                                                     {0.42f, 0.33f, 0.27f},
                                                                     {0.80f, 0.62f, 0.58f}}};
    auto c = palette[size_t(hash01(seed, 40, id) * palette.size())];
    for (int k = 0; k < 3; ++k)
        c[k] = std::clamp(c[k] + float(hash01(seed, 41 + k, id) - 0.5) * 0.1f, 0.05f, 0.95f);
    return c;
}

std::vector<Building> planBuildings(const Side& side, double s0, double length, uint64_t seed,
                                    uint32_t& nextId) {
    std::vector<Building> out;
    double s = 0;
    while (s < length - 1e-9) {
        uint32_t id = nextId++;
        double width = 6 + 22 * std::pow(hash01(seed, 1, id), 2);
        if (length - (s + width) < 4) width = length - s;  // no sliver at the end
        Building b;
        b.id = id;
        b.s0 = s;
        b.s1 = s + width;
        double height = 7 + 25 * (0.3 + 0.7 * side.downtown) * (0.25 + 0.75 * hash01(seed, 2, id));
        b.setback = hash01(seed, 3, id) < 0.7 ? 0.0 : 1 + 3 * hash01(seed, 4, id);
        b.depth = 10 + 10 * hash01(seed, 5, id);
        b.wall = wallColour(seed, id);
        b.floorHeight = 3.0 + 0.6 * hash01(seed, 6, id);
        b.groundFloor = std::min(height - 0.5, 3.6 + 1.0 * hash01(seed, 7, id));
        b.windowPitch = 2.4 + 1.6 * hash01(seed, 8, id);
        b.windowWidth = b.windowPitch * (0.45 + 0.2 * hash01(seed, 9, id));
        b.windowHeight = 1.3 + 0.6 * hash01(seed, 10, id);
        b.windowPhase = b.windowPitch * hash01(seed, 11, id);
        double ground = 1e300;
        for (double t = 0; t <= 1.0; t += 0.25) {
            double along = s0 + lerp(b.s0, b.s1, t);
            Vec2 p{side.origin.x + side.dir.x * along, side.origin.y + side.dir.y * along};
            ground = std::min(ground, terrainHeight(p));
        }
        b.roofZ = ground + height;
        out.push_back(b);
        s = b.s1;
    }
    return out;
}

// Parked cars (low, near the kerb) and street trees (crowns) between truck and facade.
std::vector<Occluder> planOccluders(double length, double streetHalf, uint64_t seed) {
    std::vector<Occluder> out;
    uint32_t k = 0;
    double s = 8 * hash01(seed, 20, 0);
    while (s < length) {
        Occluder o;
        if (hash01(seed, 21, k) < 0.65) {  // car
            double len = 4 + hash01(seed, 22, k);
            o = {s, s + len, std::min(streetHalf - 1, 4.0), 0.0, 1.4 + 0.3 * hash01(seed, 23, k)};
        } else {  // tree crown
            double crown = 3 + 3 * hash01(seed, 24, k);
            o = {s, s + crown, std::min(streetHalf - 1, 2.0), 2.6, 5 + 4 * hash01(seed, 25, k)};
        }
        out.push_back(o);
        s = o.s1 + 2 + 14 * hash01(seed, 26, k);
        ++k;
    }
    return out;
}

std::vector<Side> planSides(const CityOptions& options, uint32_t cityBlocks) {
    uint32_t cols = uint32_t(std::ceil(std::sqrt(double(cityBlocks))));
    uint32_t rows = (cityBlocks + cols - 1) / cols;
    uint64_t seed = options.seed;
    std::vector<double> x(cols + 1), y(rows + 1), widths(cols), depths(rows);
    auto street = [&](int axis, uint32_t i) { return 14 + 10 * hash01(seed, 30 + axis, i); };
    for (uint32_t j = 0; j < cols; ++j) widths[j] = 90 + 90 * hash01(seed, 32, j);
    for (uint32_t i = 0; i < rows; ++i) depths[i] = 70 + 70 * hash01(seed, 33, i);
    for (uint32_t j = 0; j < cols; ++j) x[j + 1] = x[j] + widths[j] + street(0, j + 1);
    for (uint32_t i = 0; i < rows; ++i) y[i + 1] = y[i] + depths[i] + street(1, i + 1);
    double cx = x[cols] / 2, cy = y[rows] / 2, radius = std::hypot(cx, cy) + 1;
    std::vector<Side> sides;
    for (uint32_t n = 0; n < cityBlocks; ++n) {
        uint32_t i = n / cols, j = n % cols;
        double x0 = x[j], x1 = x[j] + widths[j], y0 = y[i], y1 = y[i] + depths[i];
        double downtown = 1 - std::hypot((x0 + x1) / 2 - cx, (y0 + y1) / 2 - cy) / radius;
        // Counter-clockwise, so that dir x up is the outward normal.
        sides.push_back({n, {x0, y0}, {1, 0}, {0, -1}, x1 - x0, street(1, i) / 2, downtown});
        sides.push_back({n, {x1, y0}, {0, 1}, {1, 0}, y1 - y0, street(0, j + 1) / 2, downtown});
        sides.push_back({n, {x1, y1}, {-1, 0}, {0, 1}, x1 - x0, street(1, i + 1) / 2, downtown});
        sides.push_back({n, {x0, y1}, {0, -1}, {-1, 0}, y1 - y0, street(0, j) / 2, downtown});
    }
    return sides;
}

void assignTargets(CityPlan& plan) {
    std::vector<double> wTris, wTex;
    for (const BlockPlan& b : plan.blocks) {
        double facade = 0, aerial = b.length * b.streetHalf;
        for (const Building& bld : b.buildings) {
            facade += (bld.s1 - bld.s0) * (bld.roofZ - terrainHeight(b.origin) + 1.5);
            aerial += (bld.s1 - bld.s0) * bld.depth;
        }
        double w = std::max(1.0, facade + 0.15 * aerial);
        wTris.push_back(w);
        wTex.push_back(w * (0.7 + 0.6 * hash01(b.seed, 50)));  // photos at varying distance
    }
    double sumT = std::accumulate(wTris.begin(), wTris.end(), 0.0);
    double sumX = std::accumulate(wTex.begin(), wTex.end(), 0.0);
    double scale = plan.options.scale;
    for (size_t k = 0; k < plan.blocks.size(); ++k) {
        plan.blocks[k].targetTriangles = uint64_t(std::llround(scale * kThesisTriangles * wTris[k] / sumT));
        plan.blocks[k].targetTexels = uint64_t(std::llround(scale * kThesisTexels * wTex[k] / sumX));
    }
}

}  // namespace

double hash01(uint64_t seed, int64_t a, int64_t b, int64_t c) {
    const int64_t key[3] = {a, b, c};
    return double(XXH3_64bits_withSeed(key, sizeof key, seed) >> 11) * 0x1.0p-53;
}

double terrainHeight(Vec2 p) {
    return 0.025 * p.y + 2.5 * std::sin(p.x / 140.0) * std::cos(p.y / 190.0);
}

CityPlan planCity(const CityOptions& options) {
    if (!std::isfinite(options.scale) || options.scale <= 0 || options.scale > 4)
        throw std::invalid_argument("scale must be in (0, 4], got " + std::to_string(options.scale));
    if (options.jpegQuality < 1 || options.jpegQuality > 100)
        throw std::invalid_argument("JPEG quality must be in 1..100");
    if (options.cityBlocks > 10000) throw std::invalid_argument("at most 10000 city blocks");
    CityPlan plan;
    plan.options = options;
    plan.cityBlocks = options.cityBlocks
                          ? options.cityBlocks
                          : uint32_t(std::max(1L, std::lround(kThesisCityBlocks * std::sqrt(options.scale))));
    std::vector<Side> sides = planSides(options, plan.cityBlocks);
    std::vector<size_t> order(sides.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return sides[a].length > sides[b].length; });
    std::vector<bool> split(sides.size(), false);
    size_t splits = size_t(std::lround(double(sides.size()) * kSplitFraction));
    for (size_t k = 0; k < splits; ++k) split[order[k]] = true;

    uint32_t nextBuilding = 0;
    for (size_t k = 0; k < sides.size(); ++k) {
        const Side& side = sides[k];
        int pieces = split[k] ? 2 : 1;
        for (int piece = 0; piece < pieces; ++piece) {
            BlockPlan b;
            b.index = uint32_t(plan.blocks.size());
            b.cityBlock = side.cityBlock;
            b.seed = XXH3_64bits_withSeed(&b.index, sizeof b.index, options.seed);
            b.length = side.length / pieces;
            double start = piece * b.length;
            b.origin = {side.origin.x + side.dir.x * start, side.origin.y + side.dir.y * start};
            b.dir = side.dir;
            b.normal = side.normal;
            b.streetHalf = side.streetHalf;
            b.buildings = planBuildings(side, start, b.length, b.seed, nextBuilding);
            b.occluders = planOccluders(b.length, b.streetHalf, b.seed);
            plan.blocks.push_back(std::move(b));
        }
    }
    assignTargets(plan);
    return plan;
}

const Building* buildingAt(const BlockPlan& block, double s) {
    auto it = std::upper_bound(block.buildings.begin(), block.buildings.end(), s,
                               [](double v, const Building& b) { return v < b.s1; });
    if (it == block.buildings.end()) return block.buildings.empty() ? nullptr : &block.buildings.back();
    return &*it;
}

}  // namespace hlod::synth
