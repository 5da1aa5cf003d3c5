// `hlod`: one command-line tool, subcommands in the manner of git.
#include "formats/cli.h"
#include "pipeline/cli.h"
#include "pipeline/stats/cli_stats.h"
#include "pipeline/synth/cli_synth.h"
#include "player/cli.h"
#include "player/gl/cli.h"

#include <CLI/CLI.hpp>

#include <iostream>

#ifndef HLOD_VERSION
#define HLOD_VERSION "0.0.0"
#endif

int main(int argc, char** argv) {
    CLI::App app{"hlod: out-of-core HLOD databases for huge scanned 3D models (build, inspect, play)"};
    app.set_version_flag("--version", std::string("hlod ") + HLOD_VERSION);
    app.require_subcommand(1);
    int status = 0;
    hlod::cli::addBuild(app, status);  // build + merge
    hlod::cli::addInspect(app, status);
    hlod::cli::addValidate(app, status);
    hlod::cli::addStats(app, status);
    hlod::cli::addPlay(app, status);
    hlod::cli::addPath(app, status);
    hlod::cli::addView(app, status);
    hlod::cli::addCalibrate(app, status);
    hlod::cli::addSynth(app, status);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    return status;
}
