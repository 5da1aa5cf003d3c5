// Subcommands contributed by the player (registered in player/cli/main.cpp).
#pragma once

namespace CLI {
class App;
}

namespace hlod::cli {

// `hlod play DB --path FILE`: replays a camera path through the Chapter 4 engine, writes the
// per-frame CSV (player/STATS.md) and prints a summary.
void addPlay(CLI::App& app, int& status);
// `hlod path DB --kind walk|drive|fly|erratic -o FILE`: generates a camera path from the bounds.
void addPath(CLI::App& app, int& status);

}  // namespace hlod::cli
