// `hlod split`'s work folder (README "Beyond one machine"): the input read and split on the block
// grid once, so that shard builds on many machines (`hlod build WORK --shard --blocks A:B`) start
// from their blocks instead of each re-reading and re-splitting the whole input. Layout, version
// hlod-split-2 (a folder; -1 lacked the materials' uv_period):
//   manifest.json      written last (the folder is renamed into place whole, so a killed split
//                      leaves no WORK): format, input (as given: the database's META "input"), up
//                      axis and why, the split options, the grid, bounds, position lattice, block
//                      count, per block its file, triangles, bytes and XXH3-64, the materials, and
//                      the unusable textures found.
//   cells/cell_N.piece the blocks of a single-mesh input (appendPiece files; N = grid cell)
//   materials/M.image  the embedded textures of a glTF input (width, height, channels, pixels)
// A folder input's blocks are its mesh files, and textures stay where the input has them: both
// are recorded by absolute path, so every machine that builds shards must see them at that path.
#pragma once

#include "pipeline/pipeline.h"

#include <optional>
#include <string>
#include <vector>

namespace hlod {

inline constexpr const char* kSplitFormat = "hlod-split-2";

struct BlockSource {
    std::string file;      // mesh file of a folder input, or a loadPiece file (cell)
    bool isPiece = false;  // true: a loadPiece file using SplitInputs::materials
    uint64_t triangles = 0;
};

// The blocks of an input and what every block shares.
struct SplitInputs {
    std::vector<BlockSource> blocks;
    std::vector<Material> materials;  // of a single-mesh input
    std::optional<GridSpec> grid;     // of a single-mesh input
    Box3f bounds{};                   // of a single-mesh input
    double positionStep = 0;          // one position lattice for the grid's blocks; 0 = per block
    std::vector<TextureProblem> textureProblems;  // of a single-mesh input
    uint64_t inputTriangles = 0;  // read from a single-mesh input, before the grid cuts; 0: the blocks' sum
};

// build.cpp: the blocks of `input` (a folder: one per mesh file, by name; one mesh: read and split
// on the grid into loadPiece files under `tempDir`).
SplitInputs findBlocks(const std::string& input, const BuildOptions& options, const std::string& tempDir,
                       Progress& progress);

// A work folder opened for a build: the original input, the up axis chosen at the split, blocks.
struct SplitWork {
    std::string input;
    UpChoice up;
    SplitInputs inputs;
};

struct SplitSummary {
    uint32_t blockCount = 0;
    uint64_t triangles = 0;  // in the blocks (a folder input: 0, its meshes are read by the build)
};

// `hlod split INPUT -o WORK`: findBlocks into a temporary folder next to WORK, then renamed to
// WORK. WORK may be absent, an empty folder, or an earlier work folder (replaced); anything else
// is refused (std::invalid_argument: a usage error) rather than deleted.
SplitSummary writeSplitWork(const std::string& input, const BuildOptions& options, const std::string& work,
                            Progress& progress);

// A folder holding manifest.json.
bool isSplitWork(const std::string& path);

// Reads WORK's manifest and checks every block file (present, its size, and for the blocks
// [first, last) its XXH3-64): InputError "WORK/FILE: problem" otherwise. The split's options
// (--block-triangles, --block-size, --up, --allow-outside-input) are adopted into `options`; a
// different value given to the build is a usage error (std::invalid_argument). --strict with an
// unusable texture found at the split is an InputError. The lattice is the manifest's unless
// --draco-position-bits differs from the split's (then recomputed from the grid).
SplitWork openSplitWork(const std::string& work, BuildOptions& options, uint32_t first, uint32_t last);

}  // namespace hlod
