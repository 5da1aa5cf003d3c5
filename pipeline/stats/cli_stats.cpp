// `hlod stats DB [--json] [--thesis]`: prints the preprocessing statistics of pipeline/stats/
// stats.h; --thesis puts the thesis's figures beside ours even when the input is not known to be
// the thesis-scale city. Errors are one line naming the file, exit status 1.
#include "pipeline/stats/cli_stats.h"

#include "pipeline/stats/stats.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>

namespace hlod::cli {

namespace {
struct StatsArgs {
    std::string path;
    bool json = false;
    bool thesis = false;
};
}  // namespace

void addStats(CLI::App& app, int& status) {
    auto args = std::make_shared<StatsArgs>();
    CLI::App* sub = app.add_subcommand("stats", "Preprocessing statistics of a database (thesis §3.2), with build times");
    sub->add_option("database", args->path, "HLOD database file")->required();
    sub->add_flag("--json", args->json, "Print JSON instead of text");
    sub->add_flag("--thesis", args->thesis, "Show the thesis's figures beside ours whatever the input");
    sub->callback([args, &status] {
        try {
            Database db = Database::open(args->path);
            stats::Stats s = stats::computeStats(db, args->thesis);
            if (args->json) std::cout << stats::toJson(s).dump(2) << "\n";
            else stats::printStats(std::cout, s);
            status = 0;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "hlod stats: %s\n", e.what());
            status = 1;
        }
    });
}

}  // namespace hlod::cli
