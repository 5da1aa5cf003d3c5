// Packing of flattened charts (chart.cpp) into one atlas for bake.cpp (and, by packMasks, of the
// block groups of texture.cpp's atlases): the "Tetris" horizon
// packing of Lévy, Petitjean, Ray & Maillot 2002, "Least squares conformal maps for automatic
// texture atlas generation" (its packing section), on a grid of 8 x 8 texel blocks (JPEG's:
// formats/codec_image.cpp writes 4:4:4) instead of texels, so that no block holds two charts.
// - One scale (texels per world unit) for all charts: texel area follows world area.
// - A chart occupies every block that comes within kChartGutter + 0.5 texels of one of its
//   triangles (exact triangle/box separating-axis test), so every texel within the gutter of the
//   chart, and every texel a bilinear tap inside it reads, lies in the chart's own blocks.
// - Charts, largest first (ties by chart order), are dropped from the top onto the horizon (the
//   highest occupied block per column): at each column, the chart rests where its lowest block
//   in some column meets the horizon; the column giving the lowest top wins (then the least
//   space left under it, then the leftmost). Concave charts (a banana's crescents) nest. The
//   atlas width (in blocks) giving the smallest area is chosen among 9 candidates from
//   sqrt(total blocks) to 2x that.
// - The scale starts at sqrt(budget / chart area) and shrinks (by 2-50 % a step) until width x
//   height <= budget, or until every chart is one block (a budget under one block counts as one).
#include "pipeline/chart.h"

#include "formats/layout.h"

#include <algorithm>
#include <cmath>

