// A node as one glTF 2.0 binary (GLB, glTF 2.0 §4.4) built from the database's blobs as stored:
// each geometry blob's Draco bitstream becomes a buffer view referenced by its primitive's
// KHR_draco_mesh_compression extension, each texture blob's JPEG/PNG bytes a buffer view of an
// image. Nothing is re-encoded. Each Draco blob is decoded once, only to read what glTF needs
// beside the bytes: the attributes' Draco unique ids (the extension's `attributes` map), the
// exact POSITION min/max (required by glTF) and the decoded counts (checked against the record).
// Materials are unlit (KHR_materials_unlit): scan textures hold the captured lighting, as the
// OpenGL renderer draws them. Positions stay in the database's z-up frame; the glTF node's matrix
// turns them y-up, which 3D Tiles turns back to z-up (3D Tiles 1.1 §glTF up-axis).
#include "formats/codec.h"
#include "formats/draco_attribute.h"
#include "formats/json_text.h"
#include "formats/tiles_detail.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace hlod::tiles {

namespace {

constexpr uint32_t kGlbMagic = 0x46546C67, kChunkJson = 0x4E4F534A, kChunkBin = 0x004E4942;
constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125;

// z-up (x, y, z) to glTF's y-up (x, z, -y), column-major.
const nlohmann::json kZUpToYUp = nlohmann::json::array({1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1});

// What glTF needs to know of one Draco blob besides its bytes.
struct DracoFacts {
    int position = -1, texcoord = -1, normal = -1, color = -1;  // Draco unique ids, -1 = absent
    int colorComponents = 0;
    uint32_t points = 0, faces = 0;
    float min[3], max[3];
};

DracoFacts dracoFacts(const std::vector<uint8_t>& bytes, const BlobRef& record, const std::string& name) {
    const std::unique_ptr<draco::Mesh> decoded = decodeDracoMesh(bytes, name);
    const draco::Mesh& mesh = *decoded;
    using GA = draco::GeometryAttribute;
    DracoFacts f;
    f.points = mesh.num_points();
    f.faces = mesh.num_faces();
    if (f.points != record.vertices || f.faces != record.triangles || f.points == 0)
        throw FormatError(name + ": Draco geometry decodes to " + std::to_string(f.faces) + " triangles and " +
                          std::to_string(f.points) + " vertices, its record says " + std::to_string(record.triangles) +
                          " and " + std::to_string(record.vertices));
    const draco::PointAttribute* pos = checkedDracoAttribute(mesh, GA::POSITION, draco::DT_FLOAT32, 3, 3, name);
    if (!pos) throw FormatError(name + ": Draco geometry has no positions");
    f.position = int(pos->unique_id());
    if (auto* a = checkedDracoAttribute(mesh, GA::TEX_COORD, draco::DT_FLOAT32, 2, 2, name)) f.texcoord = int(a->unique_id());
    if (auto* a = checkedDracoAttribute(mesh, GA::NORMAL, draco::DT_FLOAT32, 3, 3, name)) f.normal = int(a->unique_id());
    if (auto* a = checkedDracoAttribute(mesh, GA::COLOR, draco::DT_UINT8, 3, 4, name)) {
        f.color = int(a->unique_id());
        f.colorComponents = a->num_components();
    }
    std::fill(f.min, f.min + 3, std::numeric_limits<float>::max());
    std::fill(f.max, f.max + 3, std::numeric_limits<float>::lowest());
    float p[3];
    for (uint32_t i = 0; i < f.points; ++i) {
        pos->ConvertValue(pos->mapped_index(draco::PointIndex(i)), 3, p);
        for (int c = 0; c < 3; ++c) f.min[c] = std::min(f.min[c], p[c]), f.max[c] = std::max(f.max[c], p[c]);
    }
    return f;
}

// The GLB's binary chunk and the JSON that describes it.
struct Builder {
    nlohmann::json gltf;
    std::vector<uint8_t> bin;

