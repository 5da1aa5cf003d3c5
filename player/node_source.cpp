// Node sources for the loading thread (thesis §4.3): chunked positioned reads of a node's data
// range, then verification (XXH3-64 per blob) and decoding (Draco geometry, JPEG/PNG textures
// through formats/codec.h) - all on the loading thread, never on the render thread.
#include "player/node_source.h"

#include "formats/codec.h"

#include <xxhash.h>

#include <unordered_map>

namespace hlod {
namespace {

class DatabaseSource final : public NodeSource {
public:
    explicit DatabaseSource(const Database& db) : db_(db) {}
    const Skeleton& skeleton() const override { return db_.skeleton(); }
    std::string name() const override { return db_.path(); }
    uint64_t nodeSize(uint32_t id) const override { return skeleton().nodes[id].dataSize; }

    void readChunk(uint32_t id, uint64_t offset, std::span<uint8_t> out) const override {
        db_.readRange(skeleton().nodes[id].dataOffset + offset, out);
    }

    DecodedNode decode(uint32_t id, std::span<const uint8_t> data) const override {
        const Node& node = skeleton().nodes[id];
        DecodedNode out;
        out.id = id;
        std::unordered_map<uint32_t, int32_t> textureSlot;  // global blob index -> textures[]
        for (uint32_t b = node.firstBlob; b < node.firstBlob + node.blobCount; ++b) {
            const BlobRef& blob = skeleton().blobs[b];
            std::span<const uint8_t> bytes = blobBytes(node, b, data);
            if (blob.kind == BlobKind::Texture) {
                textureSlot[b] = int32_t(out.textures.size());
                out.textures.push_back(decodeTexture(bytes, blob.codec, blobName(id, b)));
            }
        }
        for (uint32_t b = node.firstBlob; b < node.firstBlob + node.blobCount; ++b) {
            const BlobRef& blob = skeleton().blobs[b];
            if (blob.kind != BlobKind::Geometry) continue;
            out.meshes.push_back(decodeGeometry(blobBytes(node, b, data), blobName(id, b)));
            auto t = textureSlot.find(blob.texture);
            out.meshTexture.push_back(t == textureSlot.end() ? -1 : t->second);
        }
        return out;
    }

    uint64_t expectedBytes(uint32_t id) const override {
        const Node& node = skeleton().nodes[id];
        uint64_t total = 0;
        for (uint32_t b = node.firstBlob; b < node.firstBlob + node.blobCount; ++b) {
            const BlobRef& r = skeleton().blobs[b];
            if (r.kind == BlobKind::Texture) {
                total += uint64_t(r.width) * r.height * r.channels;
                continue;
            }
            uint64_t floats = 3 + (r.attributes & kAttrTexcoord ? 2 : 0) + (r.attributes & kAttrNormal ? 3 : 0);
            total += uint64_t(r.vertices) * (floats * 4 + (r.attributes & kAttrColor ? 4 : 0));
            total += uint64_t(r.triangles) * 12;
        }
        return total;
    }

private:
    const Database& db_;

    std::string blobName(uint32_t node, uint32_t blob) const {
        return db_.path() + " (node " + std::to_string(node) + ", blob " + std::to_string(blob) + ")";
    }

    std::span<const uint8_t> blobBytes(const Node& node, uint32_t b, std::span<const uint8_t> data) const {
        const BlobRef& blob = skeleton().blobs[b];
        if (blob.offset < node.dataOffset || blob.offset - node.dataOffset > data.size() ||
            blob.size > data.size() - (blob.offset - node.dataOffset))
            throw FormatError(blobName(node.id, b) + ": blob lies outside the node's data range");
        std::span<const uint8_t> bytes = data.subspan(blob.offset - node.dataOffset, blob.size);
        if (XXH3_64bits(bytes.data(), bytes.size()) != blob.checksum)
            throw FormatError(blobName(node.id, b) + ": checksum mismatch (corrupt data)");
        return bytes;
    }
};

}  // namespace

std::shared_ptr<const NodeSource> databaseSource(const Database& db) { return std::make_shared<DatabaseSource>(db); }

}  // namespace hlod
