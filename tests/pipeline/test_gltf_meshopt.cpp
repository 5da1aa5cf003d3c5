// EXT_meshopt_compression as gltfpack writes it (compressed data in buffer 0, views pointing at
// a fallback buffer without data): files coded here with meshoptimizer's own encoders read as the
// same mesh uncompressed, in a .gltf and in a GLB, through readMesh and `hlod build`; views that
// do not decode or claim more than their data are one line naming the view.
#include "helpers.h"

#include "formats/codec.h"
#include "pipeline/read_gltf_load.h"
#include "tests/support/run_hlod.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

namespace hlod::test {
namespace {

using nlohmann::json;

struct Coded {
    json document;
    std::vector<uint8_t> data;  // buffer 0: every view's compressed bytes
};

// One compressed view of `count` elements of `stride` bytes: its bytes appended to `coded.data`,
// the view (over the fallback buffer 1) appended to the document.
void addCodedView(Coded& c, const std::vector<uint8_t>& bytes, size_t count, size_t stride, const char* mode, const char* filter = nullptr) {
    while (c.data.size() % 4) c.data.push_back(0);
    json extension = {{"buffer", 0}, {"byteOffset", c.data.size()}, {"byteLength", bytes.size()}, {"byteStride", stride},
                      {"count", count}, {"mode", mode}};
    if (filter) extension["filter"] = filter;
    c.data.insert(c.data.end(), bytes.begin(), bytes.end());
    json view = {{"buffer", 1}, {"byteOffset", 0}, {"byteLength", count * stride}, {"extensions", {{"EXT_meshopt_compression", extension}}}};
    if (std::string(mode) == "ATTRIBUTES") view["byteStride"] = stride;
    c.document["bufferViews"].push_back(view);
}

template <class T>
std::vector<uint8_t> vertexCode(const std::vector<T>& values, size_t count, size_t stride) {
    std::vector<uint8_t> out(meshopt_encodeVertexBufferBound(count, stride));
    out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), values.data(), count, stride));
    return out;
}

// terrain(6) coded: positions (no filter), UVs (EXPONENTIAL, 24-bit mantissas), normals
// (OCTAHEDRAL, 8 bits), colours (QUATERNION, 12 bits: four positive unit components, read back
// as RGBA) and the indices as `indexMode` with `indexStride`-byte indices; textured by a.png.
Coded codedTerrain(const MeshData& m, std::vector<float>& normals, std::vector<float>& quaternions,
                   const char* indexMode = "TRIANGLES", size_t indexStride = 4) {
    Coded c;
    const size_t n = m.vertexCount();
    normals.clear(), quaternions.clear();
    std::vector<float> unit;
    for (size_t v = 0; v < n; ++v) {
        const float x = std::sin(float(v)), y = std::cos(float(v)), z = 2.0f, length = std::sqrt(x * x + y * y + z * z);
        normals.insert(normals.end(), {x / length, y / length, z / length});
        unit.insert(unit.end(), {x / length, y / length, z / length, 0.0f});
        const float q[4] = {0.2f + 0.01f * float(v % 7), 0.3f, 0.4f - 0.02f * float(v % 5), 0.8f};
        const float norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (float k : q) quaternions.push_back(k / norm);
    }
    std::vector<int8_t> octahedral(4 * n);
    meshopt_encodeFilterOct(octahedral.data(), n, 4, 8, unit.data());
    std::vector<uint32_t> exponential(2 * n);
    meshopt_encodeFilterExp(exponential.data(), n, 8, 24, m.texcoords.data());
    std::vector<int16_t> quaternion(4 * n);
    meshopt_encodeFilterQuat(quaternion.data(), n, 8, 12, quaternions.data());
    const bool sequence = std::string(indexMode) == "INDICES";
    std::vector<uint8_t> indices(sequence ? meshopt_encodeIndexSequenceBound(m.indices.size(), n) : meshopt_encodeIndexBufferBound(m.indices.size(), n));
    indices.resize(sequence ? meshopt_encodeIndexSequence(indices.data(), indices.size(), m.indices.data(), m.indices.size())
                            : meshopt_encodeIndexBuffer(indices.data(), indices.size(), m.indices.data(), m.indices.size()));
    c.document = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", {0}}}}}, {"nodes", {{{"mesh", 0}}}},
                  {"extensionsUsed", {"EXT_meshopt_compression"}}, {"extensionsRequired", {"EXT_meshopt_compression"}},
                  {"bufferViews", json::array()},
                  {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}, {"NORMAL", 2}, {"COLOR_0", 4}}},
                                                {"indices", 3}, {"material", 0}}}}}}},
                  {"materials", {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}}},
                  {"textures", {{{"source", 0}}}}, {"images", {{{"uri", "a.png"}}}}};
    const Box3f b = pieceBounds(m);
    addCodedView(c, vertexCode(m.positions, n, 12), n, 12, "ATTRIBUTES");
    addCodedView(c, vertexCode(exponential, n, 8), n, 8, "ATTRIBUTES", "EXPONENTIAL");
    addCodedView(c, vertexCode(octahedral, n, 4), n, 4, "ATTRIBUTES", "OCTAHEDRAL");
    addCodedView(c, indices, m.indices.size(), indexStride, indexMode);
    addCodedView(c, vertexCode(quaternion, n, 8), n, 8, "ATTRIBUTES", "QUATERNION");
    c.document["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"},
                                {"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}},
                               {{"bufferView", 1}, {"componentType", 5126}, {"count", n}, {"type", "VEC2"}},
                               {{"bufferView", 2}, {"componentType", 5120}, {"normalized", true}, {"count", n}, {"type", "VEC3"}},
                               {{"bufferView", 3}, {"componentType", indexStride == 2 ? 5123 : 5125}, {"count", m.indices.size()},
                                {"type", "SCALAR"}},
                               {{"bufferView", 4}, {"componentType", 5122}, {"normalized", true}, {"count", n}, {"type", "VEC4"}}};
    return c;
}

