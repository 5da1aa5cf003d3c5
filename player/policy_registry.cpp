// The table of selection policies by name (player/policy.h "HOW TO ADD A POLICY").
#include "player/policy.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hlod {

std::unique_ptr<SelectionPolicy> makeThesisPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeThesisRhPolicy(const PolicyOptions& options);
// Baselines and screen-space error (player/policy_baselines.cpp, player/policy_sse.cpp).
std::unique_ptr<SelectionPolicy> makeNonePolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeStaticPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeFeedbackPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeSsePolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeSseBudgetPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeNodeHoldPolicy(const PolicyOptions& options);  // player/policy_hold.cpp

// Solvers over blocks x levels (player/choice.h): declare their factories below this line.
std::unique_ptr<SelectionPolicy> makeFsGreedyPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeFsIncrementalPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeHoldPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeRhPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeGbPolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeOraclePolicy(const PolicyOptions& options);
std::unique_ptr<SelectionPolicy> makeFsNodePolicy(const PolicyOptions& options);  // player/policy_fs_node.cpp
std::unique_ptr<SelectionPolicy> makeFsNodeIncrementalPolicy(const PolicyOptions& options);


namespace {

const PolicyInfo kPolicies[] = {
    {"thesis", "the thesis engine: time slices (eq. 4.1), hysteresis, cumHyst (§4.2)", "", makeThesisPolicy},
    {"thesis-rh", "thesis with unused slices passed on to the next siblings (§6.6 future work; Robin Hood §5)", "",
     makeThesisRhPolicy},
    // Baselines and screen-space error.
    {"none", "everything at full detail: every visible leaf (FS 1993 §7 a)", "", makeNonePolicy},
    {"static", "highest level whose average triangle covers >= N pixels (FS 1993 §7 b)", "pixels", makeStaticPolicy},
    {"feedback", "static with N scaled by last frame's actual / target (FS 1993 §7 c)", "pixels", makeFeedbackPolicy},
    {"sse", "refine while projected geometric error > tolerance pixels (3D Tiles, Nexus)", "tolerance", makeSsePolicy},
    {"sse-budget", "sse with the tolerance scaled by sqrt(actual / target) each frame", "tolerance", makeSseBudgetPolicy},
    {"hold", "the thesis traversal with kept refine flags changed by FS 1993 §6 raise/lower steps in a dead band",
     "headroom overrun exchange_gain", makeNodeHoldPolicy},

    // Solvers over blocks x levels (player/choice.h): their rows go below this line.
    {"fs-greedy", "Funkhouser & Sequin 1993 §6 greedy by value over blocks x cuts, + best single tuple",
     "allow_skip pixel_ms fs_benefit focus motion hysteresis literal best_single", makeFsGreedyPolicy},
    {"fs-incremental", "Funkhouser & Sequin 1993 §6 incremental raise/lower from last frame's cuts",
     "allow_skip pixel_ms fs_benefit focus motion hysteresis", makeFsIncrementalPolicy},
    {"fs-node", "Funkhouser & Sequin 1993 §6 greedy by value over front nodes: refine the node of highest value",
     "allow_skip pixel_ms best_single", makeFsNodePolicy},
    {"fs-node-inc", "Funkhouser & Sequin 1993 §6 incremental over front nodes: refine/merge from last frame's front",
     "allow_skip pixel_ms", makeFsNodeIncrementalPolicy},
    {"fs-hold", "FS 1993 §6 raise/lower from last frame's cuts with a symmetric dead band, + a swap to the greedy's",
     "allow_skip pixel_ms headroom swap_gain", makeHoldPolicy},
    {"rh", "Robin Hood (Hernandez & Benes) §5: time shared by value, remainders passed simple to complex",
     "allow_skip pixel_ms value c logic_ms", makeRhPolicy},
    {"gb", "Gobbetti & Bouvier 1999: continuous resolutions by a barrier method, rounded onto the cuts",
     "allow_skip pixel_ms opt_ms accuracy max_newton", makeGbPolicy},
    {"oracle", "the exact optimum of blocks x cuts (dynamic programming over non-dominated states, LP bound): a yardstick",
     "allow_skip pixel_ms max_states", makeOraclePolicy},

};

}  // namespace

double PolicyOptions::get(const std::string& key, double fallback) const {
    auto it = values.find(key);
    return it == values.end() ? fallback : it->second;
}

std::span<const PolicyInfo> policyRegistry() { return kPolicies; }

std::string policyNamesList() {
    std::string s;
    for (const PolicyInfo& p : kPolicies) s += (s.empty() ? "" : ", ") + std::string(p.name);
    return s;
}

static const PolicyInfo* findPolicy(const std::string& name) {
    for (const PolicyInfo& p : kPolicies)
        if (name == p.name) return &p;
    return nullptr;
}

void checkPolicySettings(std::span<const std::string> names, const PolicyOptions& options) {
    for (const auto& [key, value] : options.values) {
        bool known = false;
        for (const std::string& name : names) {
            const PolicyInfo* p = findPolicy(name);
            if (!p || key.rfind(name + ".", 0) != 0) continue;
            std::istringstream settings(p->settings);
            for (std::string setting; settings >> setting;) known |= key.substr(name.size() + 1) == setting;
        }
        if (!known) throw std::invalid_argument("unknown policy setting '" + key + "' for the chosen policies");
    }
}

PolicyOptions parsePolicySettings(std::span<const std::string> settings) {
    PolicyOptions options;
    for (const std::string& text : settings) {
        size_t eq = text.find('=');
        size_t used = 0;
        double value = 0;
        try {
            if (eq != std::string::npos) value = std::stod(text.substr(eq + 1), &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (eq == std::string::npos || text.find('.') > eq || used == 0 || used != text.size() - eq - 1 ||
            !std::isfinite(value))
            throw std::invalid_argument("--policy-set '" + text + "': expected POLICY.SETTING=NUMBER (a finite number)");
        options.values[text.substr(0, eq)] = value;
    }
    return options;
}

std::unique_ptr<SelectionPolicy> makePolicy(const std::string& name, const PolicyOptions& options) {
    const PolicyInfo* p = findPolicy(name);
    if (!p) throw std::invalid_argument("unknown policy '" + name + "' (known: " + policyNamesList() + ")");
    return p->make(options);
}

}  // namespace hlod
