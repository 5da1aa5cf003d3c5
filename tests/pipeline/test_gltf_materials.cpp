// glTF materials as exporters write them: the base-colour texture's own texture coordinate set
// (`texCoord`), KHR_texture_transform (offset, rotation, scale and its texCoord override) applied
// to the UVs, a specular-glossiness material's diffuse texture, and a file whose extensionsRequired names an extension hlod does not read refused
// in one line instead of built wrong.
#include "helpers.h"

#include "formats/codec.h"
#include "pipeline/tiny_gltf_config.h"
#include "tests/support/gltf_model.h"
#include "tests/support/run_hlod.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <numbers>

namespace hlod::test {
namespace {

// terrain(4)'s mesh with its real UVs as TEXCOORD_1 and zeros as TEXCOORD_0, textured by a.png
// (written beside it); the material reads set `set`, with `transform` when not null.
tinygltf::Model twoSetModel(TempDir& dir, const MeshData& m, int set, const tinygltf::Value* transform) {
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.buffers.resize(1);
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.attributes["POSITION"] = addData(model, m.positions, kFloat, TINYGLTF_TYPE_VEC3, 3);
    prim.attributes["TEXCOORD_0"] = addData(model, std::vector<float>(m.texcoords.size(), 0.0f), kFloat, TINYGLTF_TYPE_VEC2, 2);
    prim.attributes["TEXCOORD_1"] = addData(model, m.texcoords, kFloat, TINYGLTF_TYPE_VEC2, 2);
    prim.indices = addData(model, m.indices, kUint, TINYGLTF_TYPE_SCALAR, 1);
    prim.material = 0;
    model.meshes.resize(1);
    model.meshes[0].primitives.push_back(prim);
    singleNodeScene(model);
    tinygltf::Image image;
    image.uri = "a.png";
    model.images.push_back(image);
    model.textures.resize(1);
    model.textures[0].source = 0;
    model.materials.resize(1);
    tinygltf::TextureInfo& info = model.materials[0].pbrMetallicRoughness.baseColorTexture;
    info.index = 0, info.texCoord = set;
    if (transform) info.extensions["KHR_texture_transform"] = *transform;
    return model;
}

void saveModel(const tinygltf::Model& model, const std::string& path, bool binary = false) {
    tinygltf::TinyGLTF writer;
    ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, path, false, true, true, binary)) << path;
}

tinygltf::Value transformValue(double ox, double oy, double rotation, double sx, double sy, int texCoord = -1) {
    tinygltf::Value::Object t;
    t["offset"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(ox), tinygltf::Value(oy)});
    t["rotation"] = tinygltf::Value(rotation);
    t["scale"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(sx), tinygltf::Value(sy)});
    if (texCoord >= 0) t["texCoord"] = tinygltf::Value(texCoord);
    return tinygltf::Value(t);
}

// Every corner of `s` reads `expected(u, v)` for the corner's vertex in `m`.
template <class Expected>
void expectTexcoords(const SourceMesh& s, const MeshData& m, Expected expected) {
    const MeshData& r = s.piece.mesh;
    ASSERT_EQ(r.indices.size(), m.indices.size());
    ASSERT_FALSE(r.texcoords.empty());
    for (size_t c = 0; c < m.indices.size(); ++c) {
        const float u = m.texcoords[2 * m.indices[c]], v = m.texcoords[2 * m.indices[c] + 1];
        const auto [eu, ev] = expected(u, v);
        ASSERT_NEAR(r.texcoords[2 * r.indices[c]], eu, 1e-5f) << "corner " << c;
        ASSERT_NEAR(r.texcoords[2 * r.indices[c] + 1], ev, 1e-5f) << "corner " << c;
    }
}

TEST(GltfMaterials, TheTexturesTexCoordSetIsRead) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    saveModel(twoSetModel(dir, m, 1, nullptr), dir.file("set1.gltf"));
    expectTexcoords(readMesh(dir.file("set1.gltf")), m, [](float u, float v) { return std::pair{u, v}; });
    saveModel(twoSetModel(dir, m, 0, nullptr), dir.file("set0.gltf"));
    expectTexcoords(readMesh(dir.file("set0.gltf")), m, [](float, float) { return std::pair{0.0f, 0.0f}; });
}

TEST(GltfMaterials, KhrTextureTransformIsApplied) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    // The extension's own example: the lower-left quadrant of the image, turned 90° clockwise.
    const tinygltf::Value quadrant = transformValue(0, 1, std::numbers::pi / 2, 0.5, 0.5);
    saveModel(twoSetModel(dir, m, 1, &quadrant), dir.file("q.gltf"));
    expectTexcoords(readMesh(dir.file("q.gltf")), m, [](float u, float v) { return std::pair{0.5f * v, 1.0f - 0.5f * u}; });
    // Its other example, the T axis inverted; and its texCoord overrides the textureInfo's.
    const tinygltf::Value flip = transformValue(0, 1, 0, 1, -1, 1);
    saveModel(twoSetModel(dir, m, 0, &flip), dir.file("f.glb"), true);
    expectTexcoords(readMesh(dir.file("f.glb")), m, [](float u, float v) { return std::pair{u, 1.0f - v}; });
}