    int bufferView(const std::vector<uint8_t>& bytes) {
        bin.resize((bin.size() + 3) & ~size_t(3));  // 4-byte aligned views
        nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
        bin.insert(bin.end(), bytes.begin(), bytes.end());
        gltf["bufferViews"].push_back(view);
        return int(gltf["bufferViews"].size() - 1);
    }
    int accessor(nlohmann::json a) {
        gltf["accessors"].push_back(std::move(a));
        return int(gltf["accessors"].size() - 1);
    }
};

void appendChunk(std::vector<uint8_t>& out, uint32_t type, const std::vector<uint8_t>& data, uint8_t pad) {
    const uint32_t length = uint32_t((data.size() + 3) & ~size_t(3));
    const uint32_t header[2] = {length, type};
    const size_t at = out.size();
    out.resize(at + 8);
    std::memcpy(out.data() + at, header, 8);
    out.insert(out.end(), data.begin(), data.end());
    out.resize(at + 8 + length, pad);
}

std::vector<uint8_t> glbBytes(const nlohmann::json& gltf, const std::vector<uint8_t>& bin) {
    const std::string text = jsonText(gltf);
    std::vector<uint8_t> json(text.begin(), text.end());
    std::vector<uint8_t> out(12);
    appendChunk(out, kChunkJson, json, ' ');
    appendChunk(out, kChunkBin, bin, 0);
    const uint32_t header[3] = {kGlbMagic, 2, uint32_t(out.size())};
    std::memcpy(out.data(), header, 12);
    return out;
}

}  // namespace

std::string contentUri(uint32_t node) { return "tiles/" + std::to_string(node) + ".glb"; }

