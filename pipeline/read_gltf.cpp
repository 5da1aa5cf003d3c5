// glTF 2.0 / GLB input through tinygltf (header-only mode, built with Draco so
// KHR_draco_mesh_compression primitives decode): the default scene's node tree with its
// transforms flattened into one mesh; TRIANGLES primitives; POSITION, TEXCOORD_0, NORMAL,
// COLOR_0; base-colour textures: embedded images decoded by stb_image, external ones by path
// (resolved inside the input's folder, loaded later through OpenImageIO).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_ENABLE_DRACO
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_INCLUDE_JSON
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "pipeline/pipeline.h"

#include <array>
#include <cmath>
#include <filesystem>

namespace hlod {
namespace {

using Matrix = std::array<double, 16>;  // column-major, as glTF

Matrix multiply(const Matrix& a, const Matrix& b) {
    Matrix r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row)
            for (int k = 0; k < 4; ++k) r[c * 4 + row] += a[k * 4 + row] * b[c * 4 + k];
    return r;
}

Matrix localMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Matrix m;
        std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
        return m;
    }
    const auto& t = node.translation.size() == 3 ? node.translation : std::vector<double>{0, 0, 0};
    const auto& q = node.rotation.size() == 4 ? node.rotation : std::vector<double>{0, 0, 0, 1};
    const auto& s = node.scale.size() == 3 ? node.scale : std::vector<double>{1, 1, 1};
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const Matrix r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
                      2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
                      2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
                      0,                       0,                       0,                       1};
    Matrix m = r;
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row) m[c * 4 + row] *= s[c];
    m[12] = t[0], m[13] = t[1], m[14] = t[2];
    return m;
}

// Reads accessor `index` as `width` floats per element (normalized integers mapped to [0,1]).
std::vector<float> readFloats(const tinygltf::Model& model, int index, int width, const std::string& path) {
    if (index < 0 || index >= static_cast<int>(model.accessors.size())) throw InputError(path + ": accessor out of range");
    const tinygltf::Accessor& a = model.accessors[index];
    const int components = tinygltf::GetNumComponentsInType(a.type);
    const int bytes = tinygltf::GetComponentSizeInBytes(a.componentType);
    if (components < width || bytes <= 0 || a.bufferView < 0 || a.bufferView >= static_cast<int>(model.bufferViews.size()))
        throw InputError(path + ": unsupported or corrupt accessor " + std::to_string(index));
    const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) throw InputError(path + ": corrupt buffer view");
    const auto& data = model.buffers[view.buffer].data;
    const size_t stride = a.ByteStride(view) > 0 ? static_cast<size_t>(a.ByteStride(view)) : static_cast<size_t>(components * bytes);
    const size_t begin = view.byteOffset + a.byteOffset;
    if (a.count > 0 && (begin + stride * (a.count - 1) + static_cast<size_t>(components * bytes) > data.size() ||
                        begin + stride * (a.count - 1) + static_cast<size_t>(components * bytes) > view.byteOffset + view.byteLength))
        throw InputError(path + ": accessor " + std::to_string(index) + " runs past its buffer (truncated file?)");
    std::vector<float> out;
    out.reserve(a.count * width);
    for (size_t i = 0; i < a.count; ++i)
        for (int c = 0; c < width; ++c) {
            const unsigned char* p = data.data() + begin + stride * i + static_cast<size_t>(c * bytes);
            float v = 0;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, p, 4); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = p[0] / (a.normalized ? 255.0f : 1.0f); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t u;
                std::memcpy(&u, p, 2);
                v = u / (a.normalized ? 65535.0f : 1.0f);
                break;
            }
            default: throw InputError(path + ": unsupported component type in accessor " + std::to_string(index));
            }
            out.push_back(v);
        }
    return out;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& path) {
    const tinygltf::Accessor& a = model.accessors.at(static_cast<size_t>(index));
    const tinygltf::BufferView& view = model.bufferViews.at(static_cast<size_t>(a.bufferView));
    const auto& data = model.buffers.at(static_cast<size_t>(view.buffer)).data;
    const int bytes = tinygltf::GetComponentSizeInBytes(a.componentType);
    const size_t begin = view.byteOffset + a.byteOffset;
    if (bytes <= 0 || begin + a.count * static_cast<size_t>(bytes) > data.size())
        throw InputError(path + ": index accessor " + std::to_string(index) + " runs past its buffer (truncated file?)");
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        const unsigned char* p = data.data() + begin + i * bytes;
        uint32_t v = 0;
        if (bytes == 1) v = p[0];
        else if (bytes == 2) { uint16_t u; std::memcpy(&u, p, 2); v = u; }
        else std::memcpy(&v, p, 4);
        out[i] = v;
    }
    return out;
}

struct Context {
    const tinygltf::Model& model;
    const std::string& path;
    SourceMesh& out;
    std::vector<uint32_t> materialOfGltf;  // glTF material -> index in out.materials
};

