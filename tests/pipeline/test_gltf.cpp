// The glTF reader on files written by tinygltf's own writer: NORMAL and COLOR_0, GLB (any case
// of the extension), embedded (data URI) and external images, node transforms (normals and the
// winding of mirrored nodes too), KHR_draco_mesh_compression, and one InputError per class of
// bad input (index accessors, truncated buffers, out-of-range indices, NaN/Inf values).
#include "helpers.h"

#include "formats/codec.h"
#include "pipeline/read_gltf_load.h"
#include "pipeline/tiny_gltf_config.h"
#include "tests/support/gltf_model.h"
#include "tests/support/run_hlod.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

namespace hlod::test {
namespace {

constexpr int kUbyte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;

// terrain(4) with unit normals and RGBA colours that differ per vertex.
MeshData sample() {
    MeshData m = terrain(4).mesh;
    for (size_t v = 0; v < m.vertexCount(); ++v) {
        const float n[3] = {std::sin(float(v)), std::cos(float(v)), 2.0f}, len = std::sqrt(n[0] * n[0] + n[1] * n[1] + 4.0f);
        m.normals.insert(m.normals.end(), {n[0] / len, n[1] / len, n[2] / len});
        m.colors.insert(m.colors.end(), {uint8_t(v * 9), uint8_t(255 - v), uint8_t(v * 3 + 1), uint8_t(200 + v)});
    }
    return m;
}

// One mesh (POSITION, TEXCOORD_0, NORMAL, COLOR_0 as normalised RGBA bytes, uint32 indices) in
// the scene's only node; buffer 0 is embedded as a data URI unless `external`.
// One node instancing one mesh made of `prim`, in the default scene.
void singleMeshScene(tinygltf::Model& model, const tinygltf::Primitive& prim) {
    model.meshes.resize(1);
    model.meshes[0].primitives.push_back(prim);
    singleNodeScene(model);
}

tinygltf::Model modelOf(const MeshData& m) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.buffers.resize(1);
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.attributes["POSITION"] = addData(model, m.positions, kFloat, TINYGLTF_TYPE_VEC3, 3);
    prim.attributes["TEXCOORD_0"] = addData(model, m.texcoords, kFloat, TINYGLTF_TYPE_VEC2, 2);
    if (!m.normals.empty()) prim.attributes["NORMAL"] = addData(model, m.normals, kFloat, TINYGLTF_TYPE_VEC3, 3);
    if (!m.colors.empty()) prim.attributes["COLOR_0"] = addData(model, m.colors, kUbyte, TINYGLTF_TYPE_VEC4, 4, true);
    prim.indices = addData(model, m.indices, kUint, TINYGLTF_TYPE_SCALAR, 1);
    singleMeshScene(model, prim);
    return model;
}

tinygltf::Primitive& primitive(tinygltf::Model& model) { return model.meshes[0].primitives[0]; }

void save(const tinygltf::Model& model, const std::string& path, bool binary = false, bool externalBuffer = false) {
    tinygltf::TinyGLTF writer;
    ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, path, false, !externalBuffer, true, binary)) << path;
}

void addTexturedMaterial(tinygltf::Model& model, const tinygltf::Image& image) {
    model.images.push_back(image);
    model.textures.resize(1);
    model.textures[0].source = 0;
    model.materials.resize(1);
    model.materials[0].name = "atlas";
    model.materials[0].pbrMetallicRoughness.baseColorTexture.index = 0;
    primitive(model).material = 0;
}

