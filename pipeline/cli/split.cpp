// `hlod split INPUT -o WORK`: reads the input and splits it on the block grid once, into a work
// folder (pipeline/split_work.h) that shard builds start from (`hlod build WORK --shard --blocks
// A:B`) on one machine or many (README "Beyond one machine"). The options that decide the blocks
// (--block-triangles, --block-size, --up, --offset, --allow-outside-input) belong to the split; the build
// adopts them from the work folder.
#include "pipeline/cli/subcommands.h"

#include "pipeline/split_work.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <iostream>
#include <memory>

namespace hlod::cli {
namespace {

struct SplitArgs {
    std::string input, work;
    BuildOptions options;
    ProgressOptions progress;
};

int runSplit(SplitArgs& a) {
    SplitSummary summary;
    {
        a.progress.live = !a.progress.json && isatty(STDOUT_FILENO) != 0;
        Progress progress(std::cout, a.progress);
        summary = writeSplitWork(a.input, a.options, a.work, progress);
    }
    std::cout << a.work << ": " << summary.blockCount << " blocks";
    if (summary.triangles) std::cout << ", " << summary.triangles << " triangles";
    std::cout << " (build them with: hlod build " << a.work << " -o SHARD --shard --blocks FIRST:LAST)\n";
    return kExitOk;
}

}  // namespace

void addSplit(CLI::App& app, int& status) {
    auto a = std::make_shared<SplitArgs>();
    BuildOptions& o = a->options;
    CLI::App* sub = app.add_subcommand("split", "read and split a mesh (or list a folder of block meshes) once, into a work folder for shard builds");
    sub->add_option("INPUT", a->input, "mesh file, or folder of meshes (one block per file, ordered by name)")->required();
    sub->add_option("-o,--output", a->work, "work folder to write (absent, empty, or an earlier work folder)")
        ->required()->check(nonEmptyPath());
    sub->add_option("--block-triangles", o.blockTriangles, "target triangles per block of a single mesh (default and 0: 671,088)")
        ->check(wholeNumber(o.blockTriangles));
    sub->add_option("--block-size", o.blockSize, "block side length in input units (overrides --block-triangles; 0: not given)")
        ->check(finiteAtLeast(0));
    addMemoryLimitOption(sub, o.memoryLimit, "bound on the split's buffers");
    sub->add_option("--draco-position-bits", o.draco.positionBits,
                    "Draco position bits the recorded lattice is for (a build with other bits recomputes it)")
        ->check(CLI::Range(kMinPositionBits, kMaxPositionBits));
    sub->add_flag("--allow-outside-input", o.read.allowOutsideInput,
                  "let an input refer to files outside its folder (as for hlod build)");
    sub->add_option("--up", o.up, "up axis of the input, recorded in the database (default: y for glTF, z for OBJ/PLY)")
        ->check(CLI::IsMember({"y", "z"}));
    sub->add_flag("--strict", o.strict, "an unusable texture found while reading is fatal (exit 2)");
    addOffsetOption(sub, o.read.offset);
    addProgressOptions(sub, a->progress);
    sub->callback([a, &status] { status = runGuarded("split", [&] { return runSplit(*a); }); });
}

}  // namespace hlod::cli
