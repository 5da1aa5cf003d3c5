// Test fixture (memory_source.h): chunks are filled with a byte pattern, decoding ignores them
// and returns placeholder meshes of the node's triangle counts.
#include "tests/support/memory_source.h"

#include <cstring>
#include <utility>

namespace hlod {
namespace {

class MemorySource final : public NodeSource {
public:
    MemorySource(Skeleton skeleton, uint32_t bytesPerTriangle)
        : skeleton_(std::move(skeleton)), bytesPerTriangle_(bytesPerTriangle) {}
    const Skeleton& skeleton() const override { return skeleton_; }
    std::string name() const override { return "memory"; }
    uint64_t nodeSize(uint32_t id) const override {
        return uint64_t(skeleton_.nodes[id].triangles()) * bytesPerTriangle_;
    }
    void readChunk(uint32_t id, uint64_t offset, std::span<uint8_t> out) const override {
        std::memset(out.data(), int((id + offset) & 0xFF), out.size());
    }
    DecodedNode decode(uint32_t id, std::span<const uint8_t>) const override {
        const Node& n = skeleton_.nodes[id];
        DecodedNode out;
        out.id = id;
        out.textures.push_back(Image{1, 1, 3, {128, 128, 128}});
        for (uint32_t triangles : {n.texturedTriangles, n.untexturedTriangles}) {
            MeshData m;
            m.positions.assign(9, 0.0f);
            m.indices.assign(size_t(triangles) * 3, 0);
            out.meshTexture.push_back(out.meshes.empty() ? 0 : -1);
            out.meshes.push_back(std::move(m));
        }
        return out;
    }
    uint64_t expectedBytes(uint32_t id) const override {
        return 3 + 2 * 9 * sizeof(float) + uint64_t(skeleton_.nodes[id].triangles()) * 12;
    }

private:
    Skeleton skeleton_;
    uint32_t bytesPerTriangle_;
};

}  // namespace

std::shared_ptr<const NodeSource> memorySource(Skeleton skeleton, uint32_t bytesPerTriangle) {
    return std::make_shared<MemorySource>(std::move(skeleton), bytesPerTriangle);
}

}  // namespace hlod