TEST(Gltf, ReadsNormalsAndColours) {
    TempDir dir;
    const MeshData m = sample();
    save(modelOf(m), dir.file("n.gltf"));
    const SourceMesh s = readMesh(dir.file("n.gltf"));
    EXPECT_EQ(s.piece.mesh.indices, m.indices);
    EXPECT_EQ(s.piece.mesh.positions, m.positions);
    ASSERT_EQ(s.piece.mesh.normals.size(), m.normals.size());
    for (size_t i = 0; i < m.normals.size(); ++i) EXPECT_NEAR(s.piece.mesh.normals[i], m.normals[i], 1e-6f);
    EXPECT_EQ(s.piece.mesh.colors, m.colors);

    tinygltf::Model rgb = modelOf(m);  // COLOR_0 as float RGB: alpha 255
    std::vector<float> colors;
    for (size_t v = 0; v < m.vertexCount(); ++v) colors.insert(colors.end(), {v / 24.0f, 0.5f, 1.0f});
    primitive(rgb).attributes["COLOR_0"] = addData(rgb, colors, kFloat, TINYGLTF_TYPE_VEC3, 3);
    save(rgb, dir.file("rgb.gltf"));
    const std::vector<uint8_t> read = readMesh(dir.file("rgb.gltf")).piece.mesh.colors;
    ASSERT_EQ(read.size(), 4 * m.vertexCount());
    for (size_t v = 0; v < m.vertexCount(); ++v)
        EXPECT_EQ(std::vector<uint8_t>(read.begin() + 4 * v, read.begin() + 4 * v + 4),
                  (std::vector<uint8_t>{uint8_t(std::lround(v * 255 / 24.0)), 128, 255, 255}));
}

TEST(Gltf, GlbWithAnUpperCaseExtension) {
    TempDir dir;
    const MeshData m = sample();
    save(modelOf(m), dir.file("m.GLB"), true);
    EXPECT_EQ(readFile(dir.file("m.GLB"))[0], 'g');  // binary: the "glTF" magic
    const SourceMesh s = readMesh(dir.file("m.GLB"));
    EXPECT_EQ(s.piece.mesh.positions, m.positions);
    EXPECT_EQ(s.piece.mesh.indices, m.indices);
    EXPECT_EQ(s.piece.mesh.colors, m.colors);
}

TEST(Gltf, EmbeddedAndExternalImages) {
    TempDir dir;
    const Image atlas = testImage(16, 8);
    const std::vector<uint8_t> png = encodeTexture(atlas, Codec::Png).bytes;
    tinygltf::Model embedded = modelOf(terrain(4).mesh);
    tinygltf::Image image;
    image.uri = "data:image/png;base64," + base64(png);
    addTexturedMaterial(embedded, image);
    save(embedded, dir.file("e.gltf"));
    const SourceMesh e = readMesh(dir.file("e.gltf"));
    ASSERT_TRUE(e.materials[0].image);
    EXPECT_EQ(e.materials[0].image->width, 16u);
    EXPECT_EQ(e.materials[0].image->pixels, atlas.pixels);  // PNG is lossless
    EXPECT_EQ(e.piece.mesh.texcoords.size(), 2 * e.piece.mesh.vertexCount());

    writeFile(dir.file("atlas.png"), png);
    tinygltf::Model external = modelOf(terrain(4).mesh);
    image.uri = "atlas.png";
    addTexturedMaterial(external, image);
    save(external, dir.file("x.gltf"));
    const SourceMesh x = readMesh(dir.file("x.gltf"));
    EXPECT_FALSE(x.materials[0].image);
    EXPECT_EQ(x.materials[0].texturePath, std::filesystem::canonical(dir.file("atlas.png")).string());
}

// Primitives over one vertex buffer (one primitive per material, common accessors) share its
// vertices instead of adding a copy each; a second node instancing the mesh adds its own.
TEST(Gltf, PrimitivesSharingAVertexBufferShareItsVertices) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    tinygltf::Model model = modelOf(m);
    const size_t half = m.indices.size() / 6 * 3;
    tinygltf::Primitive second = primitive(model);
    const std::vector<uint32_t> first(m.indices.begin(), m.indices.begin() + half), rest(m.indices.begin() + half, m.indices.end());
    primitive(model).indices = addData(model, first, kUint, TINYGLTF_TYPE_SCALAR, 1);
    second.indices = addData(model, rest, kUint, TINYGLTF_TYPE_SCALAR, 1);
    model.meshes[0].primitives.push_back(second);
    save(model, dir.file("shared.gltf"));
    const SourceMesh s = readMesh(dir.file("shared.gltf"));
    EXPECT_EQ(s.piece.mesh.positions, m.positions);
    EXPECT_EQ(s.piece.mesh.indices, m.indices);
    model.nodes.push_back(model.nodes[0]);  // the mesh again, by a second node
    model.nodes[1].translation = {0, 0, 5};
    model.scenes[0].nodes = {0, 1};
    save(model, dir.file("twice.gltf"));
    const SourceMesh twice = readMesh(dir.file("twice.gltf"));
    EXPECT_EQ(twice.piece.mesh.vertexCount(), 2 * m.vertexCount());
    EXPECT_EQ(twice.piece.mesh.triangleCount(), 2 * m.triangleCount());
}

