// `hlod synth city`: registers the synthetic city generator subcommand (pipeline/synth/synth.h).
#pragma once

namespace CLI {
class App;
}

namespace hlod::cli {

void addSynth(CLI::App& app, int& status);

}  // namespace hlod::cli
