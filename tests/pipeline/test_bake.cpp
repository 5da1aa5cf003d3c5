// Texture baking (pipeline/bake.cpp, chart.cpp, pack_charts.cpp): a wavy terrain split into two
// materials with smooth procedural textures, simplified 8x, baked: charts never overlap and no
// 8 x 8 JPEG block holds two charts (checked by rasterising every UV triangle at 4x the atlas
// resolution), UVs in [0, 1], no zero-area UV triangle, the atlas within its budget, the baked
// colours close to the source (PSNR); a constant source baked exactly; determinism; small and
// zero budgets; vertex colours on an untextured sphere; a folded surface split into charts; a
// thin sheet baked from the side the simplified surface faces; a chart's texels independent of
// other charts' sources (the chart-by-chart baking).
#include "helpers.h"

#include "pipeline/chart.h"
#include "tests/support/synthetic.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

namespace hlod::test {
namespace {

Image constantTexture(uint32_t size, uint8_t r, uint8_t g, uint8_t b) {
    Image img{size, size, 3, {}};
    for (uint32_t i = 0; i < size * size; ++i) img.pixels.insert(img.pixels.end(), {r, g, b});
    return img;
}

struct Fixture {
    std::vector<SubMesh> parts;  // original triangles per material
    MeshData simplified;         // all materials, simplified
};

Fixture terrainFixture(uint32_t n, double factor) {
    const Piece piece = terrain(n, 100, true);
    Fixture f;
    f.parts = splitByMaterial(piece);
    MeshData whole = piece.mesh;
    whole.texcoords.clear();
    f.simplified = simplifyMesh(whole, factor, Simplifier::Meshopt);
    return f;
}

std::vector<BakeSource> sources(const Fixture& f, const std::vector<Image>& images) {
    std::vector<BakeSource> s;
    for (size_t i = 0; i < f.parts.size(); ++i) s.push_back({&f.parts[i].mesh, &images[i]});
    return s;
}

// Charts of the baked mesh: triangles connected through vertices equal in position and UV.
std::vector<uint32_t> chartOfTriangle(const MeshData& m) {
    std::map<std::array<float, 5>, uint32_t> id;
    std::vector<uint32_t> parent;
    auto find = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::vector<uint32_t> corner(m.indices.size());
    for (size_t i = 0; i < m.indices.size(); ++i) {
        const uint32_t v = m.indices[i];
        const std::array<float, 5> key = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2], m.texcoords[2 * v],
                                          m.texcoords[2 * v + 1]};
        auto [it, added] = id.emplace(key, static_cast<uint32_t>(parent.size()));
        if (added) parent.push_back(it->second);
        corner[i] = it->second;
    }
    for (size_t t = 0; t < m.triangleCount(); ++t)
        for (int k = 1; k < 3; ++k) parent[find(corner[3 * t + k])] = find(corner[3 * t]);
    std::vector<uint32_t> chart(m.triangleCount());
    for (size_t t = 0; t < chart.size(); ++t) chart[t] = find(corner[3 * t]);
    return chart;
}

// Rasterises every UV triangle at `fine` x the atlas resolution (sample points strictly inside):
// returns the samples inside more than one triangle (0 when no two triangles overlap), and the
// 8 x 8 atlas blocks holding samples of two charts (0 when JPEG never mixes charts).
std::pair<size_t, size_t> overlaps(const MeshData& m, uint32_t width, uint32_t height, int fine) {
    const uint32_t w = width * fine, h = height * fine;
    std::vector<uint8_t> count(size_t(w) * h, 0);
    const std::vector<uint32_t> chart = chartOfTriangle(m);
    std::vector<uint32_t> blockChart(size_t((width + 7) / 8) * ((height + 7) / 8), kNone);
    size_t samples = 0, blocks = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        double x[3], y[3];
        for (int k = 0; k < 3; ++k) x[k] = m.texcoords[2 * m.indices[3 * t + k]] * w, y[k] = m.texcoords[2 * m.indices[3 * t + k] + 1] * h;
        const double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
        const int x0 = std::max(0, int(std::min({x[0], x[1], x[2]}))), x1 = std::min(int(w) - 1, int(std::max({x[0], x[1], x[2]})));
        const int y0 = std::max(0, int(std::min({y[0], y[1], y[2]}))), y1 = std::min(int(h) - 1, int(std::max({y[0], y[1], y[2]})));
        for (int py = y0; py <= y1; ++py)
            for (int px = x0; px <= x1; ++px) {
                const double sx = px + 0.5, sy = py + 0.5;
                bool inside = true;
                for (int k = 0; k < 3; ++k) {
                    const int a = k, b = (k + 1) % 3;
                    const double e = ((x[b] - x[a]) * (sy - y[a]) - (sx - x[a]) * (y[b] - y[a])) / area;
                    inside = inside && e > 1e-6;
                }
                if (!inside) continue;
                if (++count[size_t(py) * w + px] == 2) ++samples;
                uint32_t& owner = blockChart[size_t(py / fine / 8) * ((width + 7) / 8) + px / fine / 8];
                if (owner == kNone) owner = chart[t];
                else if (owner != chart[t] && owner != kNone - 1) ++blocks, owner = kNone - 1;
            }
    }
    return {samples, blocks};
}