// `hlod build` streams a glTF as it does a PLY (parseGltf into a spilled RawMesh, given an image
// folder): the same mesh readMesh welds, and an embedded image (a data: URI, or a buffer view of a GLB's BIN chunk,
// which glbWithoutImages takes out before tinygltf copies the chunk) written, still encoded, into
// the image folder instead of decoded into memory; the build textures its nodes from that file.
TEST(Gltf, StreamedParseWritesEmbeddedImagesEncoded) {
    TempDir dir;
    const std::vector<uint8_t> jpeg = encodeTexture(testImage(64, 32), Codec::Jpeg, 90).bytes;
    for (const bool inBin : {false, true}) {
        tinygltf::Model model = modelOf(sample());
        tinygltf::Image image;
        if (inBin) image.bufferView = addView(model, jpeg.data(), jpeg.size()), image.mimeType = "image/jpeg";
        else image.uri = "data:image/jpeg;base64," + base64(jpeg);
        addTexturedMaterial(model, image);
        save(model, dir.file("m.glb"), true);
        RawMesh raw;
        raw.spillTo(dir.file(""));
        ReadOptions options;
        options.imageDir = dir.file("images");
        parseGltf(dir.file("m.glb"), raw, options);
        ASSERT_EQ(raw.materials.size(), 2u);
        EXPECT_FALSE(raw.materials[0].image);
        EXPECT_EQ(raw.materials[0].texturePath, dir.file("images/image_0.jpg"));
        EXPECT_EQ(readFile(dir.file("images/image_0.jpg")), jpeg);
        const SourceMesh streamed = toSourceMesh(raw, "m.glb"), read = readMesh(dir.file("m.glb"));
        ASSERT_TRUE(read.materials[0].image);  // readMesh decodes it
        EXPECT_EQ(read.materials[0].image->width, 64u);
        EXPECT_EQ(streamed.piece.mesh.positions, read.piece.mesh.positions);
        EXPECT_EQ(streamed.piece.mesh.indices, read.piece.mesh.indices);
        EXPECT_EQ(streamed.piece.mesh.texcoords, read.piece.mesh.texcoords);
        EXPECT_EQ(streamed.piece.mesh.normals, read.piece.mesh.normals);
        EXPECT_EQ(streamed.piece.mesh.colors, read.piece.mesh.colors);
        EXPECT_EQ(streamed.piece.materials, read.piece.materials);

        const RunResult build = runHlod({"build", dir.file("m.glb"), "-o", dir.file("m.hlod")});
        ASSERT_EQ(build.exitCode, 0) << build.outAndErr();
        EXPECT_EQ(build.out.find("untextured"), std::string::npos) << build.out;
        const RunResult stats = runHlod({"stats", dir.file("m.hlod")});
        EXPECT_EQ(stats.out.find("finest texels                      0 "), std::string::npos) << stats.out;
        EXPECT_NE(stats.out.find("finest texels"), std::string::npos) << stats.out;
    }
}

