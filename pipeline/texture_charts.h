// texture.cpp: the original triangles of one material by UV chart, each with only the texels it
// covers, for bakeTexture (bake.cpp): a node's original triangles may use charts spread over a
// whole atlas, and one rectangle around them all would hold most of it (issue #14).
// texture_fidelity.cpp: a stored (decoded) node texture against the source texels it copies.
#pragma once

#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"

namespace hlod {

// The UV charts of `mesh`: triangles connected through shared (welded, so same-UV) vertices;
// returns the chart of every vertex, `count` the number of charts.
std::vector<uint32_t> uvCharts(const MeshData& mesh, uint32_t& count);

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

}  // namespace hlod
