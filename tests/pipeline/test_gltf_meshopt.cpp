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

// terrain(6)'s positions, UVs (textured by a.png), octahedral-coded normals and indices, coded.
Coded codedTerrain(const MeshData& m, std::vector<float>& normals) {
    Coded c;
    const size_t n = m.vertexCount();
    normals.clear();
    std::vector<float> unit;
    for (size_t v = 0; v < n; ++v) {
        const float x = std::sin(float(v)), y = std::cos(float(v)), z = 2.0f, length = std::sqrt(x * x + y * y + z * z);
        normals.insert(normals.end(), {x / length, y / length, z / length});
        unit.insert(unit.end(), {x / length, y / length, z / length, 0.0f});
    }
    std::vector<int8_t> octahedral(4 * n);
    meshopt_encodeFilterOct(octahedral.data(), n, 4, 8, unit.data());
    std::vector<uint8_t> indices(meshopt_encodeIndexBufferBound(m.indices.size(), n));
    indices.resize(meshopt_encodeIndexBuffer(indices.data(), indices.size(), m.indices.data(), m.indices.size()));
    c.document = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", {0}}}}}, {"nodes", {{{"mesh", 0}}}},
                  {"extensionsUsed", {"EXT_meshopt_compression"}}, {"extensionsRequired", {"EXT_meshopt_compression"}},
                  {"bufferViews", json::array()},
                  {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}, {"NORMAL", 2}}}, {"indices", 3},
                                                {"material", 0}}}}}}},
                  {"materials", {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}}},
                  {"textures", {{{"source", 0}}}}, {"images", {{{"uri", "a.png"}}}}};
    const Box3f b = pieceBounds(m);
    addCodedView(c, vertexCode(m.positions, n, 12), n, 12, "ATTRIBUTES");
    addCodedView(c, vertexCode(m.texcoords, n, 8), n, 8, "ATTRIBUTES");
    addCodedView(c, vertexCode(octahedral, n, 4), n, 4, "ATTRIBUTES", "OCTAHEDRAL");
    addCodedView(c, indices, m.indices.size(), 4, "TRIANGLES");
    c.document["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"},
                                {"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}},
                               {{"bufferView", 1}, {"componentType", 5126}, {"count", n}, {"type", "VEC2"}},
                               {{"bufferView", 2}, {"componentType", 5120}, {"normalized", true}, {"count", n}, {"type", "VEC3"}},
                               {{"bufferView", 3}, {"componentType", 5125}, {"count", m.indices.size()}, {"type", "SCALAR"}}};
    return c;
}

// The coded file as a .gltf (buffer 0 a data URI) or a GLB (buffer 0 its BIN chunk); buffer 1
// the fallback, with a byteLength and no data.
void writeCoded(const Coded& c, const std::string& path, bool binary) {
    json doc = c.document;
    size_t fallback = 0;
    for (const json& view : doc["bufferViews"]) fallback = std::max(fallback, view["byteLength"].get<size_t>());
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
    std::vector<float> normals;
    const Coded coded = codedTerrain(m, normals);
    for (const bool binary : {false, true}) {
        SCOPED_TRACE(binary ? "glb" : "gltf");
        const std::string file = dir.file(binary ? "m.glb" : "m.gltf");
        writeCoded(coded, file, binary);
        const SourceMesh s = readMesh(file);
        EXPECT_EQ(s.piece.mesh.positions, m.positions);
        EXPECT_EQ(s.piece.mesh.texcoords, m.texcoords);
        EXPECT_EQ(rotated(s.piece.mesh.indices), rotated(m.indices));  // the index codec may rotate a triangle's corners
        ASSERT_EQ(s.piece.mesh.normals.size(), normals.size());
        for (size_t i = 0; i < normals.size(); ++i) EXPECT_NEAR(s.piece.mesh.normals[i], normals[i], 0.03f) << i;  // 8-bit octahedral
        const RunResult r = runHlod({"build", file, "-o", dir.file("m.hlod"), "--strict"});
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
        EXPECT_GT(Database::open(dir.file("m.hlod")).skeleton().nodes[0].texturedTriangles, 0u);
        std::filesystem::remove(dir.file("m.hlod"));
    }
}

TEST(GltfBadInput, MeshoptViewsThatDoNotDecodeSayWhich) {
    TempDir dir;
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    const MeshData m = terrain(6).mesh;
    std::vector<float> normals;
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
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.label);
        Coded coded = codedTerrain(m, normals);
        c.spoil(coded);
        writeCoded(coded, dir.file("bad.gltf"), false);
        const std::string error = errorOf([&] { readMesh(dir.file("bad.gltf")); });
        EXPECT_NE(error.find(dir.file("bad.gltf") + ": " + c.error), std::string::npos) << error;
    }
}

}  // namespace
}  // namespace hlod::test
