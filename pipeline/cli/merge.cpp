// `hlod merge SHARD... -o DB`: joins the shard folders of `hlod build --shard` into one database,
// byte-identical to a single build (c_textured comes from the shards' own metadata).
#include "pipeline/cli/subcommands.h"

#include "pipeline/pipeline.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>

namespace hlod::cli {

void addMerge(CLI::App& app, int& status) {
    auto shards = std::make_shared<std::vector<std::string>>();
    auto output = std::make_shared<std::string>();
    CLI::App* merge = app.add_subcommand("merge", "merge shard folders written by `hlod build --shard` into one database");
    merge->add_option("SHARDS", *shards, "shard folders")->required();
    merge->add_option("-o,--output", *output, "database to write")->required();
    merge->callback([shards, output, &status] {
        status = runGuarded("merge", [&] {
            const ShardInfo info = readShardInfo(shards->front());
            Constants c;
            for (const auto& [key, value] : info.meta)
                if (key == "c_textured") setConstant(c, key, value);
            mergeShards(*shards, *output, c.textured);
            std::cout << *output << ": merged " << shards->size() << " shard(s), " << info.blockCount << " blocks\n";
            return kExitOk;
        });
    });
}

}  // namespace hlod::cli
