// hlod: the entry point of the one command-line tool and its table of subcommands, in the
// manner of git's git.c. Each library's subcommands are a target of their own, in the library's
// cli/ folder, which the library itself does not depend on:
//   formats/cli/   inspect, validate, export   (command.h: exit statuses, error guard, constant options)
//   pipeline/cli/  build, split, merge, stats, synth
//   player/cli/    play, path, view, calibrate, compare
#include "formats/cli/huge_pages.h"
#include "formats/cli/subcommands.h"
#include "formats/interrupt.h"
#include "pipeline/cli/subcommands.h"
#include "player/cli/subcommands.h"

#include <CLI/CLI.hpp>

#ifndef HLOD_VERSION
#define HLOD_VERSION "0.0.0"
#endif

namespace {

// In the order `hlod --help` lists them: build, look at, play back, export, make data.
constexpr hlod::cli::AddSubcommand kSubcommands[] = {
    hlod::cli::addBuild,    hlod::cli::addSplit,   hlod::cli::addMerge,  hlod::cli::addInspect,
    hlod::cli::addValidate, hlod::cli::addStats,   hlod::cli::addPlay,   hlod::cli::addPath,
    hlod::cli::addView,     hlod::cli::addCalibrate, hlod::cli::addCompare, hlod::cli::addExport,
    hlod::cli::addSynth,
};

}  // namespace

int main(int argc, char** argv) {
    if (hlod::cli::kGlibcMalloc) hlod::cli::reexecWithHugePages(argv);  // formats/cli/huge_pages.h
    hlod::removeTemporariesOnInterrupt();  // Ctrl-C leaves no temporaries (formats/interrupt.h); before any thread
    CLI::App app{"hlod: out-of-core HLOD databases for huge scanned 3D models (build, inspect, play)"};
    app.name("hlod");  // "Usage: hlod build ...", not the binary's path
    app.set_help_flag("-h,--help", "print this help and exit");  // lower case, as every help text; subcommands copy it
    app.set_version_flag("--version", std::string("hlod ") + HLOD_VERSION, "print the version and exit");
    app.require_subcommand(1);
    // One line, like every other error, prefixed with the subcommand it concerns ("hlod:" alone
    // until stop 46); a first word that names no subcommand is said to be one.
    app.failure_message([argc, argv](const CLI::App* top, const CLI::Error& e) {
        const std::vector<CLI::App*> chosen = top->get_subcommands();
        std::string prefix = "hlod";
        for (const CLI::App* sub = chosen.empty() ? nullptr : chosen.front(); sub;) {
            prefix += " " + sub->get_name();
            const std::vector<CLI::App*> next = sub->get_subcommands();
            sub = next.empty() ? nullptr : next.front();
        }
        if (chosen.empty() && argc > 1)
            return prefix + ": '" + argv[1] + "' is not " + (argv[1][0] == '-' ? "an option" : "a subcommand") + " (see --help)\n";
        return prefix + ": " + e.what() + " (see --help)\n";
    });
    int status = hlod::cli::kExitOk;
    for (hlod::cli::AddSubcommand add : kSubcommands) add(app, status);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {  // --help and --version exit 0, every usage error 2
        return app.exit(e) == 0 ? hlod::cli::kExitOk : hlod::cli::kExitUsage;
    }
    return status;
}