void addPrimitive(Context& cx, const tinygltf::Primitive& prim, const Matrix& m) {
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) return;
    const auto attr = [&](const char* name) { auto it = prim.attributes.find(name); return it == prim.attributes.end() ? -1 : it->second; };
    if (attr("POSITION") < 0) throw InputError(cx.path + ": primitive without POSITION");
    const std::vector<float> pos = readFloats(cx.model, attr("POSITION"), 3, cx.path);
    const size_t count = pos.size() / 3;
    MeshData& mesh = cx.out.piece.mesh;
    const uint32_t base = static_cast<uint32_t>(mesh.vertexCount());
    for (size_t i = 0; i < count; ++i)
        for (int r = 0; r < 3; ++r)
            mesh.positions.push_back(static_cast<float>(m[r] * pos[3 * i] + m[4 + r] * pos[3 * i + 1] + m[8 + r] * pos[3 * i + 2] + m[12 + r]));
    std::vector<float> uv = attr("TEXCOORD_0") >= 0 ? readFloats(cx.model, attr("TEXCOORD_0"), 2, cx.path) : std::vector<float>(2 * count, 0.0f);
    if (uv.size() != 2 * count) throw InputError(cx.path + ": TEXCOORD_0 count differs from POSITION");
    mesh.texcoords.insert(mesh.texcoords.end(), uv.begin(), uv.end());
    std::vector<uint32_t> indices = prim.indices >= 0 ? readIndices(cx.model, prim.indices, cx.path) : std::vector<uint32_t>(count);
    if (prim.indices < 0)
        for (size_t i = 0; i < count; ++i) indices[i] = static_cast<uint32_t>(i);
    const uint32_t material = prim.material >= 0 && static_cast<size_t>(prim.material) < cx.materialOfGltf.size()
                                  ? cx.materialOfGltf[prim.material]
                                  : static_cast<uint32_t>(cx.out.materials.size() - 1);
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            if (indices[t + k] >= count) throw InputError(cx.path + ": index " + std::to_string(indices[t + k]) + " out of range");
            mesh.indices.push_back(base + indices[t + k]);
        }
        cx.out.piece.materials.push_back(material);
    }
}

void addNode(Context& cx, int index, const Matrix& parent, int depth) {
    if (index < 0 || index >= static_cast<int>(cx.model.nodes.size()) || depth > 64)
        throw InputError(cx.path + ": corrupt node tree");
    const tinygltf::Node& node = cx.model.nodes[index];
    const Matrix m = multiply(parent, localMatrix(node));
    if (node.mesh >= 0 && node.mesh < static_cast<int>(cx.model.meshes.size()))
        for (const auto& prim : cx.model.meshes[node.mesh].primitives) addPrimitive(cx, prim, m);
    for (int child : node.children) addNode(cx, child, m, depth + 1);
}

void addMaterials(Context& cx) {
    for (const tinygltf::Material& mat : cx.model.materials) {
        Material out{mat.name, "", nullptr};
        const int tex = mat.pbrMetallicRoughness.baseColorTexture.index;
        if (tex >= 0 && tex < static_cast<int>(cx.model.textures.size())) {
            const int source = cx.model.textures[tex].source;
            if (source >= 0 && source < static_cast<int>(cx.model.images.size())) {
                const tinygltf::Image& img = cx.model.images[source];
                if (!img.image.empty() && img.width > 0 && img.height > 0 && img.component > 0) {
                    auto image = std::make_shared<Image>();
                    image->width = static_cast<uint32_t>(img.width), image->height = static_cast<uint32_t>(img.height);
                    image->channels = img.component >= 3 ? 3 : 1;
                    for (size_t p = 0; p < static_cast<size_t>(img.width) * img.height; ++p)
                        for (uint32_t c = 0; c < image->channels; ++c) image->pixels.push_back(img.image[p * img.component + c]);
                    out.image = image;
                } else if (!img.uri.empty()) {
                    out.texturePath = resolveTexturePath(cx.path, img.uri);
                }
            }
        }
        cx.materialOfGltf.push_back(static_cast<uint32_t>(cx.out.materials.size()));
        cx.out.materials.push_back(out);
    }
    cx.out.materials.push_back({"default", "", nullptr});
}

}  // namespace

SourceMesh readGltf(const std::string& path) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    const bool binary = std::filesystem::path(path).extension() == ".glb";
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) throw InputError(path + ": corrupt glTF (" + err.substr(0, err.find('\n')) + ")");
    SourceMesh out;
    Context cx{model, path, out, {}};
    addMaterials(cx);
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (scene < static_cast<int>(model.scenes.size())) {
        for (int node : model.scenes[scene].nodes) addNode(cx, node, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, 0);
    } else {
        std::vector<bool> isChild(model.nodes.size());
        for (const auto& node : model.nodes)
            for (int c : node.children)
                if (c >= 0 && static_cast<size_t>(c) < isChild.size()) isChild[c] = true;
        for (size_t n = 0; n < model.nodes.size(); ++n)
            if (!isChild[n]) addNode(cx, static_cast<int>(n), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, 0);
    }
    bool textured = false;
    for (const Material& m : out.materials) textured = textured || m.image || !m.texturePath.empty();
    if (!textured) out.piece.mesh.texcoords.clear();
    sanitize(out, path);
    return out;
}

}  // namespace hlod
