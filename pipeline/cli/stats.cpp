// `hlod stats DB [--json] [--thesis]`: prints the preprocessing statistics of pipeline/stats/
// stats.h; --thesis puts the thesis's figures beside ours even when the input is not known to be
// the thesis-scale city.
#include "pipeline/cli/subcommands.h"

#include "formats/json_text.h"
#include "pipeline/stats/stats.h"

#include <CLI/CLI.hpp>

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
    CLI::App* sub = app.add_subcommand("stats", "preprocessing statistics of a database (thesis §3.2), with build times");
    addDatabaseArgument(*sub, args->path);
    sub->add_flag("--json", args->json, "machine-readable JSON output");
    sub->add_flag("--thesis", args->thesis, "show the thesis's figures beside ours whatever the input");
    sub->callback([args, &status] {
        status = runGuarded("stats", [&] {
            Database db = Database::open(args->path);
            stats::Stats s = stats::computeStats(db, args->thesis);
            if (!s.staleReport.empty()) std::cerr << "warning: " << s.staleReport << "\n";
            if (args->json) std::cout << jsonText(stats::toJson(s), 2) << "\n";
            else stats::printStats(std::cout, s);
            return kExitOk;
        });
    });
}

}  // namespace hlod::cli
