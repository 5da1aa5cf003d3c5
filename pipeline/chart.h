// chart.cpp: the parameterisation a baked texture (bake.cpp) is laid out on. Internal to
// pipeline/ (bake.cpp and its tests); the public entry point is bakeTexture in pipeline.h.
#pragma once

#include "formats/codec.h"
#include "formats/db.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace hlod {

// Normal-cone half-angle of a chart: every face's normal is within this angle of the chart's seed
// normal, the projection direction (pipeline/BAKE.md: chart count, coverage and PSNR for 30-70
// degrees, measured on the banana scan).
inline constexpr double kChartConeDegrees = 60;

// One chart flattened: its triangles (indices into the mesh's triangles) and, per triangle, the
// 2D positions of its three corners in world units (6 doubles), with the chart's bounding box
// at [0, width] x [0, height] and width >= height. No two triangles' interiors overlap.
struct FlatChart {
    std::vector<uint32_t> triangles;
    std::vector<double> uv;
    double width = 0, height = 0;
};

// Charts by region growing over edge-connected faces (edges shared by position), each projected
// orthographically on its seed's normal; a chart whose projection overlaps itself is grown again
// with half the cone, down to single triangles. Deterministic.
std::vector<FlatChart> flattenCharts(const MeshData& mesh, double coneDegrees = kChartConeDegrees);

// pack_charts.cpp: the charts at one scale (texels per world unit) in an atlas of 8 x 8 texel
// blocks (JPEG's), each block owned by at most one chart; width x height <= texelBudget unless
// every chart is already one block.
inline constexpr int kJpegBlock = 8;
inline constexpr int kChartGutter = 2;  // texels around a chart inside its own blocks
struct ChartPlacement {
    int x = 0, y = 0, w = 0, h = 0;  // texels spanned by the chart's blocks; its (0, 0) is at x, y + kChartGutter
};
struct AtlasLayout {
    double scale = 0;
    int width = 0, height = 0;  // texels, multiples of kJpegBlock
    std::vector<ChartPlacement> places;
    std::vector<uint32_t> blockOwner;  // per block (width / 8 per row): chart index or kNone
};
AtlasLayout packCharts(const std::vector<FlatChart>& charts, uint64_t texelBudget);

// A set of 8 x 8 texel blocks to pack: wb x hb, row-major, and (finishMask) per column its lowest
// and highest occupied row (hb and -1 when empty) and the occupied count.
struct BlockMask {
    int wb = 0, hb = 0;
    std::vector<uint8_t> blocks;
    std::vector<int> bottom, top;
    int count = 0;
};
void finishMask(BlockMask& m);
// The masks' horizon packing (pack_charts.cpp, as packCharts packs its charts) at most maxColumns
// wide unless one mask is wider: each mask's place in blocks, and the atlas's columns and rows.
struct BlockPacking {
    int columns = 0, rows = 0;
    std::vector<std::pair<int, int>> at;
};
BlockPacking packMasks(const std::vector<BlockMask>& masks, int maxColumns);

// Whether triangle (x[3], y[3]) meets the box [x0, x1] x [y0, y1] (separating axes).
bool triangleMeetsBox(const double x[3], const double y[3], double x0, double y0, double x1, double y1);

// True when the interiors of two of the triangles (6 doubles each) overlap (separating axes, with
// a tolerance of 1e-6 x the extent so that triangles sharing an edge or a corner do not count).
bool trianglesOverlap(const std::vector<double>& uv);

}  // namespace hlod
