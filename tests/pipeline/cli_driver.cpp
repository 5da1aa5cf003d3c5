// A minimal `hlod` for the CLI tests of `hlod build` / `hlod merge` / `hlod validate`, so they do
// not depend on player/cli/main.cpp registering the pipeline's subcommands.
#include "formats/cli.h"
#include "pipeline/cli.h"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    CLI::App app{"hlod (pipeline test driver)"};
    app.require_subcommand(1);
    int status = 0;
    hlod::cli::addBuild(app, status);
    hlod::cli::addValidate(app, status);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    return status;
}