TEST(GltfMaterials, TwoTransformsOverOneVertexBufferKeepTheirOwnUvs) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    const tinygltf::Value shift = transformValue(0.25, 0, 0, 1, 1);
    tinygltf::Model model = twoSetModel(dir, m, 1, nullptr);
    model.materials.push_back(model.materials[0]);
    model.materials[1].pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] = shift;
    model.meshes[0].primitives.push_back(model.meshes[0].primitives[0]);
    model.meshes[0].primitives[1].material = 1;
    saveModel(model, dir.file("two.gltf"));
    const SourceMesh s = readMesh(dir.file("two.gltf"));
    ASSERT_EQ(s.piece.mesh.vertexCount(), 2 * m.vertexCount());  // one copy per mapping, not one shared
    const size_t corners = m.indices.size();
    for (size_t c = 0; c < corners; ++c) {
        const uint32_t a = s.piece.mesh.indices[c], b = s.piece.mesh.indices[corners + c];
        EXPECT_NEAR(s.piece.mesh.texcoords[2 * b], s.piece.mesh.texcoords[2 * a] + 0.25f, 1e-5f) << "corner " << c;
    }
}

// The archived specular-glossiness workflow: the diffuse texture is the colour, with its set.
TEST(GltfMaterials, ASpecularGlossinessMaterialsDiffuseTextureIsItsColour) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    tinygltf::Model model = twoSetModel(dir, m, 0, nullptr);
    model.materials[0].pbrMetallicRoughness.baseColorTexture = tinygltf::TextureInfo{};
    tinygltf::Value::Object diffuse{{"index", tinygltf::Value(0)}, {"texCoord", tinygltf::Value(1)}};
    model.materials[0].extensions["KHR_materials_pbrSpecularGlossiness"] =
        tinygltf::Value(tinygltf::Value::Object{{"diffuseTexture", tinygltf::Value(diffuse)}});
    model.extensionsRequired = {"KHR_materials_pbrSpecularGlossiness"};
    saveModel(model, dir.file("sg.gltf"));
    const SourceMesh s = readMesh(dir.file("sg.gltf"));
    EXPECT_EQ(s.materials[0].texturePath, std::filesystem::canonical(dir.file("a.png")).string());
    expectTexcoords(s, m, [](float u, float v) { return std::pair{u, v}; });
}

// glTF URIs are percent-encoded: `my%20atlas.png` is the file `my atlas.png`, inside the same
// confinement (an encoded '..' is still a '..').
TEST(GltfMaterials, PercentEncodedImageUrisNameTheirFiles) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    tinygltf::Model model = twoSetModel(dir, m, 1, nullptr);
    writeFile(dir.file("my atlas.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    model.images[0].uri = "my%20atlas.png";
    saveModel(model, dir.file("space.gltf"));
    EXPECT_EQ(readMesh(dir.file("space.gltf")).materials[0].texturePath, std::filesystem::canonical(dir.file("my atlas.png")).string());
    for (const std::string name : {"100%.png", "a%41.png"}) {  // a '%' an exporter did not encode: the file as written
        writeFile(dir.file(name), encodeTexture(testImage(16, 16), Codec::Png).bytes);
        model.images[0].uri = name;
        saveModel(model, dir.file("percent.gltf"));
        EXPECT_EQ(readMesh(dir.file("percent.gltf")).materials[0].texturePath, std::filesystem::canonical(dir.file(name)).string());
    }
    model.images[0].uri = "..%2Fa.png";
    saveModel(model, dir.file("up.gltf"));
    EXPECT_NE(errorOf([&] { readMesh(dir.file("up.gltf")); }).find("image '../a.png' has a '..' component (refused"), std::string::npos);
}

TEST(GltfBadInput, RequiredExtensionsHlodDoesNotReadAreRefused) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    tinygltf::Model model = twoSetModel(dir, m, 1, nullptr);
    model.extensionsRequired = {"KHR_mesh_quantization", "KHR_texture_transform", "EXT_meshopt_compression"};
    saveModel(model, dir.file("known.gltf"));
    EXPECT_EQ(readMesh(dir.file("known.gltf")).piece.mesh.triangleCount(), m.triangleCount());
    for (const bool binary : {false, true}) {
        model.extensionsRequired = {"KHR_texture_transform", "KHR_texture_basisu"};
        const std::string file = dir.file(binary ? "m.glb" : "m.gltf");
        saveModel(model, file, binary);
        const std::string error = errorOf([&] { readMesh(file); });
        EXPECT_NE(error.find(file + ": requires glTF extension KHR_texture_basisu, which hlod does not read (it reads "),
                  std::string::npos)
            << error;
        const RunResult r = runHlod({"build", file, "-o", dir.file("m.hlod")});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_NE(r.err.find("requires glTF extension KHR_texture_basisu"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir.file("m.hlod")));
    }
}

