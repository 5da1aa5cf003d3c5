// The HLOD recursion of thesis §3.2 for one block, breadth-first, on the block welded by
// position (weld.cpp):
//   simplification_hlod0 = numTriangles_b / c_desiredTris,
//   simplification_hlod(i+1) = simplification_hlod(i) / c_levelFactor,
// each node simplifying the piece's ORIGINAL triangles by its factor as one mesh (simplify.cpp),
// then dividing the piece
// into c_levelFactor children by c_levelFactor - 1 plane cuts (cut.cpp), "until the factor
// becomes less than 1". Leaves keep the original triangles; which node is a leaf is the
// --leaf-rule (tree_rules.h, pipeline/TREE.md): below-one (default) divides every node whose
// factor is > 1, so leaves have a factor in (1/c_levelFactor, 1]; stop-before divides a node only
// when its children's factor would still be >= 1, so leaves have a factor in [1, c_levelFactor)
// (or the block's own, when it is below 1). Textures are cropped and downsampled by the same
// factor (texture.cpp, leaves keep the source's) while the simplification keeps the source's
// UV seams; a node simplified as geometry only gets a baked texture. The geometric error is the
// two-sided distance to the original piece (error.cpp). All nodes are encoded on
// one position lattice (DracoOptions::positionStep, by default the block root's), so the
// borders the cuts made identical stay identical after quantization.
#include "pipeline/pipeline.h"
#include "pipeline/texture_charts.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace hlod {
namespace {

// The smallest hole the geometric error must see, as a fraction of the node's extent (issue #16).
constexpr double kMeasuredHole = 10;
// Smallest baked atlas: 64 x 64 texels (a coarse node of a small piece would otherwise get a few texels).
constexpr uint64_t kMinBakeTexels = 64 * 64;

struct Pending {
    Piece piece;
    double factor;
    uint32_t level;
    uint32_t parentLocal;
};

// Source texels the triangles of `mesh` cover in `texture` (the area of their UV triangles).
double usedTexels(const MeshData& mesh, const Image& texture) {
    double area = 0;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const float* a = &mesh.texcoords[2 * mesh.indices[3 * t]];
        const float* b = &mesh.texcoords[2 * mesh.indices[3 * t + 1]];
        const float* c = &mesh.texcoords[2 * mesh.indices[3 * t + 2]];
        area += 0.5 * std::abs(double(b[0] - a[0]) * (c[1] - a[1]) - double(c[0] - a[0]) * (b[1] - a[1]));
    }
    return area * texture.width * texture.height;
}

// A node simplified as geometry only (simplify.cpp): a new texture baked from the piece's
// original triangles and their textures downsampled for the level (bake.cpp; pipeline/BAKE.md
// "Integration": ~one source texel per baked texel, so its sub-samples do not alias). texelBudget
// is the texels those triangles use in the downsampled textures, i.e. the source texels divided
// by the node's factor (thesis §3.2: texture "down-sampled by this simplification factor", as
// the cropped atlases of the other nodes are), at least kMinBakeTexels. An untextured piece is
// not baked (image empty): its node stays untextured.
BakedTexture bakeNode(const MeshData& simplified, const Piece& piece, double factor, BlockTextures& textures) {
    std::vector<TexturedChart> original;  // by material and UV chart, each with the texels it covers
    for (SubMesh& part : splitByMaterial(piece)) {
        std::vector<TexturedChart> charts;
        if (!part.mesh.texcoords.empty()) charts = textureCharts(textures, part.material, factor, part.mesh);
        if (charts.empty()) original.push_back({std::move(part.mesh), {}});
        for (TexturedChart& c : charts) original.push_back(std::move(c));
    }
    std::vector<BakeSource> sources;
    double texels = 0;
    for (const TexturedChart& c : original) {
        const Image* texture = c.texels.width > 0 ? &c.texels : nullptr;
        if (texture) texels += usedTexels(c.mesh, *texture);
        sources.push_back({&c.mesh, texture});
    }
    if (texels <= 0) return {};
    return bakeTexture(simplified, sources, std::max<uint64_t>(kMinBakeTexels, static_cast<uint64_t>(texels)));
}

}  // namespace