// A GLB's BIN-chunk image that is a decompression bomb or not an image is taken out and reported
// like a data: URI one; the geometry around it still reads.
TEST(GltfBadInput, UnusableImagesInAGlbBinChunkAreTextureProblems) {
    TempDir dir;
    std::vector<uint8_t> bomb = encodeTexture(testImage(16, 8), Codec::Png).bytes;
    const uint32_t claimed[2] = {20000, 16385};  // IHDR width and height, big-endian
    for (int k = 0; k < 2; ++k)
        for (int b = 0; b < 4; ++b) bomb[16 + 4 * k + b] = uint8_t(claimed[k] >> (24 - 8 * b));
    std::vector<uint8_t> truncatedJpeg = encodeTexture(testImage(64, 64), Codec::Jpeg, 90).bytes;
    truncatedJpeg.resize(truncatedJpeg.size() / 3);
    for (const auto& [bytes, expected] : {std::pair{bomb, std::string("20000x16385")}, std::pair{truncatedJpeg, std::string("cannot be decoded")}}) {
        tinygltf::Model model = modelOf(terrain(4).mesh);
        tinygltf::Image image;
        image.bufferView = addView(model, bytes.data(), bytes.size());
        image.mimeType = "image/png";
        addTexturedMaterial(model, image);
        save(model, dir.file("bad.glb"), true);
        RawMesh raw;
        ReadOptions options;
        options.imageDir = dir.file("images");
        parseGltf(dir.file("bad.glb"), raw, options);
        EXPECT_TRUE(raw.materials[0].texturePath.empty());
        EXPECT_EQ(raw.triangles.size(), terrain(4).mesh.triangleCount());
        ASSERT_EQ(raw.stats.textureProblems.size(), 1u);
        EXPECT_NE(raw.stats.textureProblems[0].what.find(expected), std::string::npos) << raw.stats.textureProblems[0].what;
    }
}

// An image's buffer view running past its buffer's declared byteLength (tinygltf would hand the
// image loader bytes past the end of its copy: fuzz_glb's finding) is an InputError naming the
// image, on both paths.
TEST(GltfBadInput, ImageBufferViewPastItsBuffer) {
    TempDir dir;
    const std::vector<uint8_t> png = encodeTexture(testImage(8, 8), Codec::Png).bytes;
    tinygltf::Model model = modelOf(terrain(4).mesh);
    tinygltf::Image image;
    image.bufferView = addView(model, png.data(), png.size());
    image.mimeType = "image/png";
    model.bufferViews.back().byteLength += 64;  // past the buffer, which ends with the PNG
    addTexturedMaterial(model, image);
    save(model, dir.file("past.glb"), true);
    EXPECT_NE(errorOf([&] { readMesh(dir.file("past.glb")); }).find("past.glb: image 0: buffer view"), std::string::npos);
    ReadOptions options;
    options.imageDir = dir.file("images");
    RawMesh raw;
    EXPECT_NE(errorOf([&] { parseGltf(dir.file("past.glb"), raw, options); }).find("runs past its buffer"), std::string::npos);
}

// A BIN chunk claiming up to 8 bytes more than follow its header: tinygltf checks its length
// without the header and copied past the end (a heap over-read under fuzz_glb, stop 40).
TEST(GltfBadInput, BinChunkLongerThanItsBytes) {
    TempDir dir;
    std::vector<uint8_t> glb = assembleGlb(R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":8}]})", std::vector<uint8_t>{1, 2, 3, 4});
    const size_t chunk = glb.size() - 12;  // the BIN chunk's header: 4 bytes of data follow it
    glb[chunk] = 8;                         // claimed: 8
    writeFile(dir.file("over.glb"), glb);
    const std::string expected = dir.file("over.glb") + ": corrupt GLB (its BIN chunk claims 8 bytes, 4 follow its header)";
    EXPECT_EQ(errorOf([&] { readMesh(dir.file("over.glb")); }), expected);
    EXPECT_EQ(errorOf([&] { readGltfBytes(glb, true, dir.file("over.glb")); }), expected);
    RawMesh raw;
    EXPECT_EQ(errorOf([&] { parseGltf(dir.file("over.glb"), raw); }), expected);
}

// tinygltf hands a Draco primitive's buffer view to Draco unchecked too: checked the same way.
TEST(GltfBadInput, DracoBufferViewPastItsBuffer) {
    TempDir dir;
    std::ofstream(dir.file("d.gltf"))
        << R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],"extensionsUsed":["KHR_draco_mesh_compression"],)"
           R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"extensions":{"KHR_draco_mesh_compression":)"
           R"({"bufferView":0,"attributes":{"POSITION":0}}}}]}],"accessors":[{"componentType":5126,"count":3,"type":"VEC3"}],)"
           R"("bufferViews":[{"buffer":0,"byteOffset":4,"byteLength":100}],)"
           R"("buffers":[{"byteLength":12,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}]})";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("d.gltf")); }).find("d.gltf: a Draco primitive: buffer view 0 runs past its buffer's byteLength"),
              std::string::npos)
        << errorOf([&] { readMesh(dir.file("d.gltf")); });
}

