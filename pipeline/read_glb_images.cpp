// A GLB's embedded atlases taken out before tinygltf copies its BIN chunk (read_gltf_load.h,
// glbWithoutImages). Photogrammetry tools export one GLB whose BIN chunk is mostly JPEG atlases;
// tinygltf copies a GLB's whole BIN chunk into its buffer, so without this the encoded atlases
// would sit in memory beside the mapped file. Container layout: glTF 2.0 §4.4 (GLB: 12-byte
// header, a JSON chunk, an optional BIN chunk, each chunk 4-byte aligned).
#include "pipeline/read_gltf_load.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <set>

namespace hlod {
namespace {

using nlohmann::json;

constexpr uint32_t kMagic = 0x46546C67, kJson = 0x4E4F534A, kBin = 0x004E4942;  // "glTF", "JSON", "BIN\0"

uint32_t word(const uint8_t* p) {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

void putWord(std::vector<uint8_t>& out, uint32_t v) {
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    out.insert(out.end(), p, p + 4);
}


// The buffer views some accessor or Draco-compressed primitive reads: never taken out.
std::set<size_t> viewsReadAsData(const json& doc) {
    std::set<size_t> used;
    for (const json& a : doc.value("accessors", json::array()))
        if (a.contains("bufferView") && a["bufferView"].is_number_unsigned()) used.insert(a["bufferView"].get<size_t>());
    for (const json& mesh : doc.value("meshes", json::array()))
        for (const json& prim : mesh.value("primitives", json::array())) {
            const json draco = prim.value("extensions", json::object()).value("KHR_draco_mesh_compression", json::object());
            if (draco.contains("bufferView") && draco["bufferView"].is_number_unsigned()) used.insert(draco["bufferView"].get<size_t>());
        }
    return used;
}

std::vector<uint8_t> rebuilt(const MappedFile& file, EmbeddedImages& images) {
    const uint8_t* glb = file.data;
    GlbChunks chunks;
    if (file.size < 28 || word(glb) != kMagic || word(glb + 4) != 2 || word(glb + 8) > file.size) return {};
    if (!splitGlb(glb, file.size, chunks) || chunks.bin.empty()) return {};
    const uint8_t* bin = chunks.bin.data();
    const size_t binLength = chunks.bin.size();
    json doc = json::parse(chunks.json.begin(), chunks.json.end(), nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("bufferViews") || !doc["bufferViews"].is_array()) return {};
    json& views = doc["bufferViews"];
    const std::set<size_t> data = viewsReadAsData(doc);
    // A view of the BIN chunk (buffer 0, which has no uri in a GLB) and its bytes [offset, offset + length).
    const auto inBin = [&](size_t v) { return views[v].is_object() && views[v].value("buffer", -1) == 0; };
    const auto range = [&](size_t v, size_t& offset, size_t& length) {
        const json& view = views[v];
        if (!inBin(v) || !view.contains("byteLength") || !view["byteLength"].is_number_unsigned()) return false;
        offset = view.value("byteOffset", size_t{0}), length = view["byteLength"].get<size_t>();
        return offset <= binLength && length <= binLength - offset;
    };
    std::set<size_t> taken;
    json imagesJson = doc.value("images", json::array());
    for (size_t i = 0; i < imagesJson.size(); ++i) {
        json& image = imagesJson[i];
        if (!image.contains("bufferView") || !image["bufferView"].is_number_unsigned()) continue;
        const size_t v = image["bufferView"].get<size_t>();
        size_t offset = 0, length = 0;
        if (v >= views.size() || data.count(v) || !range(v, offset, length) || !keepEncoded(static_cast<int>(i), bin + offset, length, images))
            continue;
        file.release(static_cast<size_t>(bin - glb) + offset, length);
        image.erase("bufferView"), image.erase("mimeType");
        image["uri"] = "hlod-glb-image-" + std::to_string(i);  // a placeholder tinygltf keeps (no external images)
        taken.insert(v);
    }
    if (taken.empty()) return {};
    doc["images"] = std::move(imagesJson);
    std::vector<uint8_t> compact;
    const auto keep = [&](json& owner, size_t offset, size_t length) {  // the bytes moved, owner's byteOffset with them
        while (compact.size() % 4) compact.push_back(0);
        owner["byteOffset"] = compact.size();
        compact.insert(compact.end(), bin + offset, bin + offset + length);
    };
    for (size_t v = 0; v < views.size(); ++v) {
        size_t offset = 0, length = 0;
        if (!taken.count(v) && inBin(v)) {
            if (!range(v, offset, length)) return {};  // tinygltf reports it
            keep(views[v], offset, length);
        }
        // A compressed view (EXT_meshopt_compression, gltfpack's) reads buffer 0 through its extension.
        if (!views[v].is_object() || !views[v].contains("extensions") || !views[v]["extensions"].is_object()) continue;
        const auto e = views[v]["extensions"].find("EXT_meshopt_compression");
        if (e == views[v]["extensions"].end() || !e->is_object() || e->value("buffer", -1) != 0) continue;
        offset = e->value("byteOffset", size_t{0}), length = e->value("byteLength", size_t{0});
        if (offset > binLength || length > binLength - offset) return {};  // decodeMeshoptViews reports it
        keep(*e, offset, length);
    }
    while (compact.size() % 4 || compact.empty()) compact.push_back(0);
    for (size_t v : taken) views[v]["byteOffset"] = 0, views[v]["byteLength"] = 1;  // unread now
    if (doc.contains("buffers") && doc["buffers"].is_array() && !doc["buffers"].empty()) doc["buffers"][0]["byteLength"] = compact.size();
    return assembleGlb(doc.dump(), compact);
}

// A JSON number member as a double (-1 when absent or not a number).
double number(const json& object, const char* key) {
    const auto it = object.find(key);
    return it != object.end() && it->is_number() ? it->get<double>() : -1;
}

}  // namespace

bool splitGlb(const uint8_t* bytes, size_t size, GlbChunks& out) {
    if (size < 20 || word(bytes + 8) > size) return false;
    size = word(bytes + 8);  // the header's length, as tinygltf reads it: bytes past it are not the file's
    if (size < 20) return false;
    const size_t jsonLength = word(bytes + 12);
    if (word(bytes + 16) != kJson || jsonLength > size - 20) return false;
    out.json = {bytes + 20, jsonLength}, out.bin = {};
    const uint8_t* chunk = bytes + 20 + jsonLength;
    const size_t rest = size - 20 - jsonLength;
    if (rest == 0) return true;
    // A second chunk as tinygltf requires it (a BIN chunk of 4 n bytes, n >= 1), its data inside the file.
    if (rest < 12 || word(chunk + 4) != kBin || word(chunk) < 4 || word(chunk) % 4 != 0 || word(chunk) > rest - 8) return false;
    out.bin = {chunk + 8, word(chunk)};
    return true;
}

std::vector<uint8_t> assembleGlb(std::string text, std::span<const uint8_t> bin) {
    while (text.size() % 4) text.push_back(' ');
    const size_t padded = (bin.size() + 3) / 4 * 4;
    std::vector<uint8_t> out;
    putWord(out, kMagic), putWord(out, 2), putWord(out, static_cast<uint32_t>(20 + text.size() + (bin.empty() ? 0 : 8 + padded)));
    putWord(out, static_cast<uint32_t>(text.size())), putWord(out, kJson);
    out.insert(out.end(), text.begin(), text.end());
    if (bin.empty()) return out;
    putWord(out, static_cast<uint32_t>(padded)), putWord(out, kBin);
    out.insert(out.end(), bin.begin(), bin.end());
    out.resize(out.size() + padded - bin.size(), 0);
    return out;
}

namespace {
// tinygltf reports a malformed GLB, except a BIN chunk that claims up to 8 bytes more than follow
// its header: it checks the length without the header, then reads past the file (a heap over-read
// under fuzz_glb, stop 40).
void refuseBinOverrun(const uint8_t* bytes, size_t size, const std::string& path) {
    if (size < 20 || word(bytes + 8) < 20) return;
    const size_t length = std::min<size_t>(word(bytes + 8), size), json = word(bytes + 12);
    if (json > length - 20 || length - 20 - json < 12) return;
    const size_t claimed = word(bytes + 20 + json), present = length - 28 - json;
    if (claimed > present && claimed <= present + 8)
        throw InputError(path + ": corrupt GLB (its BIN chunk claims " + std::to_string(claimed) + " bytes, " + std::to_string(present) +
                         " follow its header)");
}
}  // namespace

void checkGltfJson(const uint8_t* bytes, size_t size, bool binary, const std::string& path) {
    const uint8_t* text = bytes;
    size_t length = size;
    if (GlbChunks chunks; binary) {
        if (!splitGlb(bytes, size, chunks)) {
            refuseBinOverrun(bytes, size, path);
            return;  // tinygltf reports the rest
        }
        text = chunks.json.data(), length = chunks.json.size();
    }
    const json doc = json::parse(text, text + length, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return;
    const auto array = [&](const char* key) { const auto it = doc.find(key); return it != doc.end() && it->is_array() ? *it : json::array(); };
    for (const json& name : array("extensionsRequired"))
        if (name.is_string() && std::find(kReadExtensions.begin(), kReadExtensions.end(), name.get<std::string>()) == kReadExtensions.end()) {
            std::string read;
            for (const char* known : kReadExtensions) read += std::string(read.empty() ? "" : ", ") + known;
            throw InputError(path + ": requires glTF extension " + name.get<std::string>() + ", which hlod does not read (it reads " + read + ")");
        }
    const json images = array("images"), views = array("bufferViews"), buffers = array("buffers");
    // What tinygltf reads straight from a view's bytes without checking them: an image, a Draco primitive.
    const auto check = [&](const json& index, const std::string& what) {
        const double v = index.is_number() ? index.get<double>() : -1;
        if (v < 0 || v >= double(views.size()) || !views[size_t(v)].is_object()) return;
        const json& view = views[size_t(v)];
        const double b = number(view, "buffer");
        if (b < 0 || b >= double(buffers.size()) || !buffers[size_t(b)].is_object()) return;
        const double end = std::max(0.0, number(view, "byteOffset")) + number(view, "byteLength");
        if (end > number(buffers[size_t(b)], "byteLength"))
            throw InputError(path + ": " + what + ": buffer view " + std::to_string(size_t(v)) +
                             " runs past its buffer's byteLength (truncated or corrupt file)");
    };
    for (size_t i = 0; i < images.size(); ++i)
        if (images[i].is_object() && images[i].contains("bufferView")) check(images[i]["bufferView"], "image " + std::to_string(i));
    for (const json& mesh : array("meshes"))
        for (const json& prim : mesh.is_object() && mesh.contains("primitives") && mesh["primitives"].is_array() ? mesh["primitives"] : json::array())
            if (prim.is_object() && prim.contains("extensions") && prim["extensions"].is_object() &&
                prim["extensions"].contains("KHR_draco_mesh_compression") && prim["extensions"]["KHR_draco_mesh_compression"].is_object() &&
                prim["extensions"]["KHR_draco_mesh_compression"].contains("bufferView"))
                check(prim["extensions"]["KHR_draco_mesh_compression"]["bufferView"], "a Draco primitive");
}

std::vector<uint8_t> glbWithoutImages(const MappedFile& file, EmbeddedImages& images) {
    try {
        return rebuilt(file, images);
    } catch (const json::exception&) {  // a member of an unexpected type: tinygltf reports it
        return {};
    }
}

}  // namespace hlod
