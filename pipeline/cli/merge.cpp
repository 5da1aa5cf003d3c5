// `hlod merge SHARD... -o DB`: joins the shard folders of `hlod build --shard` into one database,
// byte-identical to a single build (c_textured comes from the shards' own metadata). Progress is
// the build's: one `write` stage, as plain lines or --progress-json.
#include "pipeline/cli/subcommands.h"

#include "pipeline/pipeline.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <iostream>
#include <memory>

namespace hlod::cli {
namespace {

struct MergeArgs {
    std::vector<std::string> shards;
    std::string output;
    ProgressOptions progress;
};

int runMerge(MergeArgs& a) {
    const ShardInfo info = readShardInfo(a.shards.front());
    Constants c;
    try {  // c_textured = -1 merged into a database no player opens, exit 0 (until stop 45)
        for (const auto& [key, value] : info.meta)
            if (key == "c_textured") setConstant(c, key, value);
        validateConstants(c, kUsedByBuild);
    } catch (const std::exception& e) {
        throw InputError(a.shards.front() + "/shard.json: " + e.what());
    }
    {
        a.progress.live = !a.progress.json && isatty(STDOUT_FILENO) != 0;
        Progress progress(std::cout, a.progress);
        progress.beginStage("write", info.blockCount, "blocks");
        progress.message("constants: c_textured=" + formatConstant(c.textured) + " (the shards')");
        mergeShards(a.shards, a.output, c.textured);
        progress.advance(info.blockCount);
        progress.endStage();
    }
    std::cout << a.output << ": merged " << a.shards.size() << " shard(s), " << info.blockCount << " blocks\n";
    warnHlod0Missed(a.output);
    return kExitOk;
}

}  // namespace

void addMerge(CLI::App& app, int& status) {
    auto a = std::make_shared<MergeArgs>();
    CLI::App* merge = app.add_subcommand("merge", "merge shard folders written by `hlod build --shard` into one database");
    merge->add_option("SHARDS", a->shards, "shard folders")->required()->check(nonEmptyPath());  // '' read ./shard.json
    merge->add_option("-o,--output", a->output, "database to write")->required()->check(nonEmptyPath());
    addProgressOptions(merge, a->progress);
    merge->callback([a, &status] { status = runGuarded("merge", [&] { return runMerge(*a); }); });
}

}  // namespace hlod::cli
