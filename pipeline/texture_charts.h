// texture.cpp: the original triangles of one material by UV chart, each with only the texels it
// covers, for bakeTexture (bake.cpp): a node's original triangles may use charts spread over a
// whole atlas, and one rectangle around them all would hold most of it (issue #14).
#pragma once

#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"

namespace hlod {

struct TexturedChart {
    MeshData mesh;  // one chart's triangles, UVs rewritten onto `texels`
    Image texels;   // BlockTextures::region of the chart
};
// `mesh` (one material's triangles) split into its charts (connected triangles), each with
// BlockTextures::region(material, factor); empty when the material is untextured.
std::vector<TexturedChart> textureCharts(BlockTextures& textures, uint32_t material, double factor, const MeshData& mesh);

}  // namespace hlod
