// `hlod stats DB [--json] [--thesis]`: registers the preprocessing statistics subcommand.
#pragma once

namespace CLI {
class App;
}

namespace hlod::cli {

void addStats(CLI::App& app, int& status);

}  // namespace hlod::cli
