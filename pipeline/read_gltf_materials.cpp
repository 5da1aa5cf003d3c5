// glTF materials for read_gltf.cpp (declared in read_gltf_load.h): each material's base-colour
// texture (or KHR_materials_pbrSpecularGlossiness's diffuse one; embedded and decoded, embedded
// and written to the image folder, or an external file confined to the input's folder), its
// sampler's wrap, and how it reads its primitive's texture coordinates: the set `texCoord` names
// and KHR_texture_transform's offset, rotation and scale.
#include "pipeline/read_gltf_load.h"
#include "pipeline/texture_store.h"

#include <cctype>
#include <climits>
#include <exception>
#include <cmath>
#include <filesystem>

namespace hlod {
namespace {

constexpr int kMaxTexcoordSet = 255;  // TEXCOORD_n: a larger n names no attribute any exporter writes

// An image stb_image decoded (8 or 16 bits per channel) as 8-bit grey or RGB.
std::shared_ptr<Image> decodedImage(const std::string& path, const tinygltf::Image& img, size_t index) {
    const size_t bytes = img.bits == 16 ? 2 : 1;
    const size_t pixels = static_cast<size_t>(img.width) * static_cast<size_t>(img.height);
    if (img.image.size() < pixels * static_cast<size_t>(img.component) * bytes)
        throw InputError(path + ": image " + std::to_string(index) + " is truncated");
    auto image = std::make_shared<Image>();
    image->width = static_cast<uint32_t>(img.width), image->height = static_cast<uint32_t>(img.height);
    image->channels = img.component >= 3 ? 3 : 1;
    image->pixels.reserve(pixels * image->channels);
    for (size_t p = 0; p < pixels; ++p)
        for (uint32_t c = 0; c < image->channels; ++c)  // the high byte of a little-endian 16-bit sample
            image->pixels.push_back(img.image[(p * static_cast<size_t>(img.component) + c) * bytes + bytes - 1]);
    return image;
}

// The bytes of an image embedded through a buffer view (empty if it is not): a JPEG's header
// gives its quality and chroma (jpegQuality, jpegChroma420).
std::span<const uint8_t> embeddedImageBytes(const tinygltf::Model& model, const tinygltf::Image& img) {
    if (img.bufferView < 0 || img.bufferView >= static_cast<int>(model.bufferViews.size())) return {};
    const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(img.bufferView)];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) return {};
    const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) return {};
    return std::span<const uint8_t>(data.data() + view.byteOffset, view.byteLength);
}

// The period of a sampler's wrap (wrap_uvs.cpp): REPEAT 1, MIRRORED_REPEAT 2, CLAMP_TO_EDGE none.
float uvPeriod(int wrap) { return wrap == TINYGLTF_TEXTURE_WRAP_REPEAT ? 1.0f : wrap == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? 2.0f : 0.0f; }

// A finite JSON number (tinygltf::Value), or InputError naming `what`.
double number(const tinygltf::Value& v, const std::string& what) {
    if (!v.IsNumber()) throw InputError(what + " is not a number");
    const double x = v.GetNumberAsDouble();
    if (!std::isfinite(x)) throw InputError(what + " is not finite");
    return x;
}

