// EXT_meshopt_compression, as gltfpack writes it (the extension's README, glTF 2.0 vendor
// extensions): buffer views coded by meshoptimizer's vertex and index codecs (Kapoulkine,
// meshoptimizer "Vertex/index buffer compression"), decoded here by meshoptimizer itself before
// any accessor is read. Two steps around tinygltf (read_gltf_load.cpp): meshoptPlan reads every
// compressed view's numbers from the JSON (exactly: tinygltf keeps extension numbers as `int`)
// and gives each fallback buffer (a byteLength without data, which tinygltf cannot load) three
// bytes; decodeMeshoptViews then decodes each view into a buffer of its own.
#include "pipeline/read_gltf_load.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

namespace hlod {
namespace {

using nlohmann::json;

constexpr const char* kMeshopt = "EXT_meshopt_compression";

// Member `key` of `object` as an unsigned integer up to `high`, or `fallback` when absent.
uint64_t integer(const json& object, const char* key, uint64_t fallback, uint64_t high, const std::string& what) {
    const auto it = object.find(key);
    if (it == object.end()) return fallback;
    const double x = it->is_number() ? it->get<double>() : -1;
    if (!(x >= 0 && x <= static_cast<double>(high) && x == std::floor(x)))
        throw InputError(what + " " + key + " is not an integer from 0 to " + std::to_string(high));
    return it->is_number_unsigned() ? it->get<uint64_t>() : static_cast<uint64_t>(x);
}

std::string text(const json& object, const char* key, const std::string& fallback, const std::string& what) {
    const auto it = object.find(key);
    if (it == object.end()) return fallback;
    if (!it->is_string()) throw InputError(what + " " + key + " is not a string");
    return it->get<std::string>();
}

const json* extensionOf(const json& object) {
    if (!object.is_object() || !object.contains("extensions") || !object["extensions"].is_object()) return nullptr;
    const auto it = object["extensions"].find(kMeshopt);
    return it == object["extensions"].end() ? nullptr : &*it;
}

// One compressed view's numbers, checked against each other and against the parent view.
MeshoptView viewOf(size_t index, const json& parent, const json& e, size_t fileBuffers, const std::string& what) {
    if (!e.is_object()) throw InputError(what + " is not an object");
    MeshoptView v;
    v.index = index;
    v.buffer = integer(e, "buffer", UINT64_MAX, fileBuffers ? fileBuffers - 1 : 0, what);
    v.offset = integer(e, "byteOffset", 0, UINT32_MAX, what), v.length = integer(e, "byteLength", UINT64_MAX, UINT32_MAX, what);
    v.stride = integer(e, "byteStride", UINT64_MAX, 256, what), v.count = integer(e, "count", UINT64_MAX, UINT32_MAX, what);
    v.mode = text(e, "mode", "", what), v.filter = text(e, "filter", "NONE", what);
    if (v.buffer == UINT64_MAX || fileBuffers == 0) throw InputError(what + " names no buffer of the file");
    if (v.length == UINT64_MAX || v.stride == UINT64_MAX || v.count == UINT64_MAX) throw InputError(what + " lacks byteLength, byteStride or count");
    const bool attributes = v.mode == "ATTRIBUTES";
    if (!attributes && v.mode != "TRIANGLES" && v.mode != "INDICES")
        throw InputError(what + " mode '" + v.mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
    if (attributes ? v.stride == 0 || v.stride % 4 != 0 : v.stride != 2 && v.stride != 4)
        throw InputError(what + " byteStride " + std::to_string(v.stride) + " does not suit mode " + v.mode);
    if (v.mode == "TRIANGLES" && v.count % 3 != 0) throw InputError(what + " codes " + std::to_string(v.count) + " indices, not whole triangles");
    const bool filterFits = v.filter == "NONE" || (attributes && ((v.filter == "OCTAHEDRAL" && (v.stride == 4 || v.stride == 8)) ||
                                                                  (v.filter == "QUATERNION" && v.stride == 8) || v.filter == "EXPONENTIAL"));
    if (!filterFits)
        throw InputError(what + " filter '" + v.filter + "' does not suit mode " + v.mode + " and byteStride " + std::to_string(v.stride));
    const uint64_t parentStride = integer(parent, "byteStride", 0, 256, what + " (its view)");
    if (parentStride != 0 && parentStride != v.stride)
        throw InputError(what + " byteStride " + std::to_string(v.stride) + " differs from its view's " + std::to_string(parentStride));
    // Every codec spends at least one byte per 64 decoded bytes (the vertex codec's constant stream;
    // the index codecs one per triangle or index): a larger claim is not data.
    if (v.count * v.stride > 64 * v.length + 4096)
        throw InputError(what + " claims " + std::to_string(v.count * v.stride) + " bytes from " + std::to_string(v.length));
    return v;
}

// A buffer without data to fill: tagged `fallback`, or (the tag is optional) without a uri and
// read by compressed views only; never a GLB's buffer 0, its BIN chunk.
std::set<size_t> fallbackBuffers(const json& doc, bool binary) {
    const json& buffers = doc["buffers"];
    std::set<size_t> out;
    std::vector<int> readers(buffers.size(), 0), compressedReaders(buffers.size(), 0);
    for (const json& view : doc.value("bufferViews", json::array()))
        if (view.is_object() && view.contains("buffer") && view["buffer"].is_number_unsigned() && view["buffer"].get<size_t>() < buffers.size()) {
            ++readers[view["buffer"].get<size_t>()];
            compressedReaders[view["buffer"].get<size_t>()] += extensionOf(view) != nullptr;
        }
    for (size_t b = binary ? 1 : 0; b < buffers.size(); ++b) {
        if (!buffers[b].is_object() || buffers[b].contains("uri")) continue;
        const json* tag = extensionOf(buffers[b]);
        const bool tagged = tag && tag->is_object() && tag->contains("fallback") && (*tag)["fallback"] == true;
        if (tagged || (readers[b] > 0 && readers[b] == compressedReaders[b])) out.insert(b);
    }
    return out;
}

// The images and Draco primitives a fallback buffer would feed: tinygltf reads them straight
// from its bytes, which are three.
void refuseDirectReaders(const json& doc, const std::set<size_t>& fallbacks, const std::string& path) {
    const json views = doc.value("bufferViews", json::array());
    const auto onFallback = [&](const json& index) {
        return index.is_number_unsigned() && index.get<size_t>() < views.size() && views[index.get<size_t>()].is_object() &&
               fallbacks.count(views[index.get<size_t>()].value("buffer", size_t(0)));
    };
    const json images = doc.value("images", json::array());
    for (size_t i = 0; i < images.size(); ++i)
        if (images[i].is_object() && images[i].contains("bufferView") && onFallback(images[i]["bufferView"]))
            throw InputError(path + ": image " + std::to_string(i) + " lies in a compressed buffer view (not supported)");
    for (const json& mesh : doc.value("meshes", json::array()))
        for (const json& prim : mesh.is_object() ? mesh.value("primitives", json::array()) : json::array()) {
            const json draco = prim.is_object() ? prim.value("extensions", json::object()).value("KHR_draco_mesh_compression", json::object())
                                                : json::object();
            if (draco.is_object() && draco.contains("bufferView") && onFallback(draco["bufferView"]))
                throw InputError(path + ": a Draco primitive lies in a compressed buffer view (not supported)");
        }
}

MeshoptFile plan(const uint8_t* bytes, size_t size, bool binary, const std::string& path) {
    GlbChunks chunks{{bytes, size}, {}};
    if (binary && !splitGlb(bytes, size, chunks)) return {};
    if (std::string_view(reinterpret_cast<const char*>(chunks.json.data()), chunks.json.size()).find(kMeshopt) == std::string_view::npos)
        return {};
    json doc = json::parse(chunks.json.begin(), chunks.json.end(), nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("buffers") || !doc["buffers"].is_array()) return {};
    MeshoptFile file;
    file.fileBuffers = doc["buffers"].size();
    const json views = doc.value("bufferViews", json::array());
    uint64_t claimed = 0, budget = 0;
    std::set<uint64_t> sources;
    for (size_t i = 0; i < views.size(); ++i)
        if (const json* e = extensionOf(views[i])) {
            file.views.push_back(viewOf(i, views[i], *e, file.fileBuffers, path + ": buffer view " + std::to_string(i) + ": " + kMeshopt));
            claimed += file.views.back().count * file.views.back().stride, budget += 4096;
            sources.insert(file.views.back().buffer);
        }
    // Views may share compressed bytes: the whole file's claim is bounded by its source buffers' bytes.
    for (const uint64_t b : sources) budget += 64 * integer(doc["buffers"][b], "byteLength", 0, UINT32_MAX, path + ": buffer " + std::to_string(b));
    if (claimed > budget) throw InputError(path + ": " + kMeshopt + " views claim " + std::to_string(claimed) + " bytes in all, more than their buffers hold");
    const std::set<size_t> fallbacks = fallbackBuffers(doc, binary);
    refuseDirectReaders(doc, fallbacks, path);
    for (const MeshoptView& v : file.views)
        if (fallbacks.count(v.buffer)) throw InputError(path + ": buffer view " + std::to_string(v.index) + ": its compressed data is in a fallback buffer");
    if (fallbacks.empty()) return file;
    for (size_t b : fallbacks) doc["buffers"][b]["uri"] = "data:application/octet-stream;base64,AAAA", doc["buffers"][b]["byteLength"] = 3;
    const std::string out = doc.dump();
    file.bytes = binary ? assembleGlb(out, chunks.bin) : std::vector<uint8_t>(out.begin(), out.end());
    return file;
}

}  // namespace

MeshoptFile meshoptPlan(const uint8_t* bytes, size_t size, bool binary, const std::string& path) {
    try {
        return plan(bytes, size, binary, path);
    } catch (const json::exception&) {  // a member of an unexpected type: tinygltf reports the file
        return {};
    }
}

void decodeMeshoptViews(tinygltf::Model& model, const MeshoptFile& file, const std::string& path) {
    for (const MeshoptView& v : file.views) {
        const std::string what = path + ": buffer view " + std::to_string(v.index) + ": " + kMeshopt;
        if (v.index >= model.bufferViews.size() || v.buffer >= file.fileBuffers || v.buffer >= model.buffers.size())
            throw InputError(what + " names no buffer of the file");
        const std::vector<unsigned char>& source = model.buffers[v.buffer].data;
        if (v.offset > source.size() || v.length > source.size() - v.offset) throw InputError(what + " runs past its buffer (truncated or corrupt file)");
        tinygltf::Buffer decoded;
        decoded.data.resize(v.count * v.stride);
        const unsigned char* in = source.data() + v.offset;
        const int rc = v.mode == "ATTRIBUTES" ? meshopt_decodeVertexBuffer(decoded.data.data(), v.count, v.stride, in, v.length)
                       : v.mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(decoded.data.data(), v.count, v.stride, in, v.length)
                                               : meshopt_decodeIndexSequence(decoded.data.data(), v.count, v.stride, in, v.length);
        if (rc != 0) throw InputError(what + " does not decode (meshoptimizer error " + std::to_string(rc) + ")");
        if (v.filter == "OCTAHEDRAL") meshopt_decodeFilterOct(decoded.data.data(), v.count, v.stride);
        if (v.filter == "QUATERNION") meshopt_decodeFilterQuat(decoded.data.data(), v.count, v.stride);
        if (v.filter == "EXPONENTIAL") meshopt_decodeFilterExp(decoded.data.data(), v.count, v.stride);
        tinygltf::BufferView& view = model.bufferViews[v.index];
        view.byteStride = v.mode == "ATTRIBUTES" ? v.stride : 0;
        view.buffer = static_cast<int>(model.buffers.size()), view.byteOffset = 0, view.byteLength = decoded.data.size();
        model.buffers.push_back(std::move(decoded));
    }
}

}  // namespace hlod
