// `hlod synth city`: a deterministic generator of a scanned-city-like model, standing in for the
// Berkeley model of thesis §1.1 (25 city blocks, 114 blocks, ~8.95 M triangles, ~937 M texels;
// 1 unit = 1 m, z up). Facades are sampled as by a truck-mounted vertical laser (one scan line
// every ~10 cm, range noise, holes behind occluders and glass, uneven density); ground and roofs
// come at lower density as from aerial data; every block (one side of a city block, §3.2) has its
// own non-tiled photo-like texture. Output: block_NNN.obj/.mtl/.jpg per block and city.json.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hlod::synth {

// The thesis model (§1.1, §3.2) that scale 1 reproduces.
inline constexpr uint32_t kThesisCityBlocks = 25;
inline constexpr uint32_t kThesisBlocks = 114;
inline constexpr uint64_t kThesisTriangles = 8'950'000;
inline constexpr uint64_t kThesisTexels = 937'000'000;

struct CityOptions {
    double scale = 1.0;        // fraction of the thesis model's triangles and texels
    uint64_t seed = 1;
    int jpegQuality = 85;
    uint32_t cityBlocks = 0;   // 0: round(25 * sqrt(scale)), at least 1
};

struct Vec2 {
    double x = 0, y = 0;
};

// One building along a block's street front; s runs along the street, w inward from the
// property line, h up from the local ground.
struct Building {
    double s0 = 0, s1 = 0;
    double roofZ = 0;          // absolute height of the flat roof
    double setback = 0;        // facade distance behind the property line
    double depth = 0;          // roof extent behind the facade
    std::array<float, 3> wall{};  // base wall colour, linear 0..1
    double groundFloor = 4;    // storefront height
    double floorHeight = 3.2;
    double windowPitch = 3;    // horizontal distance between window centres
    double windowWidth = 1.4;
    double windowHeight = 1.6;
    double windowPhase = 0;
    uint32_t id = 0;           // for hashing
};

// Something between the truck and the facade that blocks the laser (parked car, tree crown).
struct Occluder {
    double s0 = 0, s1 = 0;
    double distance = 0;       // in front of the property line
    double hMin = 0, hMax = 0; // blocked heights at that distance
};

// One block = one side of a city block (or half of a long side), planned before meshing.
struct BlockPlan {
    uint32_t index = 0;
    uint32_t cityBlock = 0;
    Vec2 origin;               // property-line start
    Vec2 dir;                  // unit, along the street; dir x up = outward normal
    Vec2 normal;               // unit, towards the street
    double length = 0;
    double streetHalf = 9;     // property line to the street centre, where the truck drives
    std::vector<Building> buildings;
    std::vector<Occluder> occluders;
    uint64_t targetTriangles = 0;
    uint64_t targetTexels = 0;
    uint64_t seed = 0;
};

struct CityPlan {
    CityOptions options;
    uint32_t cityBlocks = 0;
    std::vector<BlockPlan> blocks;
};

// Ground height of the (gently hilly) city at a point.
double terrainHeight(Vec2 p);

// Deterministic layout: city blocks on a street grid, sides split so that 25 city blocks give
// 114 blocks, buildings and occluders per block, per-block triangle/texel targets summing to
// scale * thesis totals. Throws std::invalid_argument for an absurd scale.
CityPlan planCity(const CityOptions& options);

// A block's mesh: positions, per-vertex texture coordinates (OBJ convention, v up), triangles.
struct BlockMesh {
    std::vector<std::array<float, 3>> positions;
    std::vector<std::array<float, 2>> texcoords;
    std::vector<std::array<uint32_t, 3>> triangles;
    uint64_t facadeTriangles = 0;
    uint64_t aerialTriangles = 0;
    double meanScanSpacing = 0;  // metres between vertical scan lines
};

// Texture atlas of a block: facade bands (street length cut into `bands` pieces stacked
// vertically) over aerial bands (ground and roofs from above at lower resolution).
struct TextureLayout {
    uint32_t width = 0, height = 0;
    uint32_t bands = 1;          // facade bands
    uint32_t aerialBands = 1;
    double facadeTop = 0;        // metres above ground mapped to a band's first row
    double facadeBottom = -1.5;  // sidewalk in front of the facade (negative h)
    uint32_t bandHeight = 0;     // pixels
    double pxPerMetre = 0;       // facade vertical resolution
    double aerialNear = 0;       // w range of the aerial bands (street centre .. deepest roof)
    double aerialFar = 0;
    uint32_t aerialBandHeight = 0;
    double aerialPxPerMetre = 0;
};

TextureLayout layoutTexture(const BlockPlan& block);

// Texture coordinates (OBJ convention) of a facade point / an aerial point in band `band`.
std::array<float, 2> facadeUv(const TextureLayout& t, const BlockPlan& b, uint32_t band, double s, double h);
std::array<float, 2> aerialUv(const TextureLayout& t, const BlockPlan& b, uint32_t band, double s, double w);

// Facade and aerial meshing (facade_scan.cpp, aerial.cpp), appended to `mesh`.
void scanFacade(const BlockPlan& block, const TextureLayout& t, BlockMesh& mesh);
void sampleAerial(const BlockPlan& block, const TextureLayout& t, BlockMesh& mesh);

// Facade detail shared by geometry (window recesses) and texture (window pixels).
const Building* buildingAt(const BlockPlan& block, double s);
// hTop: height of the roof above the local ground.
bool isWindow(const Building& b, double s, double h, double hTop);

// RGB8 pixels, row-major from the top, width * height * 3.
std::vector<uint8_t> paintTexture(const BlockPlan& block, const TextureLayout& t);

// Deterministic hash noise in [0, 1) (xxHash of the integer key).
double hash01(uint64_t seed, int64_t a, int64_t b = 0, int64_t c = 0);

struct BlockRecord {
    std::string obj, mtl, jpg;
    uint64_t triangles = 0, vertices = 0, facadeTriangles = 0, aerialTriangles = 0;
    uint32_t width = 0, height = 0;
    uint64_t texels = 0;
    uint64_t targetTriangles = 0, targetTexels = 0;
    double length = 0, meanScanSpacing = 0;
    std::array<double, 3> boundsMin{}, boundsMax{};
};

// Writes block_NNN.obj/.mtl/.jpg of one block into `dir` (each through a temporary file and a
// rename); returns its record. Throws std::runtime_error naming the file on failure.
BlockRecord writeBlock(const BlockPlan& block, const std::string& dir, int jpegQuality);

struct CityResult {
    std::vector<BlockRecord> blocks;
    uint64_t triangles = 0, texels = 0, bytes = 0;
};

// Plans and writes the whole city block by block (in parallel, bounded memory), then city.json.
CityResult generateCity(const CityOptions& options, const std::string& dir);

}  // namespace hlod::synth
