// DecodedNode (player/renderer.h): CPU bytes held by a decoded node, the "real bytes" that
// the memory budget of thesis §4.3 is checked against.
#include "player/renderer.h"

namespace hlod {

uint64_t DecodedNode::bytes() const {
    uint64_t total = 0;
    for (const MeshData& m : meshes)
        total += m.positions.size() * sizeof(float) + m.texcoords.size() * sizeof(float) +
                 m.normals.size() * sizeof(float) + m.colors.size() + m.indices.size() * sizeof(uint32_t);
    for (const Image& image : textures) total += image.pixels.size();
    return total;
}

}  // namespace hlod
