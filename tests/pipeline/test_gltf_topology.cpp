// glTF primitives as triangle strips and fans (glTF 2.0 §3.7.2.1, "Topology types"): read as the
// triangle lists they stand for, with the list's facing, indexed or not; a strip's joining
// triangles (a repeated vertex) left out; points and lines still skipped with a warning. What the
// reader does not apply is said: morph targets with a weight (a warning), a scene that does not exist
// (refused).
#include "helpers.h"

#include "pipeline/tiny_gltf_config.h"
#include "tests/support/gltf_model.h"

namespace hlod::test {
namespace {

// `positions` (x, y, 0 per vertex) as one primitive of each of `modes`, indexed by `indices`
// unless empty, written as a glTF file; returns what readGltf reads from it.
SourceMesh readPrimitives(TempDir& dir, const std::vector<int>& modes, const std::vector<float>& xy, const std::vector<uint32_t>& indices) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.buffers.resize(1);
    std::vector<float> positions;
    for (size_t i = 0; i + 1 < xy.size(); i += 2) positions.insert(positions.end(), {xy[i], xy[i + 1], 0.0f});
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = addData(model, positions, kFloat, TINYGLTF_TYPE_VEC3, 3);
    if (!indices.empty()) prim.indices = addData(model, indices, kUint, TINYGLTF_TYPE_SCALAR, 1);
    model.meshes.resize(1);
    for (const int mode : modes) model.meshes[0].primitives.push_back(prim), model.meshes[0].primitives.back().mode = mode;
    singleNodeScene(model);
    const std::string path = dir.file("m" + std::to_string(modes[0]) + (indices.empty() ? "" : "i") + ".gltf");
    tinygltf::TinyGLTF writer;
    EXPECT_TRUE(writer.WriteGltfSceneToFile(&model, path, false, true, true, false)) << path;
    return readGltf(path);
}

// Twice the signed area of every triangle, in the x-y plane (positive: counter-clockwise).
std::vector<double> signedAreas(const MeshData& m) {
    std::vector<double> areas;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const float *a = &m.positions[3 * m.indices[3 * t]], *b = &m.positions[3 * m.indices[3 * t + 1]],
                    *c = &m.positions[3 * m.indices[3 * t + 2]];
        areas.push_back(double(b[0] - a[0]) * (c[1] - a[1]) - double(b[1] - a[1]) * (c[0] - a[0]));
    }
    return areas;
}

// A strip zig-zagging along a 2 x 5 grid, (0,0) (0,1) (1,0) (1,1) ...: 8 triangles of area 1/2,
// all facing the same way (the list's rule: triangle i odd swaps its first two vertices).
TEST(GltfTopology, StripReadsAsItsTrianglesWithOneFacing) {
    TempDir dir;
    std::vector<float> xy;
    for (int i = 0; i < 5; ++i) xy.insert(xy.end(), {float(i), 0.0f, float(i), 1.0f});
    for (const bool indexed : {false, true}) {
        std::vector<uint32_t> indices;
        if (indexed)
            for (uint32_t i = 0; i < 10; ++i) indices.push_back(i);
        const SourceMesh m = readPrimitives(dir, {TINYGLTF_MODE_TRIANGLE_STRIP}, xy, indices);
        const std::vector<double> areas = signedAreas(m.piece.mesh);
        ASSERT_EQ(areas.size(), 8u) << (indexed ? "indexed" : "not indexed");
        for (double a : areas) EXPECT_DOUBLE_EQ(a, -1.0);  // (0,0) (0,1) (1,0): clockwise in x-y
        EXPECT_TRUE(m.stats.warnings.empty());
    }
}

// Two strips joined by repeating the last vertex of one and the first of the next: the four
// joining triangles (each repeating a vertex) are not read; the others face one way.
TEST(GltfTopology, AStripsJoiningTrianglesAreLeftOut) {
    TempDir dir;
    std::vector<float> xy;
    for (int i = 0; i < 3; ++i) xy.insert(xy.end(), {float(i), 0.0f, float(i), 1.0f});
    for (int i = 0; i < 3; ++i) xy.insert(xy.end(), {float(i), 5.0f, float(i), 6.0f});
    const std::vector<uint32_t> indices = {0, 1, 2, 3, 4, 5, 5, 6, 6, 7, 8, 9, 10, 11};
    const SourceMesh m = readPrimitives(dir, {TINYGLTF_MODE_TRIANGLE_STRIP}, xy, indices);
    const std::vector<double> areas = signedAreas(m.piece.mesh);
    ASSERT_EQ(areas.size(), 8u);
    for (double a : areas) EXPECT_DOUBLE_EQ(a, -1.0);
}

