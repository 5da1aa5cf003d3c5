// EXT_meshopt_compression, as gltfpack writes it (the extension's README, glTF 2.0 vendor
// extensions): buffer views coded by meshoptimizer's vertex and index codecs (Kapoulkine,
// meshoptimizer "Vertex/index buffer compression"), decoded here by meshoptimizer itself before
// any accessor is read. Two steps around tinygltf (read_gltf_load.cpp): a file's fallback buffers
// (declared with a byteLength but no data) are given three bytes so that tinygltf loads the file;
// then each compressed view is decoded into a buffer of its own and the view pointed at it.
#include "pipeline/read_gltf_load.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>

namespace hlod {
namespace {

using nlohmann::json;

constexpr const char* kMeshopt = "EXT_meshopt_compression";

// A member of the view's extension object as an unsigned integer up to `high`, or `fallback`
// when absent; InputError when it is anything else.
uint64_t integer(const tinygltf::Value& object, const char* key, uint64_t fallback, uint64_t high, const std::string& what) {
    if (!object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    const double x = v.IsNumber() ? v.GetNumberAsDouble() : -1;
    if (!(x >= 0 && x <= static_cast<double>(high) && x == std::floor(x)))
        throw InputError(what + " " + key + " is not an integer from 0 to " + std::to_string(high));
    return static_cast<uint64_t>(x);
}

std::string text(const tinygltf::Value& object, const char* key, const std::string& fallback, const std::string& what) {
    if (!object.Has(key)) return fallback;
    if (!object.Get(key).IsString()) throw InputError(what + " " + key + " is not a string");
    return object.Get(key).Get<std::string>();
}

// One compressed view decoded: `count` elements of `stride` bytes.
std::vector<unsigned char> decoded(const tinygltf::Value& e, const std::vector<unsigned char>& source, const std::string& what) {
    const uint64_t offset = integer(e, "byteOffset", 0, UINT32_MAX, what), length = integer(e, "byteLength", UINT64_MAX, UINT32_MAX, what);
    const uint64_t stride = integer(e, "byteStride", UINT64_MAX, 256, what), count = integer(e, "count", UINT64_MAX, UINT32_MAX, what);
    const std::string mode = text(e, "mode", "", what), filter = text(e, "filter", "NONE", what);
    if (length == UINT64_MAX || stride == UINT64_MAX || count == UINT64_MAX) throw InputError(what + " lacks byteLength, byteStride or count");
    if (offset > source.size() || length > source.size() - offset) throw InputError(what + " runs past its buffer (truncated or corrupt file)");
    const bool attributes = mode == "ATTRIBUTES", triangles = mode == "TRIANGLES", indices = mode == "INDICES";
    if (!attributes && !triangles && !indices) throw InputError(what + " mode '" + mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
    if (attributes ? stride == 0 || stride % 4 != 0 : stride != 2 && stride != 4)
        throw InputError(what + " byteStride " + std::to_string(stride) + " does not suit mode " + mode);
    if (triangles && count % 3 != 0) throw InputError(what + " codes " + std::to_string(count) + " indices, not whole triangles");
    // Every codec spends at least one byte per 64 decoded bytes: a larger claim is not data.
    if (count * stride > 64 * length + 4096) throw InputError(what + " claims " + std::to_string(count * stride) + " bytes from " + std::to_string(length));
    std::vector<unsigned char> out(count * stride);
    const unsigned char* in = source.data() + offset;
    const int rc = attributes ? meshopt_decodeVertexBuffer(out.data(), count, stride, in, length)
                   : triangles ? meshopt_decodeIndexBuffer(out.data(), count, stride, in, length)
                               : meshopt_decodeIndexSequence(out.data(), count, stride, in, length);
    if (rc != 0) throw InputError(what + " does not decode (meshoptimizer error " + std::to_string(rc) + ")");
    if (filter == "OCTAHEDRAL" && attributes && (stride == 4 || stride == 8)) meshopt_decodeFilterOct(out.data(), count, stride);
    else if (filter == "QUATERNION" && attributes && stride == 8) meshopt_decodeFilterQuat(out.data(), count, stride);
    else if (filter == "EXPONENTIAL" && attributes) meshopt_decodeFilterExp(out.data(), count, stride);
    else if (filter != "NONE") throw InputError(what + " filter '" + filter + "' does not suit mode " + mode + " and byteStride " + std::to_string(stride));
    return out;
}

}  // namespace

std::vector<uint8_t> withMeshoptFallbacksFilled(const uint8_t* bytes, size_t size, bool binary) {
    GlbChunks chunks{{bytes, size}, {}};
    if (binary && !splitGlb(bytes, size, chunks)) return {};
    if (std::string_view(reinterpret_cast<const char*>(chunks.json.data()), chunks.json.size()).find(kMeshopt) == std::string_view::npos)
        return {};
    json doc = json::parse(chunks.json.begin(), chunks.json.end(), nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("buffers") || !doc["buffers"].is_array()) return {};
    bool filled = false;
    for (json& buffer : doc["buffers"]) {
        const bool fallback = buffer.is_object() && !buffer.contains("uri") && buffer.contains("extensions") &&
                              buffer["extensions"].is_object() && buffer["extensions"].contains(kMeshopt) &&
                              buffer["extensions"][kMeshopt].is_object() && buffer["extensions"][kMeshopt].value("fallback", false) == true;
        if (!fallback || (binary && &buffer == &doc["buffers"][0])) continue;  // a GLB's buffer 0 is its BIN chunk
        buffer["uri"] = "data:application/octet-stream;base64,AAAA", buffer["byteLength"] = 3;
        filled = true;
    }
    if (!filled) return {};
    const std::string out = doc.dump();
    return binary ? assembleGlb(out, chunks.bin) : std::vector<uint8_t>(out.begin(), out.end());
}

void decodeMeshoptViews(tinygltf::Model& model, const std::string& path) {
    for (size_t v = 0; v < model.bufferViews.size(); ++v) {
        tinygltf::BufferView& view = model.bufferViews[v];
        const auto it = view.extensions.find(kMeshopt);
        if (it == view.extensions.end()) continue;
        const std::string what = path + ": buffer view " + std::to_string(v) + ": " + kMeshopt;
        if (!it->second.IsObject()) throw InputError(what + " is not an object");
        const uint64_t source = model.buffers.empty() ? UINT64_MAX : integer(it->second, "buffer", UINT64_MAX, model.buffers.size() - 1, what);
        if (source == UINT64_MAX) throw InputError(what + " names no buffer");
        tinygltf::Buffer buffer;
        buffer.data = decoded(it->second, model.buffers[source].data, what);
        view.byteStride = it->second.Get("mode").Get<std::string>() == "ATTRIBUTES" ? it->second.Get("byteStride").GetNumberAsInt() : 0;
        view.buffer = static_cast<int>(model.buffers.size()), view.byteOffset = 0, view.byteLength = buffer.data.size();
        model.buffers.push_back(std::move(buffer));
    }
}

}  // namespace hlod