// Embedded images that cannot be used are TextureProblems that leave their material untextured,
// as a missing texture file does: a PNG whose header claims 20000 x 16385 texels (more than
// kMaxTextureTexels: a decompression bomb of a few hundred bytes) is never decoded, and bytes
// that are no image are reported as undecodable.
TEST(GltfBadInput, EmbeddedImagesThatCannotBeUsedLeaveTheMaterialUntextured) {
    TempDir dir;
    std::vector<uint8_t> bomb = encodeTexture(testImage(16, 8), Codec::Png).bytes;
    ASSERT_GT(bomb.size(), 24u);
    const uint32_t claimed[2] = {20000, 16385};  // IHDR width and height, big-endian, at bytes 16 and 20
    for (int k = 0; k < 2; ++k)
        for (int b = 0; b < 4; ++b) bomb[16 + 4 * k + b] = uint8_t(claimed[k] >> (24 - 8 * b));
    const std::vector<uint8_t> garbage(64, 0x5a);
    for (const auto& [bytes, expected] : {std::pair{bomb, std::string("20000x16385")}, std::pair{garbage, std::string("cannot be decoded")}}) {
        tinygltf::Model model = modelOf(terrain(4).mesh);
        tinygltf::Image image;
        image.uri = "data:image/png;base64," + base64(bytes);
        addTexturedMaterial(model, image);
        save(model, dir.file("bad.gltf"));
        const SourceMesh mesh = readMesh(dir.file("bad.gltf"));
        EXPECT_FALSE(mesh.materials[0].image);
        EXPECT_TRUE(mesh.materials[0].texturePath.empty());
        ASSERT_EQ(mesh.stats.textureProblems.size(), 1u);  // README "Textures: one rule": counted, fatal with --strict
        EXPECT_NE(mesh.stats.textureProblems[0].what.find(expected), std::string::npos) << mesh.stats.textureProblems[0].what;
    }
}

double triangleNormalZ(const MeshData& m, size_t t) {
    const float* a = &m.positions[3 * m.indices[3 * t]];
    const float* b = &m.positions[3 * m.indices[3 * t + 1]];
    const float* c = &m.positions[3 * m.indices[3 * t + 2]];
    return double(b[0] - a[0]) * (c[1] - a[1]) - double(b[1] - a[1]) * (c[0] - a[0]);
}

// Node 0 translated by (10, 0, 0), its child rotated 90 degrees about z and scaled by 2:
// p -> (10 - 2 y, 2 x, 2 z), n -> (-n.y, n.x, n.z). A node mirrored in x keeps the facing.
TEST(Gltf, NodeTransformsMovePositionsAndNormals) {
    TempDir dir;
    const MeshData m = sample();
    tinygltf::Model model = modelOf(m);
    model.nodes.resize(2);
    model.nodes[1] = model.nodes[0];
    model.nodes[0] = tinygltf::Node();
    model.nodes[0].translation = {10, 0, 0};
    model.nodes[0].children = {1};
    model.nodes[1].rotation = {0, 0, std::sqrt(0.5), std::sqrt(0.5)};
    model.nodes[1].scale = {2, 2, 2};
    save(model, dir.file("t.gltf"));
    const MeshData t = readMesh(dir.file("t.gltf")).piece.mesh;
    ASSERT_EQ(t.indices, m.indices);
    ASSERT_EQ(t.normals.size(), m.normals.size());
    for (size_t v = 0; v < m.vertexCount(); ++v) {
        EXPECT_NEAR(t.positions[3 * v], 10 - 2 * m.positions[3 * v + 1], 1e-4f);
        EXPECT_NEAR(t.positions[3 * v + 1], 2 * m.positions[3 * v], 1e-4f);
        EXPECT_NEAR(t.positions[3 * v + 2], 2 * m.positions[3 * v + 2], 1e-4f);
        EXPECT_NEAR(t.normals[3 * v], -m.normals[3 * v + 1], 1e-5f);
        EXPECT_NEAR(t.normals[3 * v + 1], m.normals[3 * v], 1e-5f);
        EXPECT_NEAR(t.normals[3 * v + 2], m.normals[3 * v + 2], 1e-5f);
    }

    tinygltf::Model mirrored = modelOf(m);
    mirrored.nodes[0].scale = {-1, 1, 1};
    save(mirrored, dir.file("mirror.gltf"));
    const MeshData r = readMesh(dir.file("mirror.gltf")).piece.mesh;
    ASSERT_EQ(r.triangleCount(), m.triangleCount());
    ASSERT_EQ(r.normals.size(), m.normals.size());
    for (size_t tri = 0; tri < m.triangleCount(); ++tri) {
        ASSERT_GT(triangleNormalZ(m, tri), 0) << tri;  // the terrain faces +z
        EXPECT_GT(triangleNormalZ(r, tri), 0) << tri;
    }
    for (size_t v = 0; v < m.vertexCount(); ++v) EXPECT_NEAR(r.normals[3 * v], -m.normals[3 * v], 1e-6f);
}