std::optional<Glb> nodeGlb(const Database& db, uint32_t node) {
    const Skeleton& s = db.skeleton();
    const Node& n = s.nodes[node];
    Builder b;
    using J = nlohmann::json;
    b.gltf = {{"asset", {{"version", "2.0"}, {"generator", "hlod export tiles"}}},
              {"scene", 0},
              {"scenes", J::array({J{{"nodes", J::array({0})}}})},
              {"nodes", J::array({J{{"mesh", 0}, {"matrix", kZUpToYUp}}})},
              {"bufferViews", J::array()},
              {"accessors", J::array()},
              {"extensionsUsed", J::array({"KHR_draco_mesh_compression"})},
              {"extensionsRequired", J::array({"KHR_draco_mesh_compression"})}};
    J primitives = J::array(), materials = J::array(), images = J::array(), textures = J::array();
    std::vector<int> materialOfTexture(n.blobCount, -1);  // by blob slot within the node
    int untexturedMaterial = -1;
    Glb glb;
    glb.bounds = {{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()},
                  {std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest()}};

    auto materialFor = [&](uint32_t textureBlob) {
        if (textureBlob == kNone) {
            if (untexturedMaterial < 0) {
                materials.push_back({{"pbrMetallicRoughness", {{"baseColorFactor", J::array({0.8, 0.8, 0.8, 1.0})},
                                                               {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
                                     {"doubleSided", true}});
                untexturedMaterial = int(materials.size() - 1);
            }
            return untexturedMaterial;
        }
        if (textureBlob < n.firstBlob || textureBlob >= n.firstBlob + n.blobCount)
            throw FormatError(db.path() + ": node " + std::to_string(node) + " samples texture blob " +
                              std::to_string(textureBlob) + " of another node");
        int& m = materialOfTexture[textureBlob - n.firstBlob];
        if (m < 0) {
            const BlobRef& t = s.blobs[textureBlob];
            const std::vector<uint8_t> bytes = db.readBlob(textureBlob);
            // Copied as stored, so it is decoded once here (a blob that does not decode made a
            // tileset no viewer can show, with status 0: its header before stop 36, its body before 38).
            const std::string name = db.path() + ": node " + std::to_string(node) + ": blob " + std::to_string(textureBlob);
            const Image size = decodeTexture(bytes, t.codec, name);
            if (size.width != t.width || size.height != t.height)
                throw FormatError(name + ": texture is " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                                  ", its record says " + std::to_string(t.width) + "x" + std::to_string(t.height));
            const int view = b.bufferView(bytes);
            images.push_back({{"bufferView", view}, {"mimeType", t.codec == Codec::Png ? "image/png" : "image/jpeg"}});
            textures.push_back({{"sampler", 0}, {"source", images.size() - 1}});
            materials.push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", textures.size() - 1}}},
                                                           {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
                                 {"doubleSided", true},
                                 {"extensions", {{"KHR_materials_unlit", J::object()}}}});
            m = int(materials.size() - 1);
        }
        return m;
    };

    for (uint32_t i = n.firstBlob; i < n.firstBlob + n.blobCount; ++i) {
        const BlobRef& r = s.blobs[i];
        if (r.kind != BlobKind::Geometry) continue;
        const std::string name = db.path() + ": blob " + std::to_string(i) + " (node " + std::to_string(node) + ")";
        const std::vector<uint8_t> bytes = db.readBlob(i);
        const DracoFacts f = dracoFacts(bytes, r, name);
        const int view = b.bufferView(bytes);
        J attributes, draco;
        attributes["POSITION"] = b.accessor({{"componentType", kFloat}, {"count", f.points}, {"type", "VEC3"},
                                             {"min", J::array({f.min[0], f.min[1], f.min[2]})},
                                             {"max", J::array({f.max[0], f.max[1], f.max[2]})}});
        draco["POSITION"] = f.position;
        if (f.texcoord >= 0) {
            attributes["TEXCOORD_0"] = b.accessor({{"componentType", kFloat}, {"count", f.points}, {"type", "VEC2"}});
            draco["TEXCOORD_0"] = f.texcoord;
        }
        if (f.normal >= 0) {
            attributes["NORMAL"] = b.accessor({{"componentType", kFloat}, {"count", f.points}, {"type", "VEC3"}});
            draco["NORMAL"] = f.normal;
        }
        if (f.color >= 0) {
            attributes["COLOR_0"] = b.accessor({{"componentType", kUnsignedByte}, {"normalized", true},
                                                {"count", f.points}, {"type", f.colorComponents == 4 ? "VEC4" : "VEC3"}});
            draco["COLOR_0"] = f.color;
        }
        const int indices = b.accessor({{"componentType", f.points <= 65535 ? kUnsignedShort : kUnsignedInt},
                                        {"count", uint64_t(f.faces) * 3}, {"type", "SCALAR"}});
        // A textured sub-mesh without texture coordinates is drawn untextured (validate reports it).
        const int material = materialFor(f.texcoord >= 0 ? r.texture : kNone);
        primitives.push_back({{"attributes", attributes},
                              {"indices", indices},
                              {"material", material},
                              {"mode", 4},
                              {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", draco}}}}}});
        glb.triangles += f.faces;
        glb.bounds.min = {std::min(glb.bounds.min.x, f.min[0]), std::min(glb.bounds.min.y, f.min[1]),
                          std::min(glb.bounds.min.z, f.min[2])};
        glb.bounds.max = {std::max(glb.bounds.max.x, f.max[0]), std::max(glb.bounds.max.y, f.max[1]),
                          std::max(glb.bounds.max.z, f.max[2])};
    }
    if (primitives.empty()) return std::nullopt;
    b.gltf["meshes"] = J::array({J{{"primitives", primitives}}});
    b.gltf["materials"] = materials;
    if (!images.empty()) {  // textured materials are the unlit ones
        b.gltf["images"] = images;
        b.gltf["textures"] = textures;
        // Linear, trilinear mipmaps, CLAMP_TO_EDGE as `hlod play` samples (player/gl/gl_mesh.cpp): a
        // node's UVs may pass its atlas's edge to read the edge texels (a clamped source texture, a
        // chart straddling a period); glTF's default REPEAT read the other side there until stop 51.
        b.gltf["samplers"] = J::array({J{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}});
        b.gltf["extensionsUsed"].push_back("KHR_materials_unlit");
    }
    b.gltf["buffers"] = J::array({J{{"byteLength", (b.bin.size() + 3) & ~size_t(3)}}});
    glb.bytes = glbBytes(b.gltf, b.bin);
    return glb;
}

}  // namespace hlod::tiles
