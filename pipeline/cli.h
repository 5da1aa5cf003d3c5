// Subcommands of the pipeline: `hlod build` and `hlod merge` (both registered by addBuild).
// To be folded into formats/cli.h by the lead; player/cli/main.cpp calls addBuild.
#pragma once

namespace CLI {
class App;
}

namespace hlod::cli {

void addBuild(CLI::App& app, int& status);

}  // namespace hlod::cli
