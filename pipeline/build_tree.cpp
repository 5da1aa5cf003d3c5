// The HLOD recursion of thesis §3.2 for one block, breadth-first:
//   simplification_hlod0 = numTriangles_b / c_desiredTris,
//   simplification_hlod(i+1) = simplification_hlod(i) / c_levelFactor,
// each node simplifying the piece's ORIGINAL triangles by its factor, then dividing the piece
// into c_levelFactor children by c_levelFactor - 1 plane cuts (cut.cpp), "until the factor
// becomes less than 1". Leaves keep the original triangles; which node is a leaf is the
// --leaf-rule (tree_rules.h, pipeline/TREE.md): below-one (default) divides every node whose
// factor is > 1, so leaves have a factor in (1/c_levelFactor, 1]; stop-before divides a node only
// when its children's factor would still be >= 1, so leaves have a factor in [1, c_levelFactor)
// (or the block's own, when it is below 1). Textures are cropped and downsampled by the same
// factor (texture.cpp, leaves keep the source's); the
// geometric error is measured against the original piece (error.cpp). All nodes are encoded on
// one position lattice (DracoOptions::positionStep, by default the block root's), so the
// borders the cuts made identical stay identical after quantization.
#include "pipeline/pipeline.h"

#include <deque>
#include <map>
#include <optional>

namespace hlod {
namespace {

struct Pending {
    Piece piece;
    double factor;
    uint32_t level;
    uint32_t parentLocal;
};

// Source textures of one block, loaded on first use. One that fails to decode (truncated,
// corrupt: its header passed checkTextures) is a TextureProblem and its material untextured in
// this block, or, with BuildOptions::strict, fatal.
class TextureCache {
public:
    TextureCache(const std::vector<Material>& materials, bool strict, std::vector<TextureProblem>& problems, Progress* progress)
        : materials_(materials), strict_(strict), problems_(problems), progress_(progress) {}

    // The material's texture downsampled for `level` (factor); nullptr when untextured.
    const Image* get(uint32_t material, uint32_t level, double factor) {
        if (material >= materials_.size()) return nullptr;
        const Image* source = materials_[material].image.get();
        if (!source && materials_[material].texturePath.empty()) return nullptr;
        if (!source) {
            auto it = sources_.find(material);
            if (it == sources_.end()) it = sources_.emplace(material, load(material)).first;
            if (!it->second) return nullptr;
            source = &*it->second;
        }
        if (factor <= 1) return source;
        auto it = scaled_.find({material, level});
        if (it == scaled_.end()) it = scaled_.emplace(std::pair{material, level}, downsampleTexture(*source, factor)).first;
        return &it->second;
    }

private:
    std::optional<Image> load(uint32_t material) {
        try {
            Image image = loadTexture(materials_[material].texturePath);
            if (progress_) progress_->textureLoaded(uint64_t{image.width} * image.height);
            return image;
        } catch (const InputError& e) {
            if (strict_) throw InputError(std::string(e.what()) + " (--strict)");
            problems_.push_back({e.what(), materials_[material].name});
            return std::nullopt;
        }
    }

    const std::vector<Material>& materials_;
    bool strict_;
    std::vector<TextureProblem>& problems_;
    Progress* progress_;
    std::map<uint32_t, std::optional<Image>> sources_;
    std::map<std::pair<uint32_t, uint32_t>, Image> scaled_;
};

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
    TextureCache textures(materials, options.strict, stats.textureProblems, progress);
    std::deque<Pending> queue;
    queue.push_back({block, static_cast<double>(block.mesh.triangleCount()) / c.desiredTris, 0, kNone});  // §3.2 hlod0
    std::vector<uint32_t> parentOf;
    while (!queue.empty()) {
        Pending p = std::move(queue.front());
        queue.pop_front();
        const std::vector<SubMesh> original = splitByMaterial(p.piece);
        const bool leaf = isLeaf(p.factor, c.levelFactor, options.leafRule);
        std::vector<SubMesh> parts = original;
        if (!leaf)
            for (SubMesh& part : parts) part.mesh = simplifyMesh(part.mesh, p.factor, options.simplifier, part.locked);
        const double error = leaf ? 0.0 : surfaceDistance(parts, original);
        const double textureFactor = leaf ? 1.0 : p.factor;  // a leaf keeps the source's texels
        std::vector<Image> images(parts.size());
        for (size_t i = 0; i < parts.size(); ++i)
            if (const Image* scaled = textures.get(parts[i].material, p.level, textureFactor))
                images[i] = atlasTexture(*scaled, parts[i].mesh);
        emit(packNode(parts, images, pieceBounds(p.piece.mesh), p.parentLocal, p.level, blockIndex, error, options));
        if (stats.nodesPerLevel.size() <= p.level) stats.nodesPerLevel.resize(p.level + 1);
        ++stats.nodesPerLevel[p.level];
        if (progress) progress->advance(p.piece.mesh.triangleCount());
        const uint32_t self = static_cast<uint32_t>(parentOf.size());
        parentOf.push_back(p.parentLocal);
        stats.geometricErrors.push_back(static_cast<float>(error));
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