// Member `key` of an extension object (its element `index` when the member is a 2-array; -1:
// a number), or `fallback` when absent.
double member(const tinygltf::Value& object, const char* key, int index, double fallback, const std::string& what) {
    if (!object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    if (index < 0) return number(v, what + " " + key);
    if (!v.IsArray() || v.ArrayLen() != 2) throw InputError(what + " " + key + " is not an array of 2 numbers");
    return number(v.Get(index), what + " " + key);
}

// An integer member in [0, high] (a glTF index or coordinate set), or `fallback` when absent.
int integerMember(const tinygltf::Value& object, const char* key, int fallback, int high, const std::string& what) {
    const double x = member(object, key, -1, fallback, what);
    if (x == fallback) return fallback;
    if (!(x >= 0 && x <= high && x == std::floor(x)))
        throw InputError(what + " " + key + " is " + formatConstant(x) + ", not an integer from 0 to " + std::to_string(high));
    return static_cast<int>(x);
}

// KHR_texture_transform (its README, "Overview" and the example "the lower left quadrant of the
// source image, rotated clockwise 90°"): uv' = T(offset) R(rotation) S(scale) uv, with R's rows
// (cos, sin) and (-sin, cos): the rotation that example needs (the GLSL listing there, read as
// GLSL's column-major mat3, would turn the other way).
UvMapping uvMapping(const tinygltf::TextureInfo& info, const std::string& what) {
    UvMapping m;
    m.set = info.texCoord;
    const auto it = info.extensions.find("KHR_texture_transform");
    if (it == info.extensions.end()) return m;
    const tinygltf::Value& t = it->second;
    const std::string name = what + ": KHR_texture_transform";
    if (!t.IsObject()) throw InputError(name + " is not an object");
    const double ox = member(t, "offset", 0, 0, name), oy = member(t, "offset", 1, 0, name);
    const double r = member(t, "rotation", -1, 0, name), sx = member(t, "scale", 0, 1, name), sy = member(t, "scale", 1, 1, name);
    m.set = integerMember(t, "texCoord", m.set, kMaxTexcoordSet, name);
    const double c = std::cos(r), s = std::sin(r);
    m.affine = {c * sx, -s * sx, s * sy, c * sy, ox, oy};
    return m;
}

// An image URI as a file name: glTF URIs are percent-encoded (RFC 3986, glTF 2.0 "URIs"), so
// `my%20atlas.jpg` is the file `my atlas.jpg`; a `%` not followed by two hex digits, or coding a
// control character, stays as written.
std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        const auto hex = [&](size_t k) { return k < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[k])); };
        const int byte = uri[i] == '%' && hex(i + 1) && hex(i + 2) ? std::stoi(uri.substr(i + 1, 2), nullptr, 16) : -1;
        if (byte >= 0x20) {  // not a control character (a NUL would end the name the system sees)
            out += static_cast<char>(byte);
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// An external image's file: the decoded URI's, or, when no file has that name or it is refused,
// the URI's as written when that one exists (an exporter that wrote `%` into a name unencoded).
std::string imageFile(const std::string& path, const std::string& uri, const ReadOptions& options) {
    const std::string decoded = percentDecoded(uri);
    if (decoded == uri) return resolveReference(path, folderOf(path), uri, "image", options);
    std::string file;
    std::exception_ptr refused;
    try {
        file = resolveReference(path, folderOf(path), decoded, "image", options);
        if (std::filesystem::exists(file)) return file;
    } catch (const InputError&) {
        refused = std::current_exception();
    }
    try {
        const std::string written = resolveReference(path, folderOf(path), uri, "image", options);
        if (std::filesystem::exists(written)) return written;
    } catch (const InputError&) {  // the decoded name's answer stands
    }
    if (refused) std::rethrow_exception(refused);
    return file;
}

// The texture a material's colour comes from: its base-colour texture, or without one the
// diffuse texture of KHR_materials_pbrSpecularGlossiness (the archived specular-glossiness
// workflow of older exports), read into a TextureInfo.
tinygltf::TextureInfo colourTexture(const tinygltf::Material& mat, const std::string& what) {
    const tinygltf::TextureInfo& base = mat.pbrMetallicRoughness.baseColorTexture;
    const auto it = mat.extensions.find("KHR_materials_pbrSpecularGlossiness");
    if (base.index >= 0 || it == mat.extensions.end() || !it->second.IsObject() || !it->second.Has("diffuseTexture")) return base;
    const tinygltf::Value& diffuse = it->second.Get("diffuseTexture");
    const std::string name = what + ": KHR_materials_pbrSpecularGlossiness diffuseTexture";
    if (!diffuse.IsObject()) throw InputError(name + " is not an object");
    tinygltf::TextureInfo info;
    info.index = integerMember(diffuse, "index", -1, INT_MAX, name);
    info.texCoord = integerMember(diffuse, "texCoord", 0, kMaxTexcoordSet, name);
    if (diffuse.Has("extensions") && diffuse.Get("extensions").Has("KHR_texture_transform"))
        info.extensions["KHR_texture_transform"] = diffuse.Get("extensions").Get("KHR_texture_transform");
    return info;
}

}  // namespace

