// The conventions of formats/cli/command.h: the error guard with its exit statuses, the DB
// argument, and the constant options (--config, --set) restricted to the constants a
// subcommand uses.
#include "formats/cli/command.h"

#include "formats/errors.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace hlod::cli {

namespace {

// The subcommands that read the constants of `use`.
std::string subcommandsUsing(ConstantUse use) {
    std::string out;
    if (use & kUsedByBuild) out += "build";
    if (use & kUsedByPlayer) out += std::string(out.empty() ? "" : ", ") + "play, view, compare";
    return out;
}

// The constant a "name=value" assignment sets, checked against what `options.use` reads.
void checkUsed(const ConstantOptions& options, const std::string& assignment) {
    const size_t eq = assignment.find('=');
    std::string name = assignment.substr(0, eq);
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    const ConstantInfo* info = findConstant(name);
    if (info && !(info->use & options.use))
        throw std::invalid_argument("--set " + name + ": `hlod " + options.command + "` does not use " + name +
                                    " (used by: " + subcommandsUsing(info->use) + ")");
}

// A validator accepting the finite numbers `accept` admits; `what` names them in the error and
// the help ("FLOAT:what").
CLI::Validator finiteWhere(const std::string& what, std::function<bool(double)> accept) {
    return CLI::Validator(
        [what, accept](std::string& input) {
            char* end = nullptr;
            const double v = std::strtod(input.c_str(), &end);
            if (input.empty() || *end != '\0' || !std::isfinite(v) || !accept(v))
                return "value '" + input + "': expected " + what;
            return std::string();
        },
        what);
}

std::string number(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

}  // namespace

CLI::Validator finiteNumber() {
    return finiteWhere("a finite number", [](double) { return true; });
}

CLI::Validator finiteAtLeast(double lo) {
    return finiteWhere("a finite number >= " + number(lo), [lo](double v) { return v >= lo; });
}

CLI::Validator finitePositive() {
    return finiteWhere("a finite number > 0", [](double v) { return v > 0; });
}

CLI::Validator finiteIn(double lo, double hi) {
    return finiteWhere("a finite number in [" + number(lo) + ", " + number(hi) + "]",
                       [lo, hi](double v) { return v >= lo && v <= hi; });
}

std::string defaultText(double value) { return " (default " + formatConstant(value) + ")"; }

CLI::Validator finiteAboveAtMost(double lo, double hi) {
    return finiteWhere("a finite number in (" + number(lo) + ", " + number(hi) + "]",
                       [lo, hi](double v) { return v > lo && v <= hi; });
}

CLI::Validator wholeNumberUpTo(uint64_t max) {
    return CLI::Validator(
        [max](std::string& input) {
            const size_t first = input.find_first_not_of(" \t");
            if (first == std::string::npos || !std::isdigit(static_cast<unsigned char>(input[first])))
                return "value '" + input + "': expected a whole number >= 0";
            const size_t end = input.find_last_not_of(" \t") + 1;
            const std::string digits = input.substr(first, end - first);
            if (digits.find_first_not_of("0123456789") != std::string::npos) return std::string();  // 512M: a size
            const std::string trimmed = digits.substr(std::min(digits.find_first_not_of('0'), digits.size() - 1));
            const std::string bound = std::to_string(max);
            if (trimmed.size() > bound.size() || (trimmed.size() == bound.size() && trimmed > bound))
                return "value '" + input + "': expected a whole number in [0, " + bound + "]";
            return std::string();
        },
        "");  // the help's UINT says it
}

CLI::Validator nonEmptyPath() {
    return CLI::Validator([](std::string& input) { return input.empty() ? std::string("an empty path") : std::string(); }, "");
}

namespace {
// "PATH: what failed (reason)" for a std::filesystem call no hlod check foresaw (the current
// folder deleted under the run; two runs renaming onto one folder), instead of libstdc++'s
// "filesystem error: cannot make absolute path: No such file or directory [PATH]".
std::string filesystemProblem(const std::filesystem::filesystem_error& e) {
    std::string what = e.what();
    const std::string prefix = "filesystem error: ", reason = e.code().message();
    if (what.starts_with(prefix)) what.erase(0, prefix.size());
    if (const size_t paths = what.find(" ["); paths != std::string::npos) what.erase(paths);
    if (what.ends_with(": " + reason)) what.erase(what.size() - reason.size() - 2);
    std::string path = e.path1().string();
    if (!e.path2().empty()) path += " -> " + e.path2().string();
    return (path.empty() ? "" : path + ": ") + what + " (" + reason + ")";
}
}  // namespace

namespace {

// What a subcommand wrote to standard output reached it, or the run failed: a full disk, `>&-`
// or a file-size limit left a cut JSON with status 0 (until stop 46). A failed write, status 1.
int checkStandardOutput(const std::string& command, int status) {
    errno = 0;
    std::cout.flush();
    if (std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good()) return status;
    const int error = errno;
    std::cerr << "hlod " << command << ": standard output: write failed"
              << (error ? std::string(" (") + std::strerror(error) + ")" : std::string()) << '\n';
    return status == kExitOk ? kExitInvalid : status;
}

}  // namespace

int runGuarded(const std::string& command, const std::function<int()>& body) {
    auto fail = [&](const std::exception& e, int status) {
        std::cerr << "hlod " << command << ": " << printableLine(e.what()) << '\n';
        return status;
    };
    try {
        return checkStandardOutput(command, body());
    } catch (const UnreadableDatabase& e) {
        return fail(e, kExitUsage);
    } catch (const FormatError& e) {
        return fail(e, kExitInvalid);
    } catch (const InputError& e) {
        return fail(e, kExitUsage);
    } catch (const std::invalid_argument& e) {
        return fail(e, kExitUsage);
    } catch (const std::filesystem::filesystem_error& e) {
        return fail(std::runtime_error(filesystemProblem(e)), kExitInvalid);
    } catch (const std::exception& e) {
        return fail(e, kExitInvalid);
    }
}

void addDatabaseArgument(CLI::App& sub, std::string& path) {
    sub.add_option("DB", path, "database file (.hlod)")->required()->check(nonEmptyPath());
}

void addConstantOptions(CLI::App& sub, ConstantOptions& options) {
    std::string names;
    for (const ConstantInfo& info : constantTable())
        if (info.use & options.use) names += std::string(names.empty() ? "" : ", ") + info.name;
    sub.add_option("--config", options.configFile,
                   "constants file of 'c_name = value' lines ('#' comments); this subcommand uses " + names);
    sub.add_option("--set", options.sets, "override a constant it uses (" + names + "), e.g. --set " +
                                              names.substr(0, names.find(',')) + "=VALUE (repeatable)")
        ->type_name("NAME=VALUE");
}

void applyConstantOptions(const ConstantOptions& options, Constants& c, std::ostream& out) {
    if (!options.configFile.empty()) {
        const std::vector<std::string> skipped = loadConstantsFile(c, options.configFile, options.use);
        if (!skipped.empty()) {
            out << "note: " << options.configFile << ": not used by `hlod " << options.command << "`:";
            for (const std::string& name : skipped) out << ' ' << name;
            out << '\n';
        }
    }
    for (const std::string& s : options.sets) {
        checkUsed(options, s);
        setConstantAssignment(c, s);
    }
    validateConstants(c, options.use);
}

}  // namespace hlod::cli