BlockStats buildBlock(const Piece& block, const std::vector<Material>& materials, uint32_t blockIndex,
                      const BuildOptions& blockOptions, Progress* progress, const std::function<void(NodeRecord&&)>& emit) {
    BuildOptions options = blockOptions;  // every node of the block on one position lattice
    if (options.draco.positionStep <= 0)
        options.draco.positionStep = positionLatticeStep(pieceBounds(block.mesh), options.draco.positionBits);
    const Constants& c = options.constants;
    const uint32_t levelFactor = static_cast<uint32_t>(c.levelFactor);
    BlockStats stats;
    stats.inputTriangles = block.mesh.triangleCount();
    BlockTextures textures(materials, options.textures, options.strict, stats.textureProblems, progress);
    std::deque<Pending> queue;
    Piece welded = weldPiece(block, options.draco.positionStep / 2);  // weld.cpp: chunk borders become interior
    const double rootFactor = static_cast<double>(welded.mesh.triangleCount()) / c.desiredTris;  // §3.2 hlod0
    queue.push_back({std::move(welded), rootFactor, 0, kNone});
    std::vector<uint32_t> parentOf;
    while (!queue.empty()) {
        Pending p = std::move(queue.front());
        queue.pop_front();
        const bool leaf = isLeaf(p.factor, c.levelFactor, options.leafRule);
        const SimplifiedNode simplified = leaf ? SimplifiedNode{p.piece, false} : simplifyNode(p.piece, p.factor, options.simplifier);
        std::vector<SubMesh> parts = splitByMaterial(simplified.piece);
        const Box3f bounds = pieceBounds(p.piece.mesh);
        const double extent = std::max({bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y, bounds.max.z - bounds.min.z});
        // Sample spacing: a hole of 1 / kMeasuredHole of the node's extent holds samples (error.cpp).
        const SurfaceError error = leaf ? SurfaceError{} : surfaceError(parts, {SubMesh{0, p.piece.mesh, {}}}, extent / (2 * kMeasuredHole));
        const double textureFactor = leaf ? 1.0 : p.factor;  // a leaf keeps the source's texels
        std::vector<Image> images(parts.size());
        double psnr = 0;
        if (simplified.geometryOnly) {
            if (BakedTexture baked = bakeNode(parts.at(0).mesh, p.piece, p.factor, textures); baked.image.width > 0) {
                parts[0].mesh = std::move(baked.mesh), images[0] = std::move(baked.image), psnr = baked.psnr;
            }
        } else {
            for (size_t i = 0; i < parts.size(); ++i) images[i] = textures.atlas(parts[i].material, textureFactor, parts[i].mesh);
        }
        emit(packNode(parts, images, bounds, p.parentLocal, p.level, blockIndex, error.max, options));
        if (stats.nodesPerLevel.size() <= p.level) stats.nodesPerLevel.resize(p.level + 1);
        ++stats.nodesPerLevel[p.level];
        if (progress) progress->advance(p.piece.mesh.triangleCount());
        const uint32_t self = static_cast<uint32_t>(parentOf.size());
        parentOf.push_back(p.parentLocal);
        stats.geometricErrors.push_back(static_cast<float>(error.max));
        stats.measured.push_back(error);
        stats.baked.push_back(simplified.geometryOnly);
        stats.bakePsnr.push_back(static_cast<float>(psnr));
        stats.levels.push_back(p.level);
        uint64_t triangles = 0, texels = 0;
        for (const SubMesh& part : parts) triangles += part.mesh.triangleCount();
        for (const Image& image : images) texels += uint64_t(image.width) * image.height;
        stats.triangles.push_back(triangles);
        stats.texels.push_back(texels);
        if (leaf) continue;
        for (Piece& child : dividePiece(p.piece, levelFactor, options.planes))  // §3.2: simplification_hlod(i+1)
            queue.push_back({std::move(child), p.factor / c.levelFactor, p.level + 1, self});
    }
    // A node's error bounds its whole subtree's: a child's measure can exceed its parent's.
    for (size_t i = parentOf.size(); i-- > 1;)
        stats.geometricErrors[parentOf[i]] = std::max(stats.geometricErrors[parentOf[i]], stats.geometricErrors[i]);
    return stats;
}

}  // namespace hlod
