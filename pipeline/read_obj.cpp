// OBJ + MTL input through tinyobjloader: many materials and texture atlases (map_Kd), as
// photogrammetry produces. Corners are welded by their (position, texcoord, normal) index
// triple in first-use order, so the result is deterministic and UV seams stay seams.
#include "pipeline/pipeline.h"

#include <tiny_obj_loader.h>

#include <filesystem>
#include <unordered_map>

namespace hlod {
namespace {

struct CornerKey {
    int v, t, n;
    bool operator==(const CornerKey&) const = default;
};
struct CornerHash {
    size_t operator()(const CornerKey& k) const {
        return (static_cast<size_t>(k.v) * 73856093u) ^ (static_cast<size_t>(k.t) * 19349663u) ^
               (static_cast<size_t>(k.n) * 83492791u);
    }
};

std::string firstLine(const std::string& text) {
    return text.substr(0, text.find('\n'));
}

uint32_t addCorner(const tinyobj::attrib_t& attrib, const tinyobj::index_t& index, MeshData& mesh,
                   std::unordered_map<CornerKey, uint32_t, CornerHash>& corners, bool withUV, bool withNormals,
                   const std::string& path) {
    const CornerKey key{index.vertex_index, withUV ? index.texcoord_index : -1, withNormals ? index.normal_index : -1};
    if (auto it = corners.find(key); it != corners.end()) return it->second;
    if (key.v < 0 || static_cast<size_t>(key.v) * 3 >= attrib.vertices.size() ||
        (withUV && (key.t < 0 || static_cast<size_t>(key.t) * 2 >= attrib.texcoords.size())) ||
        (withNormals && (key.n < 0 || static_cast<size_t>(key.n) * 3 >= attrib.normals.size())))
        throw InputError(path + ": face index out of range (v " + std::to_string(key.v + 1) + ")");
    const uint32_t id = static_cast<uint32_t>(mesh.vertexCount());
    for (int a = 0; a < 3; ++a) mesh.positions.push_back(attrib.vertices[3 * key.v + a]);
    if (withUV) {
        mesh.texcoords.push_back(attrib.texcoords[2 * key.t]);
        mesh.texcoords.push_back(1.0f - attrib.texcoords[2 * key.t + 1]);
    }
    if (withNormals)
        for (int a = 0; a < 3; ++a) mesh.normals.push_back(attrib.normals[3 * key.n + a]);
    corners.emplace(key, id);
    return id;
}

bool allFacesHave(const std::vector<tinyobj::shape_t>& shapes, int tinyobj::index_t::*field) {
    for (const auto& shape : shapes)
        for (const auto& index : shape.mesh.indices)
            if (index.*field < 0) return false;
    return true;
}

}  // namespace

SourceMesh readObj(const std::string& path) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = std::filesystem::path(path).parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config))
        throw InputError(path + ": corrupt OBJ (" + firstLine(reader.Error()) + ")");
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const auto& shapes = reader.GetShapes();
    SourceMesh source;
    for (const auto& m : reader.GetMaterials())
        source.materials.push_back({m.name, m.diffuse_texname.empty() ? "" : resolveTexturePath(path, m.diffuse_texname), nullptr});
    const uint32_t defaultMaterial = static_cast<uint32_t>(source.materials.size());
    source.materials.push_back({"default", "", nullptr});
    if (!reader.Warning().empty() && reader.Warning().find("not found") != std::string::npos)
        source.stats.warnings.push_back(path + ": " + firstLine(reader.Warning()));

    const bool withUV = !attrib.texcoords.empty() && allFacesHave(shapes, &tinyobj::index_t::texcoord_index);
    const bool withNormals = !attrib.normals.empty() && allFacesHave(shapes, &tinyobj::index_t::normal_index);
    std::unordered_map<CornerKey, uint32_t, CornerHash> corners;
    MeshData& mesh = source.piece.mesh;
    for (const auto& shape : shapes) {
        const auto& indices = shape.mesh.indices;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            if (shape.mesh.num_face_vertices[f] != 3) throw InputError(path + ": corrupt OBJ (face not triangulated)");
            for (int k = 0; k < 3; ++k)
                mesh.indices.push_back(addCorner(attrib, indices[3 * f + k], mesh, corners, withUV, withNormals, path));
            const int mat = shape.mesh.material_ids[f];
            source.piece.materials.push_back(mat < 0 || mat >= static_cast<int>(defaultMaterial)
                                                 ? defaultMaterial
                                                 : static_cast<uint32_t>(mat));
        }
    }
    sanitize(source, path);
    return source;
}

}  // namespace hlod
