// The subcommands of pipeline/ (registered by the table in hlod.cpp).
#pragma once

#include "formats/cli/command.h"

#include <array>
#include <cstdint>
#include <string>

namespace hlod {
struct ProgressOptions;
}

namespace hlod::cli {

// `hlod build INPUT -o DB`: a mesh or a folder of block meshes into a database (thesis §3).
void addBuild(CLI::App& app, int& status);
// `hlod split INPUT -o WORK`: the input read and split once, for shard builds (split_work.h).
void addSplit(CLI::App& app, int& status);
// `hlod merge SHARD... -o DB`: shard folders of `hlod build --shard` into one database.
void addMerge(CLI::App& app, int& status);
// `hlod stats DB`: the preprocessing statistics of thesis §3.2, with the build's times.
void addStats(CLI::App& app, int& status);
// `hlod synth city -o DIR`: the synthetic thesis-like city (pipeline/synth/synth.h).
void addSynth(CLI::App& app, int& status);

// --progress-json and --progress-interval, the same for build, split and merge.
void addProgressOptions(CLI::App* sub, ProgressOptions& progress);  // defined in build.cpp
// --offset X,Y,Z (ReadOptions::offset), the same for build and split; defined in build.cpp.
void addOffsetOption(CLI::App* sub, std::array<double, 3>& offset);
// --memory-limit (BuildOptions::memoryLimit), the same for build and split, at least
// kMinMemoryLimit; defined in build.cpp.
constexpr uint64_t kMinMemoryLimit = uint64_t{16} << 20;
void addMemoryLimitOption(CLI::App* sub, uint64_t& limit, const std::string& what);
// After a build or merge: `warning: DB: N of M hlod0 nodes keep more than 1.25 x c_desiredTris
// ...` when the coarsest level misses its target (stats::hlod0Check); defined in build.cpp.
void warnHlod0Missed(const std::string& db);

}  // namespace hlod::cli
