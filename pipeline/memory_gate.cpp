// The memory gate of the build (build.cpp): blocks are admitted into the parallel build while their
// estimated working sets fit --memory-limit together, and a block builds nodes on further threads
// only on further working sets the gate grants (pipeline/MEMORY.md "Jobs"). The working-set model
// is an empirical one, fitted on measured peaks (pipeline/MEMORY.md "The gate's model, checked").
#include "pipeline/pipeline.h"

#include <algorithm>

namespace hlod {
namespace {

// Working set of buildBlock: per input triangle (the piece, its per-material copies, the
// simplified meshes, the hierarchies of the error measure, the children's pieces) and per source
// texel the block's materials use. Since issue #14 no source texture is held (texture_store.cpp:
// decoded once to a temporary file, read by the rectangles of a node's charts), so a texel costs
// only through the node atlases, baked regions and JPEG coding: 1/12 byte. Measured (pipeline/
// MEMORY.md): a 490,000-triangle block with 55 x 4K JPEG atlases (923 Mtexel) peaked 233 MB
// above the process's baseline of then, ~128 MiB (OpenImageIO linked; now ~10 MiB) (the model: 196 + 77 = 273 MB); before, the model said
// 5.7 GB (6 B per source texel, every atlas decoded and downsampled whole) for 4.6 GB measured.
// The per-texel figure is fitted on that one generated input.
// A node's texture work (its atlas, the baker's per-chart sub-samples, the JPEG coding, the
// rectangles read from the pyramid) scales with the node's texel budget, not the block's: the
// source texels of its piece over its factor (build_tree.cpp), at every level about the block's
// texels x c_desiredTris / its triangles (nodeTexels), so a block of few triangles on many
// texels costs more than the two terms above. Fitted on generated inputs (pipeline/MEMORY.md "The
// gate's model, checked"): the facade's 55 x 4K atlases on 122,500 triangles (6.8 Mtexel a node)
// peaked at 23.4 B per node texel beyond them at -j 1, rounded up to 25; on 490,000 triangles
// (1.7 Mtexel a node) the model is then 1.66x the measured peak.
// A progressive (multi-scan) JPEG is the one texture read not by strips: libjpeg holds all its
// coefficients while decoding it (formats/image_io.h), so build.cpp adds the largest such texture a
// block has still to decode to its ticket (measured: a 4096^2 4:4:4 one, 96 MiB of coefficients,
// peaked 110 MiB against 17 MiB as baseline; pipeline/MEMORY.md "Progressive JPEGs").
constexpr uint64_t kBytesPerBlockTriangle = 400;
constexpr uint64_t kSourceTexelsPerByte = 12;
constexpr uint64_t kBytesPerNodeTexel = 25;

// Texel budget of one node of a block (a block of at most c_desiredTris triangles is one node).
uint64_t nodeTexels(uint64_t triangles, uint64_t texels, double desiredTris) {
    if (triangles <= desiredTris) return texels;
    return static_cast<uint64_t>(static_cast<double>(texels) * desiredTris / static_cast<double>(triangles));
}

}  // namespace

void MemoryGate::acquire(uint64_t bytes) {
    std::unique_lock lock(mutex_);
    freed_.wait(lock, [&] { return used_ == 0 || used_ + bytes <= limit_; });
    used_ += bytes;
    peak_ = std::max(peak_, used_);
}

bool MemoryGate::tryAcquire(uint64_t bytes) {
    const std::lock_guard lock(mutex_);
    if (used_ + bytes > limit_) return false;
    used_ += bytes;
    peak_ = std::max(peak_, used_);
    return true;
}

void MemoryGate::release(uint64_t bytes) {
    {
        const std::lock_guard lock(mutex_);
        used_ -= bytes;
    }
    freed_.notify_all();
}

uint64_t MemoryGate::inUse() const {
    const std::lock_guard lock(mutex_);
    return used_;
}

uint64_t MemoryGate::peak() const {
    const std::lock_guard lock(mutex_);
    return peak_;
}

uint64_t blockWorkingSet(uint64_t triangles, uint64_t texels, double desiredTris) {
    return triangles * kBytesPerBlockTriangle + texels / kSourceTexelsPerByte + nodeTexels(triangles, texels, desiredTris) * kBytesPerNodeTexel;
}

}  // namespace hlod