// The primitive's POSITION and indices only in a Draco bitstream (accessors without buffer views).
TEST(Gltf, DracoCompressedPrimitive) {
    TempDir dir;
    const MeshData m = terrain(6).mesh;
    draco::Mesh mesh;
    mesh.set_num_points(static_cast<uint32_t>(m.vertexCount()));
    draco::GeometryAttribute position;
    position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
    const int id = mesh.AddAttribute(position, true, static_cast<uint32_t>(m.vertexCount()));
    for (uint32_t v = 0; v < m.vertexCount(); ++v)
        mesh.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(v), &m.positions[3 * v]);
    for (size_t t = 0; t < m.triangleCount(); ++t)
        mesh.AddFace({draco::PointIndex(m.indices[3 * t]), draco::PointIndex(m.indices[3 * t + 1]), draco::PointIndex(m.indices[3 * t + 2])});
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
    draco::EncoderBuffer encoded;
    ASSERT_TRUE(encoder.EncodeMeshToBuffer(mesh, &encoded).ok());

    tinygltf::Model model;
    model.asset.version = "2.0";
    model.buffers.resize(1);
    const int view = addView(model, encoded.data(), encoded.size());
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.attributes["POSITION"] = addAccessor(model, -1, kFloat, TINYGLTF_TYPE_VEC3, m.vertexCount());
    prim.indices = addAccessor(model, -1, kUint, TINYGLTF_TYPE_SCALAR, m.indices.size());
    prim.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(tinygltf::Value::Object{
        {"bufferView", tinygltf::Value(view)},
        {"attributes", tinygltf::Value(tinygltf::Value::Object{{"POSITION", tinygltf::Value(id)}})}});
    singleMeshScene(model, prim);
    model.extensionsUsed = model.extensionsRequired = {"KHR_draco_mesh_compression"};
    save(model, dir.file("d.glb"), true);

    const MeshData d = readMesh(dir.file("d.glb")).piece.mesh;
    ASSERT_EQ(d.triangleCount(), m.triangleCount());
    EXPECT_NEAR(meshArea(d), meshArea(m), 1e-3 * meshArea(m));
    const Box3f a = pieceBounds(m), b = pieceBounds(d);
    for (const auto& [p, q] : {std::pair{a.min, b.min}, std::pair{a.max, b.max}}) {
        EXPECT_NEAR(p.x, q.x, 0.01f);
        EXPECT_NEAR(p.y, q.y, 0.01f);
        EXPECT_NEAR(p.z, q.z, 0.01f);
    }
}

