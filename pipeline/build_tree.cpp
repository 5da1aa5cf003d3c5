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
// --mode bottom-up (BuildMode, pipeline/BUILD_SPEED.md) keeps the same division, leaves,
// targets and textures, but simplifies each node from its children's simplified triangles
// instead of the original ones (bottomUp below): each input triangle is simplified about 1.33
// times instead of once per level. Its geometric error is by default an upper bound from the
// children (bottomUp), without a pass over the original triangles; --bottom-up-error exact
// measures against the original piece as top-down does; --bottom-up-error simplifier adds the
// simplifier's own error estimate to the children's, measuring no distance at all.
// --error-cap (errorCeiling below, pipeline/TREE.md): a node may stop short of its factor where
// reaching it would make it far coarser than a reference error.
#include "formats/layout.h"
#include "pipeline/blob_spill.h"
#include "pipeline/lattice_flattened.h"
#include "pipeline/pipeline.h"
#include "pipeline/tbb_sync.h"
#include "pipeline/texture_charts.h"

#include <meshoptimizer.h>

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>

namespace hlod {
namespace {

// Smallest baked atlas: 64 x 64 texels (a coarse node of a small piece would otherwise get a few texels).
constexpr uint64_t kMinBakeTexels = 64 * 64;
// Largest: a quarter of the area of the largest texture a blob may hold (layout::kMaxTextureSide
// squared), so the packed atlas's area does (uncapped until stop 47: ~4.3 G source texels under one
// baked node made an atlas the encoder refused, failing the build; a reading of the code, not run).
constexpr uint64_t kMaxBakeTexels = uint64_t(layout::kMaxTextureSide / 2) * (layout::kMaxTextureSide / 2);

struct Pending {
    Piece piece;
    double factor;
    uint32_t level;
    uint32_t parentLocal;
    Sides shared = kAllSides;  // the piece's sides another piece may share a border across
    double ceiling = HUGE_VAL;  // top-down: the error this node's simplification may reach (freeBorderCeiling, errorCeiling)
};

// --error-cap on (pipeline/TREE.md "Locked borders cost triangles, not accuracy"; errorCapped:
// the default but with --bottom-up-error simplifier): the error a node's simplification may reach
// (simplifyNode's ceiling). A node with shared sides, whose borders there stay whole, stops at
// kFreeBorderSlack x the error its piece reaches at the same factor with no border locked
// (freeBorderCeiling): top-down the block's root (one more simplification of the whole block),
// bottom-up every node (its input, the children's simplified triangles, is small) but one that
// simplifies the original triangles (its children are leaves) by at most c_levelFactor: its
// locked border is as fine as the rest, and the cap barely bound there (TREE.md "Stop 43"). A
// top-down child also stops at its parent's simplifier error. Never below the position lattice step:
// stored positions cannot tell smaller errors apart, and a flat piece's near-zero error would
// otherwise freeze it.
// kFreeBorderSlack: 1 kept the 1.6 M Lucy's hlod0 at 12.7 units (618 uncapped) for 26 % more
// triangles, but put 35 of the thesis city's 114 hlod0 nodes over 1.25 x c_desiredTris; 2 gives
// 31.2 for 10 % more and leaves the city's hlod0 on target (measured, TREE.md).
constexpr double kFreeBorderSlack = 2;
}  // namespace

bool errorCapped(const BuildOptions& o) {
    const bool speedMode = o.mode == BuildMode::BottomUp && o.bottomUpError == BottomUpError::Simplifier;
    return o.errorCap.value_or(!speedMode) && o.simplifier == Simplifier::Meshopt;
}

namespace {
double errorCeiling(double error, const BuildOptions& options) {
    return errorCapped(options) ? std::max(error, options.draco.positionStep) : HUGE_VAL;
}
double freeBorderCeiling(const Piece& piece, double factor, Sides shared, const BuildOptions& options) {
    if (!errorCapped(options) || shared == 0 || factor <= 1) return HUGE_VAL;
    return errorCeiling(kFreeBorderSlack * simplifyNode(piece, factor, options.simplifier, 0).error, options);
}

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
// the cropped atlases of the other nodes are), from kMinBakeTexels to kMaxBakeTexels. An untextured piece is
// not baked (image empty): its node stays untextured.
BakedTexture bakeNode(const MeshData& simplified, const Piece& piece, double factor, BlockTextures& textures) {
    std::vector<TexturedChart> original;  // by material and UV chart, each with the texels it covers
    for (SubMesh& part : splitByMaterial(piece, false)) {
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
    return bakeTexture(simplified, sources, std::clamp<uint64_t>(static_cast<uint64_t>(texels), kMinBakeTexels, kMaxBakeTexels));
}

// One node's output: its record (parentLocal set by the caller) and what BlockStats keeps of it.
struct NodeOut {
    NodeRecord record;
    SurfaceError error;
    bool baked = false;
    float psnr = 0;
    uint32_t level = 0;
    uint64_t triangles = 0, texels = 0;
    TextureFidelity fidelity;  // a leaf's, with options.leafPsnr
};

// A leaf's stored textures (its record's texture blobs, decoded: packNode writes one, before its
// geometry, for each part with an image) against the source texels its triangles cover;
// `sourceParts` are its sub-meshes with the source UVs (texture_fidelity.cpp).
TextureFidelity leafFidelity(const std::vector<SubMesh>& sourceParts, const std::vector<SubMesh>& parts, const std::vector<Image>& images,
                             const NodeRecord& record, BlockTextures& textures) {
    TextureFidelity sum;
    size_t blob = 0;
    for (size_t i = 0; i < parts.size(); ++i) {
        if (images[i].width == 0) continue;
        while (record.node.blobs.at(blob).info.kind != BlobKind::Texture) ++blob;
        const EncodedBlob& encoded = record.node.blobs[blob++];
        const Image stored = decodeTexture(encoded.bytes, encoded.info.codec, "leaf texture");
        const TextureFidelity f = textureFidelity(sourceParts[i].mesh, *textures.source(parts[i].material), parts[i].mesh, stored);
        sum.texels += f.texels, sum.samples += f.samples, sum.squaredError += f.squaredError;
    }
    return sum;
}

// Textures, geometric error and packing of a simplified node; the same in both modes. The error
// (error.cpp) is the two-sided distance to `measuredFrom` plus `inherited`, field by field:
// top-down, the node's ORIGINAL piece and nothing; bottom-up, by default, the surface the node was
// simplified from and its children's largest errors (bottomUp). Without `measuredFrom` it is
// `inherited` alone (bottomUp's BottomUpError::Simplifier).
NodeOut finishNode(const SimplifiedNode& simplified, const Piece& original, const MeshData* measuredFrom, const SurfaceError& inherited,
                   double factor, uint32_t level, bool leaf, uint32_t blockIndex, const BuildOptions& options, BlockTextures& textures) {
    std::vector<SubMesh> parts = splitByMaterial(simplified.piece, false);
    const Box3f bounds = pieceBounds(original.mesh);
    const double extent = std::max({bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y, bounds.max.z - bounds.min.z});
    NodeOut out;
    out.level = level;
    // Sample spacing: a hole of 1 / kMeasuredHole of the node's extent holds samples (error.cpp).
    if (!leaf) {
        if (measuredFrom) out.error = surfaceError(parts, *measuredFrom, extent / (2 * kMeasuredHole));
        out.error.oneSided += inherited.oneSided, out.error.max += inherited.max, out.error.mean += inherited.mean;
    }
    const double textureFactor = leaf ? 1.0 : factor;  // a leaf keeps the source's texels
    std::vector<Image> images(parts.size());
    if (simplified.geometryOnly) {
        if (BakedTexture baked = bakeNode(parts.at(0).mesh, original, factor, textures); baked.image.width > 0) {
            parts[0].mesh = std::move(baked.mesh), images[0] = std::move(baked.image), out.psnr = static_cast<float>(baked.psnr);
        }
    }
    const std::vector<SubMesh> sourceParts = leaf && options.leafPsnr ? parts : std::vector<SubMesh>{};
    // A baked atlas: the lowest quality of its sources', 4:4:4 unless --jpeg-chroma 4:2:0 (its charts
    // lie on 8 x 8 blocks, pack_charts.cpp); an atlas of source blocks: its source's (TEXTURE_SIZE.md).
    std::vector<JpegSettings> jpeg(parts.size(), {options.jpegQuality, options.jpegChroma == JpegChroma::Half});
    if (simplified.geometryOnly)
        for (uint32_t material : std::set<uint32_t>(original.materials.begin(), original.materials.end()))
            jpeg[0].quality = std::min(jpeg[0].quality, textures.jpegQuality(material, options.jpegQuality));
    else
        for (size_t i = 0; i < parts.size(); ++i) {
            jpeg[i] = {textures.jpegQuality(parts[i].material, options.jpegQuality), textures.chroma420(parts[i].material, options.jpegChroma)};
            images[i] = textures.atlas(parts[i].material, textureFactor, parts[i].mesh, jpeg[i].chroma420);
        }
    out.record = packNode(parts, images, jpeg, bounds, kNone, level, blockIndex, out.error.max, options);
    if (!sourceParts.empty()) out.fidelity = leafFidelity(sourceParts, parts, images, out.record, textures);
    out.baked = simplified.geometryOnly && images[0].width > 0;  // an untextured piece is simplified alone, not baked
    // The triangles as stored: Draco drops faces its quantization collapses (counted until stop 48).
    for (const EncodedBlob& blob : out.record.node.blobs)
        if (blob.info.kind == BlobKind::Geometry) out.triangles += blob.info.triangles;
    for (const Image& image : images) out.texels += uint64_t(image.width) * image.height;
    return out;
}

// Appends a node's figures to the block's, in emission order; returns its local index.
uint32_t recordNode(BlockStats& stats, std::vector<uint32_t>& parentOf, const NodeOut& out, uint32_t parentLocal) {
    if (stats.nodesPerLevel.size() <= out.level) stats.nodesPerLevel.resize(out.level + 1);
    ++stats.nodesPerLevel[out.level];
    parentOf.push_back(parentLocal);
    stats.geometricErrors.push_back(static_cast<float>(out.error.max));
    stats.measured.push_back(out.error);
    stats.baked.push_back(out.baked);
    stats.bakePsnr.push_back(out.psnr);
    stats.levels.push_back(out.level);
    stats.triangles.push_back(out.triangles);
    stats.texels.push_back(out.texels);
    stats.fidelity.push_back(out.fidelity);
    return static_cast<uint32_t>(parentOf.size() - 1);
}

// The pieces of `parts` as one welded piece; geometry only (no texture coordinates, material 0) when
// any part is (a baked child: its source UVs are gone).
Piece joinPieces(const std::vector<SimplifiedNode>& parts, bool& geometryOnly) {
    geometryOnly = false;
    for (const SimplifiedNode& p : parts) geometryOnly = geometryOnly || p.geometryOnly;
    Piece joined;
    for (const SimplifiedNode& p : parts) {
        const MeshData& m = p.piece.mesh;
        const uint32_t base = static_cast<uint32_t>(joined.mesh.vertexCount());
        joined.mesh.positions.insert(joined.mesh.positions.end(), m.positions.begin(), m.positions.end());
        if (!geometryOnly) joined.mesh.texcoords.insert(joined.mesh.texcoords.end(), m.texcoords.begin(), m.texcoords.end());
        joined.mesh.colors.insert(joined.mesh.colors.end(), m.colors.begin(), m.colors.end());
        for (uint32_t i : m.indices) joined.mesh.indices.push_back(base + i);
        for (uint32_t material : p.piece.materials) joined.materials.push_back(geometryOnly ? 0 : material);
    }
    MeshData& m = joined.mesh;
    const size_t vc = m.vertexCount();  // an attribute some part lacks is dropped for all
    if (m.texcoords.size() != 2 * vc) m.texcoords.clear();
    if (m.colors.size() != 4 * vc) m.colors.clear();
    // Identical vertices (position, attributes, material; the cut borders the parts share) merged,
    // in first use, and triangles that lose a corner dropped: what weldPiece(joined, 0)
    // does, on meshoptimizer's hash (weldPiece was a tenth of a bottom-up build).
    std::vector<uint32_t> material(vc);
    for (size_t t = 0; t < joined.materials.size(); ++t)
        for (int k = 0; k < 3; ++k) material[m.indices[3 * t + k]] = joined.materials[t];
    std::vector<meshopt_Stream> streams{{m.positions.data(), 3 * sizeof(float), 3 * sizeof(float)},
                                        {material.data(), sizeof(uint32_t), sizeof(uint32_t)}};
    if (!m.texcoords.empty()) streams.push_back({m.texcoords.data(), 2 * sizeof(float), 2 * sizeof(float)});
    if (!m.colors.empty()) streams.push_back({m.colors.data(), 4, 4});
    std::vector<uint32_t> remap(vc);
    const size_t unique = meshopt_generateVertexRemapMulti(remap.data(), m.indices.data(), m.indices.size(), vc, streams.data(), streams.size());
    auto compactStream = [&](auto& values, size_t width) {
        std::remove_reference_t<decltype(values)> out(unique * width);
        meshopt_remapVertexBuffer(out.data(), values.data(), vc, width * sizeof(values[0]), remap.data());
        values = std::move(out);
    };
    compactStream(m.positions, 3);
    if (!m.texcoords.empty()) compactStream(m.texcoords, 2);
    if (!m.colors.empty()) compactStream(m.colors, 4);
    std::vector<uint32_t> indices;
    std::vector<uint32_t> materials;
    for (size_t t = 0; t < joined.materials.size(); ++t) {
        const uint32_t a = remap[m.indices[3 * t]], b = remap[m.indices[3 * t + 1]], c = remap[m.indices[3 * t + 2]];
        if (a == b || b == c || c == a) continue;
        indices.insert(indices.end(), {a, b, c});
        materials.push_back(joined.materials[t]);
    }
    m.indices = std::move(indices), joined.materials = std::move(materials);
    return joined;
}

// Bottom-up mode (pipeline/BUILD_SPEED.md), depth first: the same division as top-down, but a
// node simplifies its children's simplified triangles, welded by position (their common cut
// borders become interior edges, its own borders stay locked as in top-down), to the same
// target, numTriangles_piece / factor. Each input triangle is simplified about once
// (1 + 1/c_levelFactor + ... ~ 1.33 passes) instead of once per level.
// Geometric error (BottomUpError::Bound, the default): with A the node's surface, B the union of
// its children's simplified surfaces (what A was simplified from) and O its original piece (the
// union of the children's pieces O_i), the Hausdorff distance satisfies the triangle inequality
// H(A, O) <= H(A, B) + H(B, O), and H(B, O) <= max_i H(B_i, O_i) (each point of B_i lies within
// H(B_i, O_i) of O_i, a part of O, and conversely); the same holds for the one-sided distance.
// So the node stores the measured H(A, B) plus its children's largest error: an upper bound of
// the error against the original, found without a pass over the original triangles. A node whose
// children are leaves (they keep the original triangles, error 0: B is O) is measured against
// its piece O, the exact measure. The mean adds the children's largest mean: an
// estimate, not a bound (the build report's; the database stores the maximum).
// BottomUpError::Simplifier: the node's error is its children's largest plus the error its
// simplifier reports for simplifying them (SimplifiedNode::error: meshoptimizer's quadric error,
// an area-weighted root mean square of distances to the merged triangles' planes, in input
// units), in all three fields; no distance is measured. Nexus's nxsbuild measures none either
// (Ponchio, 2008, PhD thesis "Multiresolution structures for interactive visualization of very
// large 3D datasets"; its source stores a patch's root-mean-square edge length after simplifying,
// src/nxsbuild/mesh.cpp edgeLengthError, made no smaller than its children's). An estimate, NOT a
// bound of the distance to the original: a hole patch (simplify.cpp) is new surface whose distance
// to the original is never counted; pipeline/BUILD_SPEED.md compares it with the exact measure.
// The children's subtrees are independent: TBB tasks, their results taken in child order.
// A finished node's blobs wait in `spill` (blob_spill.h) until the block is emitted.
struct BottomUpNode {
    NodeOut out;
    std::vector<uint32_t> children;
    std::vector<std::pair<uint64_t, uint64_t>> parked;  // its blobs in the spill
};
struct BottomUpTree {  // the nodes of a block, in the order they finish (emitted breadth-first by children)
    explicit BottomUpTree(const std::string& dir) : spill(dir) {}
    std::mutex mutex;
    std::vector<BottomUpNode> nodes;
    BlobSpill spill;
};
uint32_t bottomUp(Piece piece, Sides shared, double factor, uint32_t level, const BuildOptions& options, uint32_t blockIndex,
                  BlockTextures& textures, Progress* progress, BottomUpTree& tree, SimplifiedNode& result) {
    const Constants& c = options.constants;
    BottomUpNode node;
    if (isLeaf(factor, c.levelFactor, options.leafRule)) {
        result = {piece, false};
        node.out = finishNode(result, piece, nullptr, {}, factor, level, true, blockIndex, options, textures);
    } else {
        std::vector<Sides> childSides;
        std::vector<Piece> children = dividePiece(piece, static_cast<uint32_t>(c.levelFactor), options.planes, shared, &childSides);
        std::vector<SimplifiedNode> simplifiedChildren(children.size());
        node.children.resize(children.size());
        parallelFor(children.size(), [&](size_t k) {
            node.children[k] = bottomUp(std::move(children[k]), childSides[k], factor / c.levelFactor, level + 1, options, blockIndex, textures,
                                        progress, tree, simplifiedChildren[k]);
        });
        SurfaceError inherited;  // the children's largest errors, field by field
        {
            const std::lock_guard lock(tree.mutex);  // other subtrees may be adding nodes
            for (uint32_t id : node.children) {
                const SurfaceError& e = tree.nodes[id].out.error;
                inherited = {std::max(inherited.oneSided, e.oneSided), std::max(inherited.max, e.max), std::max(inherited.mean, e.mean)};
            }
        }
        bool geometryOnly = false;
        const Piece input = joinPieces(simplifiedChildren, geometryOnly);
        simplifiedChildren.clear();
        const double target = std::max(1.0, double(piece.mesh.triangleCount()) / factor);
        const double inputFactor = std::max(1.0, double(input.mesh.triangleCount()) / target);
        const bool leafChildren = isLeaf(factor / c.levelFactor, c.levelFactor, options.leafRule);
        // Under --leaf-rule stop-before a leaves' parent simplifies by c_levelFactor or more: capped,
        // but for a factor of exactly c_levelFactor (as near the original as below-one's).
        const bool nearOriginal = leafChildren && factor <= c.levelFactor;
        const double ceiling = nearOriginal ? HUGE_VAL : freeBorderCeiling(input, inputFactor, shared, options);
        result = simplifyNode(input, inputFactor, options.simplifier, shared, ceiling);
        result.geometryOnly = result.geometryOnly || (geometryOnly && !piece.mesh.texcoords.empty());
        if (options.bottomUpError == BottomUpError::Simplifier) {
            inherited = {inherited.oneSided + result.error, inherited.max + result.error, inherited.mean + result.error};
            node.out = finishNode(result, piece, nullptr, inherited, factor, level, false, blockIndex, options, textures);
        } else {
            // Leaf children keep the original triangles: their union is the piece itself (cut), so
            // the node is measured against its uncut piece, exactly and on fewer triangles.
            const bool bound = options.bottomUpError == BottomUpError::Bound && !leafChildren;
            node.out = finishNode(result, piece, bound ? &input.mesh : &piece.mesh, bound ? inherited : SurfaceError{}, factor, level,
                                  false, blockIndex, options, textures);
        }
    }
    if (progress) progress->advance(piece.mesh.triangleCount());
    tree.spill.park(node.out.record.node.blobs, node.parked);
    const std::lock_guard lock(tree.mutex);
    tree.nodes.push_back(std::move(node));
    return static_cast<uint32_t>(tree.nodes.size() - 1);
}

// Top-down, one breadth-first level at a time: the level's nodes are independent (each
// simplifies, measures and packs its own piece; dividePiece gives its children's), so TBB
// workers take them in order from a shared counter, and each finished node's record is emitted
// as soon as every node before it is (records wait only behind a node still being built). A node's
// piece is freed once its children's pieces exist: the level's pieces and its children's are
// what the breadth-first queue held before, one node at a time.
struct Level {
    std::vector<Pending> pending;
    std::vector<std::optional<NodeOut>> done;  // finished, not yet emitted
    std::vector<std::vector<Piece>> children;
    std::vector<std::vector<Sides>> childSides;
    std::vector<double> ceiling;
    size_t emitted = 0;
    std::atomic<size_t> next{0};
    std::mutex mutex;
};
void topDownLevel(Level& level, uint32_t levelBase, const BuildOptions& options, uint32_t blockIndex, BlockTextures& textures,
                  Progress* progress, BlockStats& stats, std::vector<uint32_t>& parentOf,
                  const std::function<void(NodeRecord&&)>& emit) {
    const Constants& c = options.constants;
    const size_t n = level.pending.size();
    level.done.resize(n);
    level.children.resize(n);
    level.childSides.resize(n);
    level.ceiling.resize(n);
    const size_t workers = std::min<size_t>(n, static_cast<size_t>(tbb::this_task_arena::max_concurrency()));
    parallelFor(workers, [&](size_t) {
        for (size_t i; (i = level.next++) < n && !tbb::is_current_task_group_canceling();) {
            Pending& p = level.pending[i];
            const bool leaf = isLeaf(p.factor, c.levelFactor, options.leafRule);
            const SimplifiedNode simplified = leaf ? SimplifiedNode{p.piece, false} : simplifyNode(p.piece, p.factor, options.simplifier, p.shared, p.ceiling);
            NodeOut out = finishNode(simplified, p.piece, &p.piece.mesh, {}, p.factor, p.level, leaf, blockIndex, options, textures);
            out.record.parentLocal = p.parentLocal;
            if (progress) progress->advance(p.piece.mesh.triangleCount());
            std::vector<Piece> children;
            std::vector<Sides> childSides;
            if (!leaf) children = dividePiece(p.piece, static_cast<uint32_t>(c.levelFactor), options.planes, p.shared, &childSides);
            p.piece = {};
            const std::lock_guard lock(level.mutex);
            level.children[i] = std::move(children);
            level.childSides[i] = std::move(childSides);
            level.ceiling[i] = errorCeiling(simplified.error, options);
            level.done[i] = std::move(out);
            for (; level.emitted < n && level.done[level.emitted]; ++level.emitted) {  // in breadth-first order
                NodeOut& ready = *level.done[level.emitted];
                const uint32_t self = recordNode(stats, parentOf, ready, level.pending[level.emitted].parentLocal);
                if (self != levelBase + level.emitted) throw std::logic_error("buildBlock: records out of order");
                emit(std::move(ready.record));
                level.done[level.emitted].reset();
            }
        }
    });
}

}  // namespace

void checkBuildOptions(const BuildOptions& o) {
    if (o.jobs < 0 || o.jobs > kMaxJobs)
        throw std::invalid_argument("jobs " + std::to_string(o.jobs) + " is not in 0.." + std::to_string(kMaxJobs));
    if (!std::isfinite(o.blockSize) || o.blockSize < 0) throw std::invalid_argument("block size must be a finite number >= 0");
    if (!std::isfinite(o.draco.positionStep) || o.draco.positionStep < 0)
        throw std::invalid_argument("position step must be a finite number >= 0");
    if (o.mode == BuildMode::BottomUp && o.bottomUpError == BottomUpError::Simplifier && o.simplifier != Simplifier::Meshopt)
        throw std::invalid_argument("--bottom-up-error simplifier needs --simplifier meshopt (OpenMesh's decimater reports no "
                                    "error of its own; pipeline/BUILD_SPEED.md)");
}

BlockStats buildBlock(const Piece& block, const std::vector<Material>& materials, uint32_t blockIndex,
                      const BuildOptions& blockOptions, Progress* progress, const std::function<void(NodeRecord&&)>& emit,
                      Sides shared) {
    checkBuildOptions(blockOptions);
    BuildOptions options = blockOptions;  // every node of the block on one position lattice
    if (options.draco.positionStep <= 0)
        options.draco.positionStep = positionLatticeStep(pieceBounds(block.mesh), options.draco.positionBits);
    const Constants& c = options.constants;
    BlockStats stats;
    stats.inputTriangles = block.mesh.triangleCount();
    stats.flattened = latticeFlattened(block.mesh, options.draco.positionStep);  // on the block's lattice, fixed above
    BlockTextures textures(materials, options.textures, options.strict, stats.textureProblems, progress);
    Piece welded = weldPiece(block, options.draco.positionStep / 2);  // weld.cpp: chunk borders become interior
    stats.straddling = wrapUvCharts(welded, materials);                // wrap_uvs.cpp: charts into the texture's [0, 1]
    const double rootFactor = static_cast<double>(welded.mesh.triangleCount()) / c.desiredTris;  // §3.2 hlod0
    std::vector<uint32_t> parentOf;
    if (options.mode == BuildMode::BottomUp) {
        BottomUpTree tree(options.tempDir);
        SimplifiedNode root;
        const uint32_t rootId = tbb::this_task_arena::isolate(
            [&] { return bottomUp(std::move(welded), shared, rootFactor, 0, options, blockIndex, textures, progress, tree, root); });
        std::vector<BottomUpNode>& nodes = tree.nodes;
        std::deque<std::pair<uint32_t, uint32_t>> order{{rootId, kNone}};  // emitted breadth-first, as top-down
        while (!order.empty()) {
            const auto [id, parentLocal] = order.front();
            order.pop_front();
            NodeOut& out = nodes[id].out;
            out.record.parentLocal = parentLocal;
            tree.spill.restore(out.record.node.blobs, nodes[id].parked);
            const uint32_t self = recordNode(stats, parentOf, out, parentLocal);
            emit(std::move(out.record));
            out.record = {};  // its blobs go now: an emit that only reads the record leaves them whole
            for (uint32_t child : nodes[id].children) order.push_back({child, self});
        }
    } else {
        std::vector<Pending> pending;
        const double ceiling =
            isLeaf(rootFactor, c.levelFactor, options.leafRule) ? HUGE_VAL : freeBorderCeiling(welded, rootFactor, shared, options);
        pending.push_back({std::move(welded), rootFactor, 0, kNone, shared, ceiling});
        while (!pending.empty()) {
            Level level;
            level.pending = std::move(pending);
            const uint32_t levelBase = static_cast<uint32_t>(parentOf.size());
            // isolated: a worker waiting here takes only this block's nodes, never another block
            // (which could wait on the memory gate this block holds)
            tbb::this_task_arena::isolate(
                [&] { topDownLevel(level, levelBase, options, blockIndex, textures, progress, stats, parentOf, emit); });
            pending.clear();
            for (size_t i = 0; i < level.pending.size(); ++i)
                for (size_t k = 0; k < level.children[i].size(); ++k)  // §3.2: simplification_hlod(i+1)
                    pending.push_back({std::move(level.children[i][k]), level.pending[i].factor / c.levelFactor,
                                       level.pending[i].level + 1, levelBase + static_cast<uint32_t>(i), level.childSides[i][k],
                                       level.ceiling[i]});
        }
    }
    // A node's error bounds its whole subtree's: a child's measure can exceed its parent's.
    for (size_t i = parentOf.size(); i-- > 1;)
        stats.geometricErrors[parentOf[i]] = std::max(stats.geometricErrors[parentOf[i]], stats.geometricErrors[i]);
    return stats;
}

}  // namespace hlod
