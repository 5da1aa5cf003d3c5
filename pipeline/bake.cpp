// Baked textures for simplified nodes whose source UVs no longer apply: Cignoni, Montani, Rocchini
// & Scopigno 1998, "A general method for preserving attribute values on simplified meshes"
// (each texel of the simplified surface takes the attribute of the closest point on the original
// surface), on the charts of chart.cpp (Sander et al. 2001), packed into one atlas.
// - Packing (pack_charts.cpp): one scale for all charts, so texel area follows world area; Lévy
//   et al. 2002's horizon packing on 8 x 8 texel blocks, each owned by one chart, with every texel
//   within kChartGutter of a chart in its own blocks; width x height <= texelBudget.
// - Baking: the centre of every texel a simplified triangle covers (or, for a triangle that covers
//   no texel centre, the texel of its centroid) is lifted to the simplified surface and its
//   closest original triangle found (the bounding volume hierarchy of closest_point.h, Ericson
//   2005 §6.6, the previous texel's answer as the hint); when that triangle faces away from the
//   simplified one (the far side of a thin sheet), the nearest facing triangle along the
//   simplified normal, both ways, within kFacingReach x the closest distance (rays in the same
//   hierarchy, Möller & Trumbore 1997), replaces it (Sander et al. 2001 cast along the normal
//   throughout).
//   The texel's footprint, kSuper x kSuper sub-samples, is projected onto that triangle (clamped
//   to it), and each sub-sample takes the source colour there: bilinear in the material's
//   texture at the interpolated source UV (clamped to the edge), else the interpolated vertex
//   colour, else kUntexturedGrey. The texel is their mean. The rest of the chart's blocks (gutter,
//   padding) is filled breadth-first with copies of the nearest baked texel, so bilinear taps and
//   JPEG blocks only ever mix one chart's colours.
// - Quality: psnr = 10 log10(255^2 / MSE), MSE over every sub-sample of every covered texel and
//   the three channels, between the sub-sample's source colour and the baked atlas read back
//   bilinearly at the sub-sample's UV: the colour a renderer shows there against the original's.
//   It counts detail finer than the budget's texels and bilinear reconstruction; MSE 0 reads 100
//   dB, no covered texel 0. pipeline/BAKE.md has the figures.
#include "pipeline/chart.h"
#include "pipeline/closest_point.h"
#include "pipeline/pipeline.h"