// Triangles of `m` with a non-zero area (bakeTexture drops the others).
size_t solidTriangles(const MeshData& m) {
    size_t n = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) n += triangleArea(m, t) > 0;
    return n;
}

void expectValidAtlas(const BakedTexture& baked, uint64_t budget, const MeshData& simplified) {
    const MeshData& m = baked.mesh;
    ASSERT_EQ(m.triangleCount(), solidTriangles(simplified));
    ASSERT_EQ(m.texcoords.size(), 2 * m.vertexCount());
    ASSERT_EQ(baked.image.channels, 3u);
    ASSERT_EQ(baked.image.pixels.size(), size_t(baked.image.width) * baked.image.height * 3);
    EXPECT_LE(uint64_t(baked.image.width) * baked.image.height, budget);
    EXPECT_GT(baked.coveredTexels, 0u);
    EXPECT_LE(baked.coveredTexels, uint64_t(baked.image.width) * baked.image.height);
    for (float c : m.texcoords) {
        EXPECT_GE(c, 0.0f);
        EXPECT_LE(c, 1.0f);
    }
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const float* a = &m.texcoords[2 * m.indices[3 * t]];
        const float* b = &m.texcoords[2 * m.indices[3 * t + 1]];
        const float* c = &m.texcoords[2 * m.indices[3 * t + 2]];
        EXPECT_NE((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]), 0.0f) << "triangle " << t;
    }
    const auto [samples, blocks] = overlaps(m, baked.image.width, baked.image.height, 4);
    EXPECT_EQ(samples, 0u);
    EXPECT_EQ(blocks, 0u);
}

TEST(Bake, TerrainChartsAreValidAndColoursFaithful) {
    const Fixture f = terrainFixture(64, 8);  // 8,192 -> ~1,000 triangles
    const std::vector<Image> images = {smoothTexture(512, 0), smoothTexture(512, 1)};
    const uint64_t budget = 256 * 256;
    const BakedTexture baked = bakeTexture(f.simplified, sources(f, images), budget);
    expectValidAtlas(baked, budget, f.simplified);
    // The baked atlas uses most of its budget; positions are the simplified ones.
    EXPECT_GE(baked.coveredTexels, budget / 3);
    EXPECT_NEAR(meshArea(baked.mesh), meshArea(f.simplified), 1e-3 * meshArea(f.simplified));
    // Smooth textures, ~1 baked texel per 5 source texels: measured 42.3 dB.
    EXPECT_GE(baked.psnr, 38.0);
    std::printf("terrain: %llu covered texels, PSNR %.2f dB\n", static_cast<unsigned long long>(baked.coveredTexels), baked.psnr);
}

TEST(Bake, IsDeterministic) {
    const Fixture f = terrainFixture(32, 4);
    const std::vector<Image> images = {smoothTexture(128, 2), smoothTexture(128, 3)};
    const BakedTexture a = bakeTexture(f.simplified, sources(f, images), 128 * 128);
    const BakedTexture b = bakeTexture(f.simplified, sources(f, images), 128 * 128);
    EXPECT_EQ(a.mesh.texcoords, b.mesh.texcoords);
    EXPECT_EQ(a.mesh.indices, b.mesh.indices);
    EXPECT_EQ(a.image.pixels, b.image.pixels);
    EXPECT_EQ(a.psnr, b.psnr);
}