// A fan around (0, 0) over four rim vertices of a square: 3 triangles, counter-clockwise as given.
TEST(GltfTopology, FanReadsAsItsTriangles) {
    TempDir dir;
    const std::vector<float> xy = {0, 0, 1, -1, 1, 1, -1, 1, -1, -1};
    const SourceMesh m = readPrimitives(dir, {TINYGLTF_MODE_TRIANGLE_FAN}, xy, {});
    const std::vector<double> areas = signedAreas(m.piece.mesh);
    ASSERT_EQ(areas.size(), 3u);
    for (double a : areas) EXPECT_DOUBLE_EQ(a, 2.0);
}

TEST(GltfTopology, PointsAndLinesAreSkippedWithAWarning) {
    TempDir dir;
    const SourceMesh m = readPrimitives(dir, {TINYGLTF_MODE_TRIANGLES, TINYGLTF_MODE_POINTS, TINYGLTF_MODE_LINE, TINYGLTF_MODE_LINE_LOOP},
                                        {0, 0, 1, 0, 1, 1}, {0, 1, 2});
    EXPECT_EQ(m.piece.mesh.triangleCount(), 1u);
    ASSERT_EQ(m.stats.warnings.size(), 1u);
    EXPECT_NE(m.stats.warnings[0].find("3 primitives that are not triangles skipped"), std::string::npos) << m.stats.warnings[0];
}

// Until stop 46 a weighted morph target was dropped without a word and `"scene": 5` of one scene read
// every root node.
TEST(GltfTopology, WeightedMorphTargetsAreWarnedOfAndAMissingSceneIsRefused) {
    TempDir dir;
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (const double weight : {0.0, 1.0}) {
        tinygltf::Model model;
        model.asset.version = "2.0";
        model.buffers.resize(1);
        tinygltf::Primitive prim;
        prim.attributes["POSITION"] = addData(model, positions, kFloat, TINYGLTF_TYPE_VEC3, 3);
        prim.targets.push_back({{"POSITION", addData(model, std::vector<float>{0, 0, 10, 0, 0, 10, 0, 0, 10}, kFloat, TINYGLTF_TYPE_VEC3, 3)}});
        model.meshes.resize(1);
        model.meshes[0].primitives.push_back(prim);
        model.meshes[0].weights = {weight};
        singleNodeScene(model);
        const std::string path = dir.file("morph.gltf");
        tinygltf::TinyGLTF writer;
        ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, path, false, true, true, false));
        const SourceMesh m = readGltf(path);
        EXPECT_EQ(m.piece.mesh.triangleCount(), 1u);
        if (weight == 0) {
            EXPECT_TRUE(m.stats.warnings.empty());
            model.defaultScene = 5;
            ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, dir.file("scene.gltf"), false, true, true, false));
            EXPECT_EQ(errorOf([&] { readGltf(dir.file("scene.gltf")); }),
                      dir.file("scene.gltf") + ": corrupt glTF (scene 5 does not exist; 1 scenes)");
            continue;
        }
        ASSERT_EQ(m.stats.warnings.size(), 1u);
        EXPECT_EQ(m.stats.warnings[0], path + ": 1 primitives have weighted morph targets, which hlod does not apply: built at "
                                              "their base positions");
    }
}

// Vertices are numbered in 32 bits: a valid 2 MB glTF placing a 65,536-vertex mesh 65,537 times
// holds 2^32 + 65,536 of them, whose numbers wrapped onto earlier vertices without a word until
// stop 47. Refused before any is read.
TEST(GltfTopology, MoreVerticesOverItsInstancesThan32BitsNumberIsRefused) {
    TempDir dir;
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.buffers.resize(1);
    std::vector<float> positions(3 * 65536);
    for (size_t i = 0; i < positions.size(); ++i) positions[i] = float(i % 251);
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = addData(model, positions, kFloat, TINYGLTF_TYPE_VEC3, 3);
    model.meshes.resize(1);
    model.meshes[0].primitives.push_back(prim);
    model.scenes.resize(1);
    model.defaultScene = 0;
    for (int n = 0; n < 65537; ++n) {
        model.nodes.emplace_back();
        model.nodes.back().mesh = 0;
        model.scenes[0].nodes.push_back(n);
    }
    const std::string path = dir.file("instances.gltf");
    tinygltf::TinyGLTF writer;
    ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, path, false, true, false, false));
    EXPECT_EQ(errorOf([&] { readGltf(path); }), path + ": 4295032832 vertices over its node instances, more than the 4294967295 hlod numbers");
}

}  // namespace
}  // namespace hlod::test
