// The conventions every `hlod` subcommand follows, written once (README "Command line"):
// - exit status 0 on success, 1 when the data is invalid or the work fails (violations, a
//   corrupt blob, a failed write), 2 on a usage error or an input that cannot be read;
// - one error guard: an exception becomes ONE line "hlod SUBCOMMAND: FILE: problem" on stderr;
// - help texts start in lower case; a database argument is named DB; JSON keys are snake_case;
// - --set / --config accept exactly the thesis constants the subcommand uses (formats/constants.h).
#pragma once

#include "formats/constants.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <iosfwd>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace CLI {
class App;
class Validator;
}

namespace hlod::cli {

enum ExitStatus : int { kExitOk = 0, kExitInvalid = 1, kExitUsage = 2 };

// A subcommand adds itself to `app`; its callback stores its exit status in `status`.
using AddSubcommand = void (*)(CLI::App& app, int& status);

// Runs a subcommand body: returns its status, or prints one line "hlod COMMAND: what()" (its
// control characters, from a bad file's bytes, shown as '?') to
// stderr and returns the status of the exception (formats/errors.h): InputError,
// UnreadableDatabase and std::invalid_argument (usage) give 2; FormatError and any other
// failure give 1.
int runGuarded(const std::string& command, const std::function<int()>& body);

// Checks for numeric options. CLI11's own number checks let nan and inf through and print
// DBL_MAX as a bound, and an unsigned option wraps "-1" around, so every floating-point option of
// every subcommand takes one of the first four and every count option wholeNumber(); a value
// outside is a usage error (exit 2) naming the option and what it accepts.
CLI::Validator finiteNumber();                  // any finite number (a negative one may mean "the default")
CLI::Validator finiteAtLeast(double lo);        // a finite number >= lo
CLI::Validator finitePositive();                // a finite number > 0
CLI::Validator finiteIn(double lo, double hi);  // a finite number in [lo, hi]
CLI::Validator finiteAboveAtMost(double lo, double hi);  // a finite number in (lo, hi]
// A count written without a sign, at most `max` (a bigger one was CLI11's "Could not convert");
// wholeNumber(option) takes the bound from the option's type (V: CLI::Validator, complete where
// an option is added).
CLI::Validator wholeNumberUpTo(uint64_t max);
template <class T, class V = CLI::Validator>
V wholeNumber(const T&) {
    static_assert(std::is_integral_v<T>, "wholeNumber is for count options");
    return wholeNumberUpTo(std::numeric_limits<T>::max());
}
template <class T, class V = CLI::Validator>
V wholeNumber(const std::optional<T>&) {
    return wholeNumber(T{});
}
// " (default V)" for an option's help, V its value when the option is added (formatConstant).
std::string defaultText(double value);
CLI::Validator nonEmptyPath();                  // every -o: "" is a usage error, not a filesystem error

// The positional database argument, named DB in every subcommand.
void addDatabaseArgument(CLI::App& sub, std::string& path);

// --config FILE and --set NAME=VALUE (repeatable) for the constants `use` reads. A --set of a
// constant this subcommand does not use is a usage error naming the subcommands that do; a
// constants file may hold any constant (one file per experiment), and those this subcommand
// does not use are listed on one note line instead of being applied.
struct ConstantOptions {
    ConstantOptions(std::string commandName, ConstantUse used) : command(std::move(commandName)), use(used) {}
    std::string command;  // "build", "play", ...
    ConstantUse use;
    std::string configFile;
    std::vector<std::string> sets;
};
void addConstantOptions(CLI::App& sub, ConstantOptions& options);
// Folds the options into `c` and checks the result (validateConstants); notes go to `out`.
// Throws std::invalid_argument (usage: a bad --set, or a value out of range) or InputError (the
// constants file).
void applyConstantOptions(const ConstantOptions& options, Constants& c, std::ostream& out);

}  // namespace hlod::cli
