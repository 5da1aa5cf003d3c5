// `hlod validate DB [--quick] [--json]`: reports every violated invariant of FORMAT.md
// §Invariants, one line each; exit 0 only when there is none, 1 when there are, 2 when the
// file cannot be opened as a database at all (formats/cli/command.h).
#include "formats/cli/subcommands.h"

#include "formats/json_text.h"
#include "formats/validate.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <iostream>

namespace hlod::cli {

namespace {

struct ValidateArgs {
    std::string path;
    bool quick = false;
    bool json = false;
    double boundsTolerance = ValidateOptions{}.boundsTolerance;
};

int runValidate(const ValidateArgs& a) {
    Database db = Database::open(a.path, false);  // the tree's violations listed, not thrown
    ValidateOptions o;
    o.quick = a.quick;
    o.boundsTolerance = a.boundsTolerance;
    std::vector<Violation> violations = validate(db, o);
    if (a.json) {
        nlohmann::json list = nlohmann::json::array();
        for (const Violation& v : violations)
            list.push_back({{"node", v.node == kNone ? nlohmann::json(nullptr) : nlohmann::json(v.node)},
                            {"message", v.message}});
        std::cout << jsonText({{"path", a.path}, {"valid", violations.empty()}, {"quick", a.quick}, {"violations", list}}, 2)
                  << '\n';
    } else {
        for (const Violation& v : violations) std::cout << a.path << ": " << v.message << '\n';
        const auto& s = db.skeleton();
        if (violations.empty())
            std::cout << a.path << ": valid (" << s.nodes.size() << " nodes, " << s.blobs.size() << " blobs"
                      << (a.quick ? ", blobs not decoded" : ", all blobs decoded") << ")\n";
        else
            std::cout << a.path << ": " << violations.size() << " violation(s)\n";
    }
    return violations.empty() ? kExitOk : kExitInvalid;
}

}  // namespace

void addValidate(CLI::App& app, int& status) {
    auto args = std::make_shared<ValidateArgs>();
    CLI::App* sub = app.add_subcommand("validate", "check every invariant of an HLOD database");
    addDatabaseArgument(*sub, args->path);
    sub->add_flag("--quick", args->quick, "skip reading and decoding blobs");
    sub->add_flag("--json", args->json, "machine-readable JSON output");
    sub->add_option("--bounds-tolerance", args->boundsTolerance,
                    "child bounds may exceed the parent's by this fraction of its diagonal")
        ->capture_default_str()
        ->check(finiteAtLeast(0));
    sub->callback([args, &status] { status = runGuarded("validate", [&] { return runValidate(*args); }); });
}

}  // namespace hlod::cli
