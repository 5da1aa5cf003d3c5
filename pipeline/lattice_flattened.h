// Triangles the position lattice flattens (lattice_flattened.cpp). Every stored position is rounded
// to the nearest multiple of the lattice step (formats/codec.h), so a triangle whose rounded corners
// lie on one line or point is stored without area. A few such triangles are detail finer than the
// lattice; most of a model's are a model thinner than a few steps (a 100,000 x 1 strip at the default
// 14 bits: a step of 4, every triangle flat), stored with status 0 and "valid" until stop 46.
#pragma once

#include "formats/codec.h"

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace hlod {

struct BlockStats;

// The share of a build's triangles above which it warns, not fitted to a dataset: measured in stop
// 46 at the default 14 bits, Lucy 100k, the bunny, the banana and the sample city flatten none, Lucy
// 1.6 M 188 (0.01 %; 0.3 % at 10 bits), a thin model all or nearly all.
inline constexpr double kFlattenedWarning = 0.01;

// Triangles of `mesh` whose corners, rounded to the lattice of `step` (rounded down to a power of
// two, as the codec does), coincide or lie on one line.
uint64_t latticeFlattened(const MeshData& mesh, double step);
// "" unless `flattened` exceeds kFlattenedWarning of `triangles`; else the warning naming `input`.
std::string latticeFlattenedWarning(const std::string& input, uint64_t flattened, uint64_t triangles);
// A folder input's files whose float positions step more coarsely than their own lattices
// (BlockStats::floatStepOver): "" for none, else one floatPrecisionWarning naming the folder, how
// many of its files, and the --offset of all their bounds, since --offset moves every file (until
// stop 49 one warning a file, each with its own centre: 95 lines for Mars's leaves at 20 bits).
std::string floatPrecisionOfFiles(const std::string& input, std::span<const BlockStats> files, const std::array<double, 3>& offset);

}  // namespace hlod