GltfMaterials addGltfMaterials(const tinygltf::Model& model, const EmbeddedImages& images, const std::string& path,
                               const ReadOptions& options, RawMesh& raw) {
    GltfMaterials out;
    for (size_t index = 0; index < model.materials.size(); ++index) {
        const tinygltf::Material& mat = model.materials[index];
        Material material{mat.name, "", nullptr};
        const tinygltf::TextureInfo info = colourTexture(mat, path + ": material " + std::to_string(index));
        out.uvOfGltf.push_back(uvMapping(info, path + ": material " + std::to_string(index)));
        if (out.uvOfGltf.back().set < 0 || out.uvOfGltf.back().set > kMaxTexcoordSet)
            throw InputError(path + ": material " + std::to_string(index) + " reads texture coordinate set " +
                             std::to_string(out.uvOfGltf.back().set));
        const int tex = info.index;
        // A texture or image that is not there is unusable like any other (README "Textures: one rule";
        // until stop 44 these left the material untextured without a word, even with --strict).
        const auto problem = [&](const std::string& what) { raw.stats.textureProblems.push_back({path + ": " + what, material.name}); };
        const bool known = tex >= 0 && tex < static_cast<int>(model.textures.size());
        if (tex != -1 && !known)  // -1: no texture
            problem("material " + std::to_string(index) + " uses texture " + std::to_string(tex) + ", which does not exist (" +
                    std::to_string(model.textures.size()) + " textures)");
        if (known) {
            const tinygltf::Texture& texture = model.textures[static_cast<size_t>(tex)];
            const int source = texture.source;
            const int sampler = texture.sampler;  // none: REPEAT (glTF 2.0 §3.8.4.6)
            if (sampler >= 0 && sampler < static_cast<int>(model.samplers.size())) {
                const tinygltf::Sampler& s = model.samplers[static_cast<size_t>(sampler)];
                material.uvPeriod[0] = uvPeriod(s.wrapS), material.uvPeriod[1] = uvPeriod(s.wrapT);
            }
            if (source >= 0 && source < static_cast<int>(model.images.size())) {
                const tinygltf::Image& img = model.images[static_cast<size_t>(source)];
                if (const auto failed = images.unusable.find(source); failed != images.unusable.end())
                    problem("image " + std::to_string(source) + " " + failed->second);
                else if (const auto file = images.written.find(source); file != images.written.end())
                    material.texturePath = file->second;
                else if (!img.image.empty() && img.width > 0 && img.height > 0 && img.component > 0) {
                    material.image = decodedImage(path, img, static_cast<size_t>(source));
                    const std::span<const uint8_t> bytes = embeddedImageBytes(model, img);
                    material.jpegQuality = jpegQuality(bytes), material.jpegChroma420 = jpegChroma420(bytes);
                }
                else if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0)
                    material.texturePath = imageFile(path, img.uri, options);
                else
                    problem("image " + std::to_string(source) + " has no data hlod can decode" +
                            (img.uri.empty() ? std::string() : " (a data: URI that does not decode)"));
            } else {
                std::string extensions;  // an image only an extension names (EXT_texture_webp, KHR_texture_basisu)
                for (const auto& [name, value] : texture.extensions) extensions += (extensions.empty() ? "; extensions: " : ", ") + name;
                problem("texture " + std::to_string(tex) + " has no image hlod can read (source " + std::to_string(source) + " of " +
                        std::to_string(model.images.size()) + " images" + extensions + ")");
            }
        }
        out.materialOfGltf.push_back(static_cast<uint32_t>(raw.materials.size()));
        raw.materials.push_back(material);
    }
    raw.materials.push_back({"default", "", nullptr});
    return out;
}

}  // namespace hlod