// The coded file as a .gltf (buffer 0 a data URI) or a GLB (buffer 0 its BIN chunk); buffer 1
// the fallback, with a byteLength and no data.
void writeCoded(const Coded& c, const std::string& path, bool binary) {
    json doc = c.document;
    const size_t fallback = size_t(1) << 20;  // larger than any BIN chunk here: a GLB loads only if it is filled
    json buffer0 = {{"byteLength", c.data.size()}};
    if (!binary) buffer0["uri"] = "data:application/octet-stream;base64," + base64(c.data);
    doc["buffers"] = {buffer0, {{"byteLength", fallback}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
    if (binary) writeFile(path, assembleGlb(doc.dump(), c.data));
    else std::ofstream(path) << doc.dump();
}

// Each triangle's corners rotated to start at its smallest index (its winding kept).
std::vector<uint32_t> rotated(std::vector<uint32_t> indices) {
    for (size_t t = 0; t + 2 < indices.size(); t += 3)
        std::rotate(indices.begin() + t, std::min_element(indices.begin() + t, indices.begin() + t + 3), indices.begin() + t + 3);
    return indices;
}

TEST(GltfMeshopt, ReadsAsTheSameMeshUncompressed) {
    TempDir dir;
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    const MeshData m = terrain(6).mesh;
    std::vector<float> normals, quaternions;
    struct Variant {
        const char* mode;
        size_t stride;
        bool binary;
    } variants[] = {{"TRIANGLES", 4, false}, {"TRIANGLES", 4, true}, {"TRIANGLES", 2, true}, {"INDICES", 4, false}, {"INDICES", 2, true}};
    for (const Variant& variant : variants) {
        SCOPED_TRACE(std::string(variant.binary ? "glb " : "gltf ") + variant.mode + " " + std::to_string(variant.stride));
        const std::string file = dir.file(variant.binary ? "m.glb" : "m.gltf");
        writeCoded(codedTerrain(m, normals, quaternions, variant.mode, variant.stride), file, variant.binary);
        const SourceMesh s = readMesh(file);
        EXPECT_EQ(s.piece.mesh.positions, m.positions);
        ASSERT_EQ(s.piece.mesh.texcoords.size(), m.texcoords.size());
        for (size_t i = 0; i < m.texcoords.size(); ++i) EXPECT_NEAR(s.piece.mesh.texcoords[i], m.texcoords[i], 1e-6f) << i;
        // The index codec may rotate a triangle's corners; the sequence codec keeps them.
        EXPECT_EQ(rotated(s.piece.mesh.indices), rotated(m.indices));
        ASSERT_EQ(s.piece.mesh.normals.size(), normals.size());
        for (size_t i = 0; i < normals.size(); ++i) EXPECT_NEAR(s.piece.mesh.normals[i], normals[i], 0.03f) << i;  // 8-bit octahedral
        ASSERT_EQ(s.piece.mesh.colors.size(), quaternions.size());
        for (size_t i = 0; i < quaternions.size(); ++i) EXPECT_NEAR(s.piece.mesh.colors[i], quaternions[i] * 255, 3) << i;
    }
    // `hlod build` of a GLB whose texture is in its BIN chunk: the images are taken out and the
    // compressed ranges kept (glbWithoutImages), and the build is textured.
    Coded coded = codedTerrain(m, normals, quaternions);
    const std::vector<uint8_t> png = encodeTexture(testImage(16, 16), Codec::Png).bytes;
    while (coded.data.size() % 4) coded.data.push_back(0);
    coded.document["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", coded.data.size()}, {"byteLength", png.size()}});
    coded.data.insert(coded.data.end(), png.begin(), png.end());
    coded.document["images"] = {{{"bufferView", coded.document["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
    writeCoded(coded, dir.file("t.glb"), true);
    const RunResult r = runHlod({"build", dir.file("t.glb"), "-o", dir.file("t.hlod"), "--strict"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_GT(Database::open(dir.file("t.hlod")).skeleton().nodes[0].texturedTriangles, 0u);
}

TEST(GltfBadInput, MeshoptViewsThatDoNotDecodeSayWhich) {
    TempDir dir;
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    const MeshData m = terrain(6).mesh;
    std::vector<float> normals, quaternions;
    struct Case {
        const char* label;
        std::function<void(Coded&)> spoil;
        const char* error;
    } cases[] = {
        {"cut short", [](Coded& c) { c.document["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 20; },
         "buffer view 0: EXT_meshopt_compression does not decode (meshoptimizer error"},
        {"absurd count", [](Coded& c) { c.document["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["count"] = 2000000000; },
         "buffer view 1: EXT_meshopt_compression claims 16000000000 bytes from"},
        {"past its buffer", [](Coded& c) { c.document["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = 1u << 30; },
         "buffer view 3: EXT_meshopt_compression runs past its buffer"},
        {"unknown mode", [](Coded& c) { c.document["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["mode"] = "STRIPS"; },
         "buffer view 0: EXT_meshopt_compression mode 'STRIPS' is not ATTRIBUTES, TRIANGLES or INDICES"},
        {"filter on indices", [](Coded& c) { c.document["bufferViews"][3]["extensions"]["EXT_meshopt_compression"]["filter"] = "OCTAHEDRAL"; },
         "buffer view 3: EXT_meshopt_compression filter 'OCTAHEDRAL' does not suit mode TRIANGLES"},
        {"a decoded buffer as a source", [](Coded& c) { c.document["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["buffer"] = 2; },
         "buffer view 1: EXT_meshopt_compression buffer is not an integer from 0 to 1"},
        {"an image on the fallback buffer",
         [](Coded& c) { c.document["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 1000}, {"byteLength", 3000}}),
                        c.document["images"] = {{{"bufferView", 5}, {"mimeType", "image/png"}}}; },
         "image 0 lies in a compressed buffer view (not supported)"},
        {"one range claimed by many views", [](Coded& c) {
             for (int k = 0; k < 200; ++k) {
                 json view = c.document["bufferViews"][0];  // each alone within 64 bytes per byte of the data it reads
                 json& e = view["extensions"]["EXT_meshopt_compression"];
                 e["byteOffset"] = 0, e["byteLength"] = c.data.size(), e["byteStride"] = 4, e["count"] = 16 * c.data.size();
                 view["byteStride"] = 4;
                 c.document["bufferViews"].push_back(view);
             } },
         "EXT_meshopt_compression views claim "},
        {"a stride its view contradicts", [](Coded& c) { c.document["bufferViews"][0]["byteStride"] = 16; },
         "buffer view 0: EXT_meshopt_compression byteStride 12 differs from its view's 16"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.label);
        Coded coded = codedTerrain(m, normals, quaternions);
        c.spoil(coded);
        writeCoded(coded, dir.file("bad.gltf"), false);
        const std::string error = errorOf([&] { readMesh(dir.file("bad.gltf")); });
        EXPECT_NE(error.find(dir.file("bad.gltf") + ": " + c.error), std::string::npos) << error;
    }
    // A GLB whose header claims more bytes than the file holds is refused as any such GLB is, not
    // repaired when the fallback buffers are filled (the file is written anew then).
    writeCoded(codedTerrain(m, normals, quaternions), dir.file("long.glb"), true);
    std::vector<uint8_t> glb = readFile(dir.file("long.glb"));
    const uint32_t claimed = static_cast<uint32_t>(glb.size() + 4);
    std::memcpy(glb.data() + 8, &claimed, 4);
    writeFile(dir.file("long.glb"), glb);
    for (const auto& read : {std::function<void()>([&] { readMesh(dir.file("long.glb")); }),
                             std::function<void()>([&] { RawMesh raw; parseGltf(dir.file("long.glb"), raw); })}) {
        const std::string error = errorOf(read);
        EXPECT_NE(error.find(dir.file("long.glb") + ": "), std::string::npos) << error;
        EXPECT_NE(error.find("Invalid glTF binary"), std::string::npos) << error;
    }
}

}  // namespace
}  // namespace hlod::test