TEST(GltfBadInput, AMalformedTextureTransformNamesItsMaterial) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    tinygltf::Value::Object bad;
    bad["rotation"] = tinygltf::Value(std::string("quarter"));
    const tinygltf::Value word(bad);
    saveModel(twoSetModel(dir, m, 1, &word), dir.file("r.gltf"));
    EXPECT_NE(errorOf([&] { readMesh(dir.file("r.gltf")); }).find("r.gltf: material 0: KHR_texture_transform rotation is not a number"),
              std::string::npos);
    tinygltf::Value::Object shortScale;
    shortScale["scale"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(2.0)});
    const tinygltf::Value scale(shortScale);
    saveModel(twoSetModel(dir, m, 1, &scale), dir.file("s.gltf"));
    EXPECT_NE(errorOf([&] { readMesh(dir.file("s.gltf")); }).find("s.gltf: material 0: KHR_texture_transform scale is not an array of 2 numbers"),
              std::string::npos);
    const tinygltf::Value hugeSet(tinygltf::Value::Object{{"texCoord", tinygltf::Value(1e10)}});
    saveModel(twoSetModel(dir, m, 1, &hugeSet), dir.file("t.gltf"));
    EXPECT_NE(errorOf([&] { readMesh(dir.file("t.gltf")); }).find("t.gltf: material 0: KHR_texture_transform texCoord is 1e+10, not an integer from 0 to 255"),
              std::string::npos)
        << errorOf([&] { readMesh(dir.file("t.gltf")); });
}

}  // namespace
// A texture or image reference that leads nowhere is an unusable texture like a bad file (until
// stop 44 the material was left untextured without a word, and --strict passed).
TEST(GltfBadInput, TextureReferencesThatLeadNowhereAreUnusableTextures) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    const std::vector<std::pair<std::function<void(tinygltf::Model&)>, std::string>> cases = {
        {[](tinygltf::Model& g) { g.materials[0].pbrMetallicRoughness.baseColorTexture.index = 99; },
         "material 0 uses texture 99, which does not exist (1 textures)"},
        {[](tinygltf::Model& g) { g.textures[0].source = -1, g.textures[0].name = "no source"; },
         "texture 0 has no image hlod can read (source -1 of 1 images)"},
        {[](tinygltf::Model& g) { g.textures[0].source = 7; }, "texture 0 has no image hlod can read (source 7 of 1 images)"},
        {[](tinygltf::Model& g) { g.images[0].uri = "data:image/png;base64"; },
         "image 0 has no data hlod can decode (a data: URI that does not decode)"},
        // every UV read as 0 (one texel's colour over the surface), status 0 even with --strict, until stop 46
        {[](tinygltf::Model& g) { g.meshes[0].primitives[0].attributes.erase("TEXCOORD_0"); },
         "material 0 needs TEXCOORD_0 for its texture, which a primitive using it lacks"}};
    for (const auto& [change, expected] : cases) {
        tinygltf::Model model = twoSetModel(dir, m, 0, nullptr);
        change(model);
        saveModel(model, dir.file("t.gltf"));
        const SourceMesh mesh = readMesh(dir.file("t.gltf"));
        EXPECT_FALSE(mesh.materials[0].image);
        EXPECT_TRUE(mesh.materials[0].texturePath.empty());
        ASSERT_EQ(mesh.stats.textureProblems.size(), 1u) << expected;
        EXPECT_EQ(mesh.stats.textureProblems[0].what, dir.file("t.gltf") + ": " + expected);
        const RunResult strict = runHlod({"build", dir.file("t.gltf"), "-o", dir.file("t.hlod"), "--strict"});
        EXPECT_EQ(strict.exitCode, 2) << strict.outAndErr();
        EXPECT_EQ(strict.err, "hlod build: " + dir.file("t.gltf") + ": " + expected + " (--strict)\n");
    }
    saveModel(twoSetModel(dir, m, 0, nullptr), dir.file("fine.gltf"));
    EXPECT_TRUE(readMesh(dir.file("fine.gltf")).stats.textureProblems.empty());
    nlohmann::json negative = nlohmann::json::parse(readText(dir.file("fine.gltf")));  // tinygltf writes no index < 0
    negative["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = -5;
    std::ofstream(dir.file("n.gltf")) << negative.dump();
    const SourceMesh mesh = readMesh(dir.file("n.gltf"));
    ASSERT_EQ(mesh.stats.textureProblems.size(), 1u);
    EXPECT_EQ(mesh.stats.textureProblems[0].what, dir.file("n.gltf") + ": material 0 uses texture -5, which does not exist (1 textures)");
}

}  // namespace hlod::test