TEST(Bake, ConstantSourceBakesExactly) {
    const Fixture f = terrainFixture(32, 4);
    const std::vector<Image> images = {constantTexture(64, 40, 120, 200), constantTexture(64, 40, 120, 200)};
    const BakedTexture baked = bakeTexture(f.simplified, sources(f, images), 128 * 128);
    expectValidAtlas(baked, 128 * 128, f.simplified);
    EXPECT_GE(baked.psnr, 99.0);  // MSE 0
    // Every texel a bilinear tap at any corner or centroid of a triangle reads holds the colour.
    const Image& img = baked.image;
    for (size_t t = 0; t < baked.mesh.triangleCount(); ++t) {
        double cu = 0, cv = 0;
        for (int k = 0; k <= 3; ++k) {
            double u = cu / 3, v = cv / 3;
            if (k < 3) {
                u = baked.mesh.texcoords[2 * baked.mesh.indices[3 * t + k]], v = baked.mesh.texcoords[2 * baked.mesh.indices[3 * t + k] + 1];
                cu += u, cv += v;
            }
            const int x = std::clamp(int(std::floor(u * img.width - 0.5)), 0, int(img.width) - 2);
            const int y = std::clamp(int(std::floor(v * img.height - 0.5)), 0, int(img.height) - 2);
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const uint8_t* p = &img.pixels[3 * (size_t(y + dy) * img.width + x + dx)];
                    ASSERT_EQ(p[0], 40) << "triangle " << t;
                    ASSERT_EQ(p[1], 120) << "triangle " << t;
                    ASSERT_EQ(p[2], 200) << "triangle " << t;
                }
        }
    }
}

TEST(Bake, SmallBudgetStaysWithinIt) {
    const Fixture f = terrainFixture(32, 4);
    const std::vector<Image> images = {smoothTexture(128, 0), smoothTexture(128, 1)};
    const BakedTexture baked = bakeTexture(f.simplified, sources(f, images), 64 * 64);
    expectValidAtlas(baked, 64 * 64, f.simplified);
}

// A UV sphere, radius 1, with a vertex colour per vertex: colour(position).
template <class Colour>
MeshData colouredSphere(Colour colour) {
    MeshData sphere;
    const int rings = 24, segments = 48;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const double th = M_PI * r / rings, ph = 2 * M_PI * s / segments;
            const float p[3] = {float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th))};
            sphere.positions.insert(sphere.positions.end(), p, p + 3);
            const std::array<uint8_t, 4> c = colour(p);
            sphere.colors.insert(sphere.colors.end(), c.begin(), c.end());
        }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = r * (segments + 1) + s, b = a + 1, c = a + segments + 1, d = c + 1;
            if (r > 0) sphere.indices.insert(sphere.indices.end(), {a, c, b});
            if (r + 1 < rings) sphere.indices.insert(sphere.indices.end(), {b, c, d});
        }
    return sphere;
}

// A UV sphere with a vertex-colour gradient and no texture: many charts, vertex colours baked.
TEST(Bake, UntexturedSphereUsesVertexColours) {
    const MeshData sphere = colouredSphere([](const float* p) {
        return std::array<uint8_t, 4>{uint8_t(127 + 127 * p[2]), 60, uint8_t(127 - 127 * p[2]), 255};
    });
    MeshData coarse = simplifyMesh(sphere, 4, Simplifier::Meshopt);
    coarse.colors.clear();
    const std::vector<BakeSource> source = {{&sphere, nullptr}};
    const BakedTexture baked = bakeTexture(coarse, source, 128 * 128);
    expectValidAtlas(baked, 128 * 128, coarse);
    // A closed surface needs several charts (a 60-degree cone covers at most 120 degrees).
    EXPECT_GE(flattenCharts(coarse).size(), 4u);
    EXPECT_GE(baked.psnr, 45.0);  // measured 57.2 dB
    std::printf("sphere: %llu covered texels, PSNR %.2f dB\n", static_cast<unsigned long long>(baked.coveredTexels), baked.psnr);
    // A red-dominated texel near the +z pole, blue near -z: sample at the vertex closest to each pole.
    for (int pole : {1, -1}) {
        size_t best = 0;
        for (size_t v = 0; v < baked.mesh.vertexCount(); ++v)
            if (pole * baked.mesh.positions[3 * v + 2] > pole * baked.mesh.positions[3 * best + 2]) best = v;
        const uint32_t x = std::min(baked.image.width - 1, uint32_t(baked.mesh.texcoords[2 * best] * baked.image.width));
        const uint32_t y = std::min(baked.image.height - 1, uint32_t(baked.mesh.texcoords[2 * best + 1] * baked.image.height));
        const uint8_t* p = &baked.image.pixels[3 * (size_t(y) * baked.image.width + x)];
        EXPECT_GT(pole * (int(p[0]) - int(p[2])), 150) << "pole " << pole;
    }
}

