// Shared pieces of the `hlod` subcommands: constant overrides (--config, --set; thesis
// Table 6.1 names) and the one-line error guard every subcommand runs under.
#include "formats/cli.h"

#include "formats/constants.h"

#include <CLI/CLI.hpp>

#include <iostream>

namespace hlod::cli {

void addConstantOptions(CLI::App& sub, ConstantOptions& options) {
    sub.add_option("--config", options.configFile, "constants file of 'c_name = value' lines ('#' comments)");
    sub.add_option("--set", options.sets, "override a constant, e.g. --set c_targetTime=20 (repeatable)")
        ->type_name("NAME=VALUE");
}

void applyConstantOptions(const ConstantOptions& options, Constants& c) {
    if (!options.configFile.empty()) loadConstantsFile(c, options.configFile);
    for (const std::string& s : options.sets) setConstantAssignment(c, s);
}

int runGuarded(const char* command, const std::function<int()>& body) {
    try {
        return body();
    } catch (const std::exception& e) {
        std::cerr << "hlod " << command << ": " << e.what() << '\n';
        return 2;
    }
}

}  // namespace hlod::cli
