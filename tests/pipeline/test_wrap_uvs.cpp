// UV charts in another period of a repeating texture are moved into [0, 1] (pipeline/wrap_uvs.cpp):
// by whole periods of their material's wrap (REPEAT 1, MIRRORED_REPEAT 2, mirrored in its odd
// periods), never a chart that straddles a period's edge (counted: the build warns), one of a clamped or untextured material; OBJ's `-clamp on` and glTF's
// samplers are read; a scan whose charts sit in other periods builds the database of the same scan
// with its UVs in [0, 1].
#include "helpers.h"

#include "pipeline/texture_charts.h"
#include "tests/support/run_hlod.h"

namespace hlod::test {
namespace {

namespace fs = std::filesystem;

// One triangle (its own chart) of `material` with UVs u0 + {0, 0.25, 0}, v0 + {0, 0, 0.25}.
void addChart(Piece& p, uint32_t material, float u0, float v0) {
    const uint32_t first = static_cast<uint32_t>(p.mesh.vertexCount());
    p.mesh.positions.insert(p.mesh.positions.end(), {float(first), 0, 0, float(first) + 1, 0, 0, float(first), 1, 0});
    p.mesh.texcoords.insert(p.mesh.texcoords.end(), {u0, v0, u0 + 0.25f, v0, u0, v0 + 0.25f});
    p.mesh.indices.insert(p.mesh.indices.end(), {first, first + 1, first + 2});
    p.materials.push_back(material);
}

TEST(WrapUvs, ChartsInAnotherPeriodMoveIntoTheTexture) {
    const auto image = std::make_shared<const Image>(testImage(8, 8));
    std::vector<Material> materials(4);
    materials[0].image = materials[1].image = materials[2].image = image;
    materials[1].uvPeriod[0] = materials[1].uvPeriod[1] = 0;  // CLAMP_TO_EDGE
    materials[2].uvPeriod[0] = materials[2].uvPeriod[1] = 2;  // MIRRORED_REPEAT
    struct Case {
        uint32_t material;
        float u0, v0, u1, v1;  // before, and expected after
        float du = 0.25f;      // the chart's u step after: -0.25 where mirrored
    };
    const std::vector<Case> cases = {
        {0, 1.25f, 0.25f, 0.25f, 0.25f},      // one period to the right
        {0, -2.75f, 3.0f, 0.25f, 0.0f},       // periods to the left and below
        {0, 0.875f, 0.5f, 0.875f, 0.5f},      // straddles u = 1: stays
        {0, 0.25f, 0.5f, 0.25f, 0.5f},        // inside: stays
        {1, 1.25f, 1.25f, 1.25f, 1.25f},      // clamped: stays
        {2, 2.25f, -1.75f, 0.25f, 0.25f},     // mirrored: two periods right, one mirrored pair up
        {2, 1.25f, 0.25f, 0.75f, 0.25f, -0.25f},  // the mirrored period: u -> 2 - u (clamped until stop 46)
        {2, -0.75f, 2.25f, 0.75f, 0.25f, -0.25f}, // a mirrored period to the left, two periods up
        {3, 1.25f, 0.25f, 1.25f, 0.25f},      // untextured: stays
    };
    Piece p;
    for (const Case& c : cases) addChart(p, c.material, c.u0, c.v0);
    EXPECT_EQ(wrapUvCharts(p, materials), 1u);  // the chart straddling u = 1 (the clamped one is as its sampler says)
    for (size_t i = 0; i < cases.size(); ++i) {
        const float* uv = &p.mesh.texcoords[6 * i];
        EXPECT_EQ(uv[0], cases[i].u1) << i;
        EXPECT_EQ(uv[1], cases[i].v1) << i;
        EXPECT_EQ(uv[2], cases[i].u1 + cases[i].du) << i;  // the whole chart by the same map
        EXPECT_EQ(uv[5], cases[i].v1 + 0.25f) << i;
    }
}

// The terrain's UVs on a 1/32 grid, so that every shift below is exact in float.
Piece dyadicTerrain() {
    Piece p = terrain(32, 100, true);
    for (uint32_t v = 0; v < p.mesh.vertexCount(); ++v)
        p.mesh.texcoords[2 * v] = float(v % 33) / 32, p.mesh.texcoords[2 * v + 1] = float(v / 33) / 32;
    return p;
}

// An OBJ whose two charts were exported two periods to the right and one up builds the bytes of
// the same scan in [0, 1]; with `map_Kd -clamp on` it does not (the charts then read the border).
TEST(WrapUvs, AScanInAnotherPeriodBuildsTheSameDatabase) {
    TempDir dir;
    writeFile(dir.file("atlas.png"), encodeTexture(noisyImage(64), Codec::Png).bytes);
    const auto build = [&](const Piece& p, const std::string& texture, const std::string& db) {
        writeObj(dir.file("t.obj"), p, texture);  // one path, so the databases' metadata agree
        const RunResult r = runHlod({"build", dir.file("t.obj"), "-o", dir.file(db), "-j", "1"});
        EXPECT_EQ(r.exitCode, 0) << r.outAndErr();
        return readFile(dir.file(db));
    };
    const Piece inside = dyadicTerrain();
    Piece shifted = inside;
    for (uint32_t v = 0; v < shifted.mesh.vertexCount(); ++v) shifted.mesh.texcoords[2 * v] += 2, shifted.mesh.texcoords[2 * v + 1] -= 1;
    const std::vector<uint8_t> reference = build(inside, "atlas.png", "inside.hlod");
    EXPECT_EQ(build(shifted, "atlas.png", "shifted.hlod"), reference);
    EXPECT_NE(build(shifted, "-clamp on atlas.png", "clamped.hlod"), reference);
    EXPECT_EQ(readMesh(dir.file("t.obj")).materials.at(0).uvPeriod[0], 0.0f);
}

// Charts tiling their texture twice (UVs 0..2, REPEAT; the terrain's two materials, two charts) cannot be moved into [0, 1]: the build says so
// (it read the border texels without a word until stop 46); the same chart in [0, 1] does not warn.
TEST(WrapUvs, AChartCrossingAPeriodsEdgeIsWarnedOf) {
    TempDir dir;
    writeFile(dir.file("atlas.png"), encodeTexture(noisyImage(64), Codec::Png).bytes);
    Piece tiled = dyadicTerrain();
    writeObj(dir.file("inside.obj"), tiled, "atlas.png");
    for (float& c : tiled.mesh.texcoords) c *= 2;
    writeObj(dir.file("tiled.obj"), tiled, "atlas.png");
    const RunResult inside = runHlod({"build", dir.file("inside.obj"), "-o", dir.file("inside.hlod")});
    ASSERT_EQ(inside.exitCode, 0) << inside.outAndErr();
    EXPECT_EQ(inside.out.find("UV charts cross"), std::string::npos) << inside.out;
    const RunResult r = runHlod({"build", dir.file("tiled.obj"), "-o", dir.file("tiled.hlod")});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_NE(r.out.find("warning: " + dir.file("tiled.obj") + ": 2 UV charts cross an edge of their repeating texture"),
              std::string::npos) << r.out;
}

// A glTF texture's sampler: REPEAT without one, else its wrapS and wrapT.
TEST(WrapUvs, GltfSamplersGiveEachAxisItsPeriod) {
    TempDir dir;
    std::ofstream(dir.file("t.gltf")) << texturedTriangleGltf(
        R"({"name": "a", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
           {"name": "b", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}})",
        R"({"source": 0}, {"source": 0, "sampler": 0})", R"( "samplers": [{"wrapS": 33071, "wrapT": 33648}],)");
    const SourceMesh s = readMesh(dir.file("t.gltf"));
    ASSERT_GE(s.materials.size(), 2u);
    EXPECT_EQ(s.materials[0].uvPeriod[0], 1.0f);
    EXPECT_EQ(s.materials[0].uvPeriod[1], 1.0f);
    EXPECT_EQ(s.materials[1].uvPeriod[0], 0.0f);  // CLAMP_TO_EDGE
    EXPECT_EQ(s.materials[1].uvPeriod[1], 2.0f);  // MIRRORED_REPEAT
}

}  // namespace
}  // namespace hlod::test