// A spiral ramp (two turns, gentle pitch): every normal is within the cone of the first one,
// but one projection would fold the second turn over the first. The chart is split instead.
TEST(Bake, FoldedSurfaceIsSplitIntoNonOverlappingCharts) {
    MeshData ramp;
    const int steps = 96, across = 4;
    for (int i = 0; i <= steps; ++i)
        for (int j = 0; j <= across; ++j) {
            const double angle = 4 * M_PI * i / steps, radius = 1 + 0.25 * j;
            ramp.positions.insert(ramp.positions.end(),
                                  {float(radius * std::cos(angle)), float(radius * std::sin(angle)), float(0.1 * angle)});
        }
    for (int i = 0; i < steps; ++i)
        for (int j = 0; j < across; ++j) {
            const uint32_t a = i * (across + 1) + j, b = a + 1, c = a + across + 1, d = c + 1;
            ramp.indices.insert(ramp.indices.end(), {a, b, d, a, d, c});
        }
    std::vector<double> all;  // the whole ramp on z overlaps itself
    for (uint32_t v : ramp.indices) all.insert(all.end(), {ramp.positions[3 * v], ramp.positions[3 * v + 1]});
    ASSERT_TRUE(trianglesOverlap(all));
    const std::vector<FlatChart> charts = flattenCharts(ramp);
    EXPECT_GE(charts.size(), 2u);
    size_t triangles = 0;
    for (const FlatChart& c : charts) {
        EXPECT_FALSE(trianglesOverlap(c.uv));
        EXPECT_GE(c.width, c.height);
        triangles += c.triangles.size();
    }
    EXPECT_EQ(triangles, ramp.triangleCount());
    const MeshData source = ramp;
    const BakedTexture baked = bakeTexture(ramp, {{&source, nullptr}}, 64 * 64);
    expectValidAtlas(baked, 64 * 64, ramp);
}

// A budget below one block per chart: one block per chart, every triangle still mapped; an empty
// texture counts as none (grey).
TEST(Bake, TinyBudgetAndEmptyTexture) {
    const Fixture f = terrainFixture(16, 2);
    const std::vector<Image> images = {Image{}, Image{}};
    const BakedTexture baked = bakeTexture(f.simplified, sources(f, images), 0);
    ASSERT_EQ(baked.mesh.triangleCount(), solidTriangles(f.simplified));
    EXPECT_EQ(baked.image.width % 8, 0u);
    EXPECT_EQ(baked.image.height % 8, 0u);
    EXPECT_GT(baked.coveredTexels, 0u);
    EXPECT_GE(baked.psnr, 99.0);  // grey everywhere
}

// A thin sheet: red facing +z at z = 0, blue facing -z at z = -0.01. A simplified square facing +z
// at z = -0.006 is closer to the blue side; it takes the red side, which faces it.
TEST(Bake, ThinSheetTakesTheSideItFaces) {
    auto grid = [](float z, bool up) {
        MeshData m;
        const uint32_t n = 8;
        for (uint32_t j = 0; j <= n; ++j)
            for (uint32_t i = 0; i <= n; ++i) {
                m.positions.insert(m.positions.end(), {float(i) / n, float(j) / n, z});
                m.texcoords.insert(m.texcoords.end(), {float(i) / n, float(j) / n});
            }
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
                if (up) m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
                else m.indices.insert(m.indices.end(), {a, d, b, a, c, d});
            }
        return m;
    };
    const MeshData front = grid(0, true), back = grid(-0.01f, false);
    const std::vector<Image> images = {constantTexture(16, 220, 20, 20), constantTexture(16, 20, 20, 220)};
    MeshData square;
    square.positions = {0, 0, -0.006f, 1, 0, -0.006f, 1, 1, -0.006f, 0, 1, -0.006f};
    square.indices = {0, 1, 2, 0, 2, 3};
    const BakedTexture baked = bakeTexture(square, {{&front, &images[0]}, {&back, &images[1]}}, 64 * 64);
    expectValidAtlas(baked, 64 * 64, square);
    EXPECT_GE(baked.psnr, 99.0);
    for (size_t v = 0; v < baked.mesh.vertexCount(); ++v) {
        const uint32_t x = std::min(baked.image.width - 1, uint32_t(baked.mesh.texcoords[2 * v] * baked.image.width));
        const uint32_t y = std::min(baked.image.height - 1, uint32_t(baked.mesh.texcoords[2 * v + 1] * baked.image.height));
        const uint8_t* p = &baked.image.pixels[3 * (size_t(y) * baked.image.width + x)];
        EXPECT_EQ(p[0], 220) << "vertex " << v;
        EXPECT_EQ(p[2], 20) << "vertex " << v;
    }
}