#include "formats/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace hlod {
namespace {

using Point = std::array<double, 3>;  // also a vector

constexpr int kSuper = 2;   // sub-samples per texel side
constexpr float kUntexturedGrey = 191;
constexpr double kFacingReach = 8;  // a facing triangle replaces a closer one facing away within this factor
constexpr double kEnough = 1e-6;  // of the sources' extent: a closest triangle that near ends the search (OriginalSurface::closest)

struct Rgb {
    float c[3] = {0, 0, 0};
};

Point vertex(const MeshData& m, uint32_t i) { return {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]}; }
Point minus(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point cross(const Point& a, const Point& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }

// Barycentric weights of the point of triangle abc closest to p (Ericson, "Real-Time Collision
// Detection" 2005, ClosestPtPointTriangle).
void closestWeights(const Point& a, const Point& b, const Point& c, const Point& p, double w[3]) {
    const Point ab = minus(b, a), ac = minus(c, a), ap = minus(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return void((w[0] = 1, w[1] = 0, w[2] = 0));
    const Point bp = minus(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return void((w[0] = 0, w[1] = 1, w[2] = 0));
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return void((w[0] = 1 - v, w[1] = v, w[2] = 0));
    }
    const Point cp = minus(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return void((w[0] = 0, w[1] = 0, w[2] = 1));
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double v = d2 / (d2 - d6);
        return void((w[0] = 1 - v, w[1] = 0, w[2] = v));
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return void((w[0] = 0, w[1] = 1 - v, w[2] = v));
    }
    const double denom = 1 / (va + vb + vc);
    w[1] = vb * denom, w[2] = vc * denom, w[0] = 1 - w[1] - w[2];
}

// Bilinear sample at pixel coordinates (x, y) (pixel centres at +0.5), clamped to the edge.
Rgb bilinear(const Image& image, double x, double y) {
    x = std::clamp(x - 0.5, 0.0, image.width - 1.0), y = std::clamp(y - 0.5, 0.0, image.height - 1.0);
    const uint32_t x0 = static_cast<uint32_t>(x), y0 = static_cast<uint32_t>(y);
    const double fx = x - x0, fy = y - y0, gx = 1 - fx, gy = 1 - fy;
    const size_t nc = image.channels, right = x0 + 1 < image.width ? nc : 0, down = y0 + 1 < image.height ? size_t(image.width) * nc : 0;
    const uint8_t* t = &image.pixels[(size_t(y0) * image.width + x0) * nc];
    Rgb out;
    for (size_t k = 0; k < 3; ++k, t += nc >= 3) {
        const double a = t[0], b = t[right], c = t[down], d = t[down + right];
        out.c[k] = static_cast<float>((a * gx + b * fx) * gy + (c * gx + d * fx) * fy);
    }
    return out;
}

// The original triangles of every source in one bounding volume hierarchy (closest_point.h), with
// their colours. A triangle is named by its place in the hierarchy's leaf order.
class OriginalSurface {
public:
    explicit OriginalSurface(const std::vector<BakeSource>& sources) : sources_(sources) {
        std::vector<float> positions;
        std::vector<uint32_t> indices;
        for (const BakeSource& source : sources) {
            first_.push_back(static_cast<uint32_t>(indices.size() / 3));
            if (!source.mesh) continue;
            const uint32_t base = static_cast<uint32_t>(positions.size() / 3);
            positions.insert(positions.end(), source.mesh->positions.begin(), source.mesh->positions.end());
            for (uint32_t i : source.mesh->indices) indices.push_back(base + i);
        }
        bvh_ = buildTriangleBvh(positions, indices);  // zero-area triangles left out
        if (bvh_.empty()) return;
        double extent = 0;  // of the triangles' box (the hierarchy's root), in doubles
        for (int k = 0; k < 3; ++k) extent = std::max(extent, double(bvh_.pairs[0].hi[k][0]) - bvh_.pairs[0].lo[k][0]);
        if (std::isfinite(extent)) enough2_ = (kEnough * extent) * (kEnough * extent);
    }

    // Index of the original triangle closest to p (on a simplified triangle of normal n); kNone
    // when there is none. The previous answer's triangle is the search's first bound (a k-d tree of
    // hints took 7 of the 14.5 CPU-ms fixed cost of a node with 32 k original triangles,
    // pipeline/BAKE.md). When that triangle faces away from n (the far side of a thin sheet or
    // wall), the nearest triangle facing n along the line p + t n within kFacingReach x the
    // closest distance is taken instead, if there is one. The search ends at a triangle within a
    // millionth of the sources' extent (kEnough; closest_point.h's enough2): where the node lies on
    // its original (a flat fan of per-face charts: every box holding p lies at 0 from it) an exact
    // search visited every such box (a 20,000-triangle fan built in 4.7 CPU-s, 2.9 with it; the
    // banana's and hlod_bench_bake's PSNRs the same, measured in stop 52).
    uint32_t closest(const Point& p, const Point& n) {
        if (bvh_.empty()) return kNone;
        const double d2 = squaredDistance(bvh_, p.data(), hint_, enough2_);
        if (hint_ == kNone) return kNone;  // p not a number
        if (dot(normal(hint_), n) >= 0) return hint_;
        double reach = kFacingReach * std::sqrt(d2);
        const double length = std::sqrt(dot(n, n));
        const Point unit = {n[0] / length, n[1] / length, n[2] / length};
        for (const Point& direction : {unit, Point{-unit[0], -unit[1], -unit[2]}})
            if (const double t = firstHit(bvh_, p.data(), direction.data(), reach, n.data(), hint_); t < reach) reach = t;
        return hint_;
    }

    // The source colour at the point of triangle `index` closest to p.
    Rgb colour(uint32_t index, const Point& p) const {
        Rgb grey;
        std::fill_n(grey.c, 3, kUntexturedGrey);
        if (index == kNone) return grey;
        const uint32_t input = bvh_.input[index];
        const uint32_t s = static_cast<uint32_t>(std::upper_bound(first_.begin(), first_.end(), input) - first_.begin() - 1);
        const uint32_t t = input - first_[s];
        const MeshData& m = *sources_[s].mesh;
        double w[3];
        closestWeights(corner(index, 0), corner(index, 1), corner(index, 2), p, w);
        const uint32_t* i = &m.indices[3 * t];
        const Image* image = sources_[s].texture;
        if (image && image->channels > 0 && image->pixels.size() == size_t(image->width) * image->height * image->channels &&
            !image->pixels.empty() && m.texcoords.size() == 2 * m.vertexCount()) {
            double u = 0, v = 0;
            for (int k = 0; k < 3; ++k) u += w[k] * m.texcoords[2 * i[k]], v += w[k] * m.texcoords[2 * i[k] + 1];
            return bilinear(*image, u * image->width, v * image->height);
        }
        if (m.colors.size() != 4 * m.vertexCount()) return grey;
        Rgb out;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) out.c[c] += static_cast<float>(w[k] * m.colors[4 * i[k] + c]);
        return out;
    }

private:
    Point corner(uint32_t index, int k) const {
        const float* v = &bvh_.triangles[index].corners[3 * k];
        return {v[0], v[1], v[2]};
    }
    Point normal(uint32_t index) const { return cross(minus(corner(index, 1), corner(index, 0)), minus(corner(index, 2), corner(index, 0))); }

    const std::vector<BakeSource>& sources_;
    std::vector<uint32_t> first_;  // per source, the input index of its first triangle
    TriangleBvh bvh_;
    uint32_t hint_ = kNone;  // the previous answer
    double enough2_ = 0;
};

// A baked texel: its index in the atlas and its sub-samples' source colours (row by row).
struct BakedTexel {
    uint32_t at;
    Rgb colour[kSuper * kSuper];
};

// Sub-sample (sx, sy)'s atlas coordinate on one axis of texel t.
float subSample(int t, int s) { return static_cast<float>(t + (s + 0.5) / kSuper); }

// Bakes the chart's covered texels into `atlas`, marking them 1 in `covered` and adding them to `baked`.
void bakeChart(const MeshData& simplified, const FlatChart& chart, const AtlasLayout& l, const ChartPlacement& r, OriginalSurface& surface,
               std::vector<uint8_t>& covered, Image& atlas, std::vector<BakedTexel>& baked) {
    const double ox = r.x + kChartGutter, oy = r.y + kChartGutter;
    for (size_t j = 0; j < chart.triangles.size(); ++j) {
        const double* uv = &chart.uv[6 * j];
        const double tx[3] = {ox + uv[0] * l.scale, ox + uv[2] * l.scale, ox + uv[4] * l.scale};
        const double ty[3] = {oy + uv[1] * l.scale, oy + uv[3] * l.scale, oy + uv[5] * l.scale};
        const double area = (tx[1] - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (ty[1] - ty[0]);
        if (area == 0) continue;
        const uint32_t* vi = &simplified.indices[3 * chart.triangles[j]];
        const Point p[3] = {vertex(simplified, vi[0]), vertex(simplified, vi[1]), vertex(simplified, vi[2])};
        const Point normal = cross(minus(p[1], p[0]), minus(p[2], p[0]));
        auto lift = [&](double x, double y) {  // texel coordinates -> point of the simplified triangle's plane
            const double b1 = ((x - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (y - ty[0])) / area;
            const double b2 = ((tx[1] - tx[0]) * (y - ty[0]) - (x - tx[0]) * (ty[1] - ty[0])) / area;
            return Point{p[0][0] + b1 * (p[1][0] - p[0][0]) + b2 * (p[2][0] - p[0][0]),
                         p[0][1] + b1 * (p[1][1] - p[0][1]) + b2 * (p[2][1] - p[0][1]),
                         p[0][2] + b1 * (p[1][2] - p[0][2]) + b2 * (p[2][2] - p[0][2])};
        };
        auto inside = [&](double x, double y) {
            const double e[3] = {(tx[1] - tx[0]) * (y - ty[0]) - (x - tx[0]) * (ty[1] - ty[0]),
                                 (tx[2] - tx[1]) * (y - ty[1]) - (x - tx[1]) * (ty[2] - ty[1]),
                                 (tx[0] - tx[2]) * (y - ty[2]) - (x - tx[2]) * (ty[0] - ty[2])};
            return area > 0 ? e[0] >= 0 && e[1] >= 0 && e[2] >= 0 : e[0] <= 0 && e[1] <= 0 && e[2] <= 0;
        };
        auto bake = [&](int x, int y) {
            const size_t at = size_t(y) * atlas.width + x;
            covered[at] = 1;
            const uint32_t nearest = surface.closest(lift(x + 0.5, y + 0.5), normal);
            BakedTexel& texel = baked.emplace_back();
            texel.at = static_cast<uint32_t>(at);
            Rgb sum;
            for (int sy = 0; sy < kSuper; ++sy)
                for (int sx = 0; sx < kSuper; ++sx) {
                    const double qx = x + (sx + 0.5) / kSuper, qy = y + (sy + 0.5) / kSuper;
                    const Rgb c = texel.colour[sy * kSuper + sx] = surface.colour(nearest, lift(qx, qy));
                    for (int k = 0; k < 3; ++k) sum.c[k] += c.c[k];
                }
            for (int k = 0; k < 3; ++k)
                atlas.pixels[3 * at + k] = static_cast<uint8_t>(std::clamp(std::lround(sum.c[k] / (kSuper * kSuper)), 0l, 255l));
        };
        const int x0 = std::max(r.x, static_cast<int>(std::floor(std::min({tx[0], tx[1], tx[2]}) - 0.5)));
        const int x1 = std::min(r.x + r.w - 1, static_cast<int>(std::ceil(std::max({tx[0], tx[1], tx[2]}) - 0.5)));
        const int y0 = std::max(r.y, static_cast<int>(std::floor(std::min({ty[0], ty[1], ty[2]}) - 0.5)));
        const int y1 = std::min(r.y + r.h - 1, static_cast<int>(std::ceil(std::max({ty[0], ty[1], ty[2]}) - 0.5)));
        bool any = false;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x)
                if (inside(x + 0.5, y + 0.5)) {
                    any = true;
                    if (!covered[size_t(y) * atlas.width + x]) bake(x, y);
                }
        const int cx = static_cast<int>((tx[0] + tx[1] + tx[2]) / 3), cy = static_cast<int>((ty[0] + ty[1] + ty[2]) / 3);
        if (!any && !covered[size_t(cy) * atlas.width + cx]) bake(cx, cy);
    }
}

// Fills the texels of the chart's blocks that were not baked with copies of the nearest baked
// one (breadth-first over 8-neighbours, in scan order: deterministic).
void dilate(const AtlasLayout& l, uint32_t chart, std::vector<uint8_t>& covered, Image& atlas) {
    const ChartPlacement& r = l.places[chart];
    const int columns = l.width / kJpegBlock;
    auto mine = [&](int x, int y) {
        return x >= r.x && x < r.x + r.w && y >= r.y && y < r.y + r.h &&
               l.blockOwner[size_t(y / kJpegBlock) * columns + x / kJpegBlock] == chart;
    };
    std::vector<size_t> queue;
    for (int y = r.y; y < r.y + r.h; ++y)
        for (int x = r.x; x < r.x + r.w; ++x)
            if (covered[size_t(y) * atlas.width + x] == 1 && mine(x, y)) queue.push_back(size_t(y) * atlas.width + x);
    for (size_t head = 0; head < queue.size(); ++head) {
        const int x = static_cast<int>(queue[head] % atlas.width), y = static_cast<int>(queue[head] / atlas.width);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                if (!mine(x + dx, y + dy)) continue;
                const size_t at = size_t(y + dy) * atlas.width + (x + dx);
                if (covered[at]) continue;
                covered[at] = 2;  // filled, not baked
                std::copy_n(&atlas.pixels[3 * queue[head]], 3, &atlas.pixels[3 * at]);
                queue.push_back(at);
            }
    }
}

}  // namespace

