// texture.cpp: the original triangles of one material by UV chart, each with only the texels it
// covers, for bakeTexture (bake.cpp): a node's original triangles may use charts spread over a
// whole atlas, and one rectangle around them all would hold most of it (issue #14).
// reachedBlocks: the source blocks a node atlas holds (texture.cpp).
// texture_fidelity.cpp: a stored (decoded) node texture against the source texels it copies.
#pragma once

#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"

#include <climits>

namespace hlod {

// The UV charts of `mesh`: triangles connected through shared (welded, so same-UV) vertices;
// returns the chart of every vertex, `count` the number of charts.
std::vector<uint32_t> uvCharts(const MeshData& mesh, uint32_t& count);

// wrap_uvs.cpp: each chart of a textured material whose UVs lie in another period of the texture
// than [0, 1] (Material::uvPeriod) moved into [0, 1] by whole periods (mirrored in a mirrored
// period): the same texels. Returns the charts left as they are because they straddle a period's edge.
uint32_t wrapUvCharts(Piece& piece, const std::vector<Material>& materials);

struct TexturedChart {
    MeshData mesh;  // one chart's triangles, UVs rewritten onto `texels`
    Image texels;   // BlockTextures::region of the chart
};
// `mesh` (one material's triangles) split into its charts (connected triangles), each with
// BlockTextures::region(material, factor); empty when the material is untextured.
std::vector<TexturedChart> textureCharts(BlockTextures& textures, uint32_t material, double factor, const MeshData& mesh);

// Squared error of a stored texture against its source over the texels triangles use (issue #14's
// texture fidelity): every texel of `stored` whose centre a triangle of `storedMesh` covers (each
// texel once) against the source texel under the same point of the same triangle in `sourceMesh`
// (the same triangles and indices, the UVs before atlasTexture rewrote them). `samples` =
// texels x channels (TextureFidelity, pipeline.h).
TextureFidelity textureFidelity(const MeshData& sourceMesh, const TextureSource& source, const MeshData& storedMesh, const Image& stored);

// The blocks (8 x 8, or 16 x 16 for 4:2:0) of a node's scaled texture (columns per row) that one group of charts reaches:
// charts that reach a common block are one group, so a block is stored once per node (texture.cpp).
struct BlockGroup {
    int bx0 = INT_MAX, by0 = INT_MAX, bx1 = -1, by1 = -1;  // inclusive
    std::vector<uint64_t> blocks;                           // by * columns + bx, in that order
};
// Every block of a width x height texture that some triangle of `mesh` (texels: UVs x the size, as
// given; clamped to the texture only to find candidate blocks, and for a triangle wholly outside)
// comes within 2 texels of (a bilinear tap's reach plus half a texel), grouped by the charts
// reaching it (`chart`: each vertex's, of `charts`); `groupOfChart` gets each chart's group
// (kNone: it reaches none). Groups are numbered in block order. UVs outside [0, 1] (glTF's REPEAT)
// are not reproduced: their translated UVs point beyond the group's blocks. Found on a grid of
// the blocks' box up to `gridBlocks` blocks (a 4K or 8K source always), beyond on a sorted list
// of the blocks reached where that is smaller: the same result (texture.cpp).
inline constexpr size_t kGridBlocks = size_t(1) << 20;  // a grid of at most 4 MiB
std::vector<BlockGroup> reachedBlocks(const MeshData& mesh, const std::vector<uint32_t>& chart, uint32_t charts, uint32_t width,
                                      uint32_t height, std::vector<uint32_t>& groupOfChart, size_t gridBlocks = kGridBlocks,
                                      int block = 8);

}  // namespace hlod