namespace hlod {

bool triangleMeetsBox(const double x[3], const double y[3], double x0, double y0, double x1, double y1) {
    if (std::max({x[0], x[1], x[2]}) < x0 || std::min({x[0], x[1], x[2]}) > x1) return false;
    if (std::max({y[0], y[1], y[2]}) < y0 || std::min({y[0], y[1], y[2]}) > y1) return false;
    for (int e = 0; e < 3; ++e) {
        const int a = e, b = (e + 1) % 3, c = (e + 2) % 3;
        const double nx = y[b] - y[a], ny = x[a] - x[b];
        const double side = nx * (x[c] - x[a]) + ny * (y[c] - y[a]);  // the third corner's side
        double lo = 1e300, hi = -1e300;
        for (double bx : {x0, x1})
            for (double by : {y0, y1}) {
                const double d = nx * (bx - x[a]) + ny * (by - y[a]);
                lo = std::min(lo, d), hi = std::max(hi, d);
            }
        if ((side >= 0 && hi < 0) || (side <= 0 && lo > 0)) return false;
    }
    return true;
}

namespace {

// The blocks of one chart at a scale.
BlockMask maskOf(const FlatChart& chart, double scale) {
    BlockMask m;
    m.wb = std::max(1, static_cast<int>(std::ceil((chart.width * scale + 2 * kChartGutter) / kJpegBlock)));
    m.hb = std::max(1, static_cast<int>(std::ceil((chart.height * scale + 2 * kChartGutter) / kJpegBlock)));
    m.blocks.assign(size_t(m.wb) * m.hb, 0);
    const double reach = kChartGutter + 0.5;
    for (size_t t = 0; t < chart.triangles.size(); ++t) {
        double x[3], y[3];
        for (int k = 0; k < 3; ++k)
            x[k] = kChartGutter + chart.uv[6 * t + 2 * k] * scale, y[k] = kChartGutter + chart.uv[6 * t + 2 * k + 1] * scale;
        const int i0 = std::max(0, static_cast<int>(std::floor((std::min({x[0], x[1], x[2]}) - reach) / kJpegBlock)));
        const int i1 = std::min(m.wb - 1, static_cast<int>(std::floor((std::max({x[0], x[1], x[2]}) + reach) / kJpegBlock)));
        const int j0 = std::max(0, static_cast<int>(std::floor((std::min({y[0], y[1], y[2]}) - reach) / kJpegBlock)));
        const int j1 = std::min(m.hb - 1, static_cast<int>(std::floor((std::max({y[0], y[1], y[2]}) + reach) / kJpegBlock)));
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
                if (!m.blocks[size_t(j) * m.wb + i] &&
                    triangleMeetsBox(x, y, i * kJpegBlock - reach, j * kJpegBlock - reach, (i + 1) * kJpegBlock + reach,
                                     (j + 1) * kJpegBlock + reach))
                    m.blocks[size_t(j) * m.wb + i] = 1;
    }
    finishMask(m);
    if (m.count == 0) m.blocks[0] = 1, m.bottom[0] = m.top[0] = 0, m.count = 1;  // a chart too small to reach any block centre
    return m;
}

// Horizon packing at a width of `columns` blocks; returns the placements (in blocks) and height.
int horizonPack(const std::vector<BlockMask>& masks, const std::vector<uint32_t>& order, int columns, std::vector<std::pair<int, int>>& at) {
    std::vector<int> horizon(columns, 0);
    at.assign(masks.size(), {0, 0});
    int height = 0;
    for (uint32_t c : order) {
        const BlockMask& m = masks[c];
        long bestTop = -1, bestWaste = 0;
        int bestX = 0, bestY = 0;
        for (int x = 0; x + m.wb <= columns; ++x) {
            int y = 0;
            for (int i = 0; i < m.wb; ++i)
                if (m.top[i] >= 0) y = std::max(y, horizon[x + i] - m.bottom[i]);
            long top = 0, waste = 0;
            for (int i = 0; i < m.wb; ++i)
                if (m.top[i] >= 0) top = std::max<long>(top, y + m.top[i] + 1), waste += y + m.bottom[i] - horizon[x + i];
            if (bestTop < 0 || top < bestTop || (top == bestTop && waste < bestWaste)) bestTop = top, bestWaste = waste, bestX = x, bestY = y;
        }
        at[c] = {bestX, bestY};
        for (int i = 0; i < m.wb; ++i)
            if (m.top[i] >= 0) horizon[bestX + i] = std::max(horizon[bestX + i], bestY + m.top[i] + 1);
        height = std::max(height, static_cast<int>(bestTop));
    }
    return std::max(height, 1);
}

AtlasLayout packAt(const std::vector<FlatChart>& charts, double scale) {
    std::vector<BlockMask> masks(charts.size());
    for (size_t c = 0; c < charts.size(); ++c) masks[c] = maskOf(charts[c], scale);
    const BlockPacking packing = packMasks(masks, layout::kMaxTextureSide / kJpegBlock);
    const int bestColumns = packing.columns, bestHeight = packing.rows;
    const std::vector<std::pair<int, int>>& bestAt = packing.at;
    AtlasLayout l;
    l.scale = scale, l.width = bestColumns * kJpegBlock, l.height = bestHeight * kJpegBlock;
    l.blockOwner.assign(size_t(bestColumns) * bestHeight, kNone);
    l.places.resize(charts.size());
    for (size_t c = 0; c < charts.size(); ++c) {
        const BlockMask& m = masks[c];
        l.places[c] = {bestAt[c].first * kJpegBlock, bestAt[c].second * kJpegBlock, m.wb * kJpegBlock, m.hb * kJpegBlock};
        for (int j = 0; j < m.hb; ++j)
            for (int i = 0; i < m.wb; ++i)
                if (m.blocks[size_t(j) * m.wb + i])
                    l.blockOwner[size_t(bestAt[c].second + j) * bestColumns + bestAt[c].first + i] = static_cast<uint32_t>(c);
    }
    return l;
}

}  // namespace

void finishMask(BlockMask& m) {
    m.bottom.assign(m.wb, m.hb), m.top.assign(m.wb, -1), m.count = 0;
    for (int j = 0; j < m.hb; ++j)
        for (int i = 0; i < m.wb; ++i)
            if (m.blocks[size_t(j) * m.wb + i]) m.bottom[i] = std::min(m.bottom[i], j), m.top[i] = std::max(m.top[i], j), ++m.count;
}

BlockPacking packMasks(const std::vector<BlockMask>& masks, int maxColumns) {
    long total = 0;
    int widest = 1;
    for (const BlockMask& m : masks) total += m.count, widest = std::max(widest, m.wb);
    std::vector<uint32_t> order(masks.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return masks[a].count > masks[b].count; });
    const double side = std::sqrt(double(total));
    BlockPacking best;
    std::vector<std::pair<int, int>> at;
    const auto candidate = [&](int k) {  // at most maxColumns unless one mask is wider
        return std::max(widest, std::min(maxColumns, static_cast<int>(std::ceil(side * (1 + k / 8.0)))));
    };
    for (int k = 0; k <= 8; ++k) {
        const int columns = candidate(k);
        if (k > 0 && columns == candidate(k - 1)) continue;
        const int height = horizonPack(masks, order, columns, at);
        if (best.columns == 0 || long(columns) * height < long(best.columns) * best.rows) best.columns = columns, best.rows = height, best.at = at;
    }
    return best;
}

AtlasLayout packCharts(const std::vector<FlatChart>& charts, uint64_t texelBudget) {
    double area = 0;
    for (const FlatChart& c : charts)
        for (size_t t = 0; t < c.triangles.size(); ++t) {
            const double* p = &c.uv[6 * t];
            area += 0.5 * std::fabs((p[2] - p[0]) * (p[5] - p[1]) - (p[4] - p[0]) * (p[3] - p[1]));
        }
    texelBudget = std::max<uint64_t>(texelBudget, kJpegBlock * kJpegBlock);
    double scale = std::sqrt(double(texelBudget) / std::max(area, 1e-300));
    AtlasLayout l = packAt(charts, scale);
    auto smallest = [](const AtlasLayout& l) {
        return std::all_of(l.places.begin(), l.places.end(), [](const ChartPlacement& p) { return p.w == kJpegBlock && p.h == kJpegBlock; });
    };
    while (uint64_t(l.width) * uint64_t(l.height) > texelBudget && !smallest(l)) {
        scale *= std::clamp(std::sqrt(double(texelBudget) / (double(l.width) * l.height)), 0.5, 0.98);
        l = packAt(charts, scale);
    }
    return l;
}

}  // namespace hlod