BakedTexture bakeTexture(const MeshData& input, const std::vector<BakeSource>& original, uint64_t texelBudget) {
    BakedTexture out;
    MeshData simplified;  // without its zero-area triangles, which cover nothing and have no chart
    simplified.positions = input.positions, simplified.normals = input.normals, simplified.colors = input.colors;
    for (size_t t = 0; t < input.triangleCount(); ++t) {
        const uint32_t* i = &input.indices[3 * t];
        if (!zeroArea(&input.positions[3 * i[0]], &input.positions[3 * i[1]], &input.positions[3 * i[2]]))
            simplified.indices.insert(simplified.indices.end(), i, i + 3);
    }
    if (simplified.triangleCount() == 0) return out;
    const std::vector<FlatChart> charts = flattenCharts(simplified);
    const AtlasLayout l = packCharts(charts, texelBudget);
    out.image = {static_cast<uint32_t>(l.width), static_cast<uint32_t>(l.height), 3, {}};
    out.image.pixels.assign(size_t(l.width) * l.height * 3, static_cast<uint8_t>(kUntexturedGrey));
    // The mesh: every chart gets its own copies of its vertices, UVs in [0, 1] over the atlas.
    const bool normals = simplified.normals.size() == 3 * simplified.vertexCount();
    const bool colors = simplified.colors.size() == 4 * simplified.vertexCount();
    std::vector<uint32_t> copyOf(simplified.vertexCount(), kNone);
    for (size_t c = 0; c < charts.size(); ++c) {
        std::vector<uint32_t> touched;
        for (size_t j = 0; j < charts[c].triangles.size(); ++j)
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = simplified.indices[3 * charts[c].triangles[j] + k];
                if (copyOf[v] == kNone) {
                    copyOf[v] = static_cast<uint32_t>(out.mesh.vertexCount());
                    touched.push_back(v);
                    MeshData& m = out.mesh;
                    m.positions.insert(m.positions.end(), &simplified.positions[3 * v], &simplified.positions[3 * v + 3]);
                    if (normals) m.normals.insert(m.normals.end(), &simplified.normals[3 * v], &simplified.normals[3 * v + 3]);
                    if (colors) m.colors.insert(m.colors.end(), &simplified.colors[4 * v], &simplified.colors[4 * v + 4]);
                    const double* uv = &charts[c].uv[6 * j + 2 * k];
                    m.texcoords.push_back(static_cast<float>((l.places[c].x + kChartGutter + uv[0] * l.scale) / l.width));
                    m.texcoords.push_back(static_cast<float>((l.places[c].y + kChartGutter + uv[1] * l.scale) / l.height));
                }
                out.mesh.indices.push_back(copyOf[v]);
            }
        for (uint32_t v : touched) copyOf[v] = kNone;
    }
    // Baking, then the gutters, then the error, chart by chart: a chart's baked and filled texels
    // and the texels its sub-samples' bilinear taps read (within kChartGutter of its triangles)
    // are all in its own blocks, which no other chart writes, so each chart is final once it is
    // filled (the same texels as baking every chart before filling any), and only one chart's
    // sub-samples are held at a time (summed in the same order; Bake.AChartsTexelsDependOnItsOwnSourceAlone).
    OriginalSurface surface(original);
    std::vector<uint8_t> covered(size_t(l.width) * l.height, 0);
    std::vector<BakedTexel> baked;
    double squared = 0;
    size_t sampleCount = 0;
    for (uint32_t c = 0; c < charts.size(); ++c) {
        baked.clear();
        bakeChart(simplified, charts[c], l, l.places[c], surface, covered, out.image, baked);
        dilate(l, c, covered, out.image);
        for (const BakedTexel& t : baked) {
            const int x = static_cast<int>(t.at % out.image.width), y = static_cast<int>(t.at / out.image.width);
            for (int sy = 0; sy < kSuper; ++sy)
                for (int sx = 0; sx < kSuper; ++sx) {
                    const Rgb shown = bilinear(out.image, subSample(x, sx), subSample(y, sy)), &source = t.colour[sy * kSuper + sx];
                    for (int k = 0; k < 3; ++k) squared += double(shown.c[k] - source.c[k]) * (shown.c[k] - source.c[k]);
                }
        }
        sampleCount += baked.size() * kSuper * kSuper;
    }
    for (uint8_t v : covered) out.coveredTexels += v == 1;  // baked (2: filled)
    out.psnr = psnrDb(squared, 3 * sampleCount);
    return out;
}

}  // namespace hlod