TEST(GltfBadInput, IndexAccessors) {
    TempDir dir;
    const auto expectError = [&](tinygltf::Model model, const std::string& expected) {
        save(model, dir.file("i.gltf"));
        const std::string error = errorOf([&] { readMesh(dir.file("i.gltf")); });
        EXPECT_EQ(error.rfind(dir.file("i.gltf") + ": ", 0), 0u) << error;
        EXPECT_NE(error.find(expected), std::string::npos) << error;
    };
    tinygltf::Model missing = modelOf(terrain(2).mesh);  // tinygltf checks links to accessors and views
    primitive(missing).indices = 42;
    expectError(missing, "indices accessor out of bounds");
    tinygltf::Model badView = modelOf(terrain(2).mesh);
    badView.accessors[static_cast<size_t>(primitive(badView).indices)].bufferView = 77;
    expectError(badView, "invalid bufferView");
    tinygltf::Model badBuffer = modelOf(terrain(2).mesh);  // but not a view's link to its buffer
    badBuffer.bufferViews[static_cast<size_t>(badBuffer.accessors[static_cast<size_t>(primitive(badBuffer).indices)].bufferView)]
        .buffer = 5;
    expectError(badBuffer, "index accessor 2: its buffer view has no valid buffer");
    tinygltf::Model floats = modelOf(terrain(2).mesh);
    floats.accessors[static_cast<size_t>(primitive(floats).indices)].componentType = kFloat;
    expectError(floats, "is not unsigned integer scalars");
}

TEST(GltfBadInput, TruncatedBuffers) {
    TempDir dir;
    const MeshData m = terrain(4).mesh;
    save(modelOf(m), dir.file("t.glb"), true);
    std::vector<uint8_t> glb = readFile(dir.file("t.glb"));
    glb.resize(glb.size() - 200);
    writeFile(dir.file("t.glb"), glb);
    EXPECT_NE(errorOf([&] { readMesh(dir.file("t.glb")); }).find("corrupt glTF"), std::string::npos);

    save(modelOf(m), dir.file("x.gltf"), false, true);  // x.bin beside it
    std::vector<uint8_t> bin = readFile(dir.file("x.bin"));
    ASSERT_FALSE(bin.empty());
    bin.resize(bin.size() / 2);
    writeFile(dir.file("x.bin"), bin);
    EXPECT_NE(errorOf([&] { readMesh(dir.file("x.gltf")); }), "");

    tinygltf::Model longAccessor = modelOf(m);  // more positions than its buffer view holds
    longAccessor.accessors[static_cast<size_t>(primitive(longAccessor).attributes["POSITION"])].count += 1000;
    save(longAccessor, dir.file("a.gltf"));
    EXPECT_NE(errorOf([&] { readMesh(dir.file("a.gltf")); }).find("POSITION accessor 0 runs past its buffer view"),
              std::string::npos);
    tinygltf::Model longView = modelOf(m);  // a buffer view longer than its buffer
    longView.bufferViews[0].byteLength += longView.buffers[0].data.size();
    save(longView, dir.file("v.gltf"));
    EXPECT_NE(errorOf([&] { readMesh(dir.file("v.gltf")); }), "");
}

TEST(GltfBadInput, OutOfRangeIndex) {
    TempDir dir;
    MeshData m = terrain(2).mesh;
    m.indices[4] = 99;
    save(modelOf(m), dir.file("o.gltf"));
    EXPECT_NE(errorOf([&] { readMesh(dir.file("o.gltf")); }).find("index 99 out of range (9 vertices)"), std::string::npos);
}

TEST(GltfBadInput, NaNAndInfValues) {
    TempDir dir;
    for (float bad : {std::nanf(""), INFINITY}) {
        MeshData m = sample();
        m.positions[7] = bad;
        save(modelOf(m), dir.file("p.gltf"));
        EXPECT_NE(errorOf([&] { readMesh(dir.file("p.gltf")); }).find("vertex 2 has a NaN/Inf coordinate"), std::string::npos);
        m = sample();
        m.normals[4] = bad;
        save(modelOf(m), dir.file("n.gltf"));
        EXPECT_NE(errorOf([&] { readMesh(dir.file("n.gltf")); }).find("vertex 1 has a NaN/Inf normal"), std::string::npos);
        tinygltf::Model colours = modelOf(sample());
        std::vector<float> rgb(3 * sample().vertexCount(), 0.5f);
        rgb[5] = bad;
        primitive(colours).attributes["COLOR_0"] = addData(colours, rgb, kFloat, TINYGLTF_TYPE_VEC3, 3);
        save(colours, dir.file("c.gltf"));
        EXPECT_NE(errorOf([&] { readMesh(dir.file("c.gltf")); }).find("COLOR_0 of vertex 1 is NaN/Inf"), std::string::npos);
    }
}

}  // namespace
}  // namespace hlod::test