// The baker finishes one chart (baked, gutters filled, error summed) before the next, which is
// only right if no chart writes or reads another's blocks. The same sphere baked twice, its
// colours changed only where z > 0: the same charts and layout, and every chart wholly below
// z = -0.3 (beyond what its texels sample) keeps every texel of its blocks, while the atlas does
// change above.
TEST(Bake, AChartsTexelsDependOnItsOwnSourceAlone) {
    auto gradient = [](bool changed) {
        return [changed](const float* p) {
            const uint8_t red = changed && p[2] > 0 ? uint8_t(255 - 100 * p[2]) : uint8_t(127 + 60 * p[0]);
            return std::array<uint8_t, 4>{red, uint8_t(127 + 60 * p[1]), uint8_t(127 + 60 * p[2]), 255};
        };
    };
    const MeshData before = colouredSphere(gradient(false)), after = colouredSphere(gradient(true));
    MeshData coarse = simplifyMesh(before, 4, Simplifier::Meshopt);
    coarse.colors.clear();
    const BakedTexture a = bakeTexture(coarse, {{&before, nullptr}}, 128 * 128);
    const BakedTexture b = bakeTexture(coarse, {{&after, nullptr}}, 128 * 128);
    ASSERT_EQ(a.mesh.texcoords, b.mesh.texcoords);
    ASSERT_EQ(a.image.width, b.image.width);
    ASSERT_EQ(a.image.height, b.image.height);
    EXPECT_NE(a.image.pixels, b.image.pixels);
    const std::vector<uint32_t> chart = chartOfTriangle(a.mesh);
    std::map<uint32_t, bool> low;  // chart -> every corner below z = -0.3
    for (size_t t = 0; t < chart.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const bool below = a.mesh.positions[3 * a.mesh.indices[3 * t + k] + 2] < -0.3f;
            low.emplace(chart[t], true).first->second &= below;
        }
    const uint32_t columns = a.image.width / 8;
    std::set<uint32_t> blocks;  // the 8 x 8 blocks of low charts' corners and centroids: their own
    for (size_t t = 0; t < chart.size(); ++t) {
        if (!low[chart[t]]) continue;
        double centroid[2] = {0, 0};
        for (int k = 0; k <= 3; ++k) {
            double uv[2] = {centroid[0] / 3, centroid[1] / 3};
            for (int c = 0; k < 3 && c < 2; ++c) centroid[c] += uv[c] = a.mesh.texcoords[2 * a.mesh.indices[3 * t + k] + c];
            const uint32_t x = std::min(a.image.width - 1, uint32_t(uv[0] * a.image.width));
            const uint32_t y = std::min(a.image.height - 1, uint32_t(uv[1] * a.image.height));
            blocks.insert(y / 8 * columns + x / 8);
        }
    }
    ASSERT_GE(blocks.size(), 16u) << "some charts lie low";
    size_t differing = 0;
    for (uint32_t block : blocks)
        for (uint32_t y = block / columns * 8; y < block / columns * 8 + 8; ++y)
            for (uint32_t x = block % columns * 8; x < block % columns * 8 + 8; ++x)
                for (int c = 0; c < 3; ++c) differing += a.image.pixels[3 * (size_t(y) * a.image.width + x) + c] != b.image.pixels[3 * (size_t(y) * a.image.width + x) + c];
    EXPECT_EQ(differing, 0u) << "of " << blocks.size() << " blocks";
}

TEST(Bake, EmptyInputGivesAnEmptyResult) {
    const BakedTexture baked = bakeTexture(MeshData{}, {}, 1024);
    EXPECT_EQ(baked.mesh.triangleCount(), 0u);
    EXPECT_EQ(baked.coveredTexels, 0u);
}

}  // namespace
}  // namespace hlod::test
