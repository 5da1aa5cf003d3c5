// Subcommands of the `hlod` tool (in the manner of git). Each library contributes its own
// subcommands; player/cli/main.cpp registers them all. A callback stores its exit status in
// `status` (0 success, 1 failure such as invalid data, 2 usage/input error).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hlod {
struct Constants;
}

namespace hlod::cli {

void addInspect(CLI::App& app, int& status);
void addValidate(CLI::App& app, int& status);

// Adds --config FILE and --set NAME=VALUE (repeatable) to `sub`; call applyConstantOptions()
// in the callback to fold them into `c` (throws with a one-line message on a bad value).
struct ConstantOptions {
    std::string configFile;
    std::vector<std::string> sets;
};
void addConstantOptions(CLI::App& sub, ConstantOptions& options);
void applyConstantOptions(const ConstantOptions& options, Constants& c);

// Runs a subcommand body: returns its status, or prints ONE line "hlod COMMAND: what()" to
// stderr and returns 2 when it throws a std::exception.
int runGuarded(const char* command, const std::function<int()>& body);

}  // namespace hlod::cli
