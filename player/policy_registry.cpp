// The table of selection policies by name (player/policy.h "HOW TO ADD A POLICY").
#include "player/policy.h"

#include <cmath>
#include <limits>
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

// The values each setting name takes, whichever policy has it (the same name means the same kind
// of quantity in every policy). A value outside is refused before a run: a negative time or
// count, a flag of 5 or a state limit beyond size_t meant nothing (or crashed) before stop 36.
struct SettingRange {
    const char* setting;
    double low, high;  // inclusive
    bool whole;        // a whole number
    const char* says;
};

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kAboveZero = std::numeric_limits<double>::denorm_min();

const SettingRange kRanges[] = {
    {"allow_skip", 0, 1, true, "0 or 1"},
    {"best_single", 0, 1, true, "0 or 1"},
    {"fs_benefit", 0, 1, true, "0 or 1"},
    {"literal", 0, 1, true, "0 or 1"},
    {"pixel_ms", 0, kInf, false, ">= 0"},
    {"logic_ms", 0, kInf, false, ">= 0"},
    {"opt_ms", 0, kInf, false, ">= 0"},
    {"focus", 0, kInf, false, ">= 0"},
    {"motion", 0, kInf, false, ">= 0"},
    {"hysteresis", 0, kInf, false, ">= 0"},
    {"overrun", 0, kInf, false, ">= 0"},
    {"exchange_gain", 0, kInf, false, ">= 0"},
    {"swap_gain", -kInf, kInf, false, "any number (< 0: never swap)"},
    {"headroom", 0, std::nextafter(1.0, 0.0), false, "in [0, 1)"},
    {"pixels", 0, kInf, false, ">= 0 (0: full detail)"},
    {"tolerance", 0, kInf, false, ">= 0 (0: full detail)"},
    {"c", kAboveZero, kInf, false, "> 0"},
    {"accuracy", 0, kInf, false, ">= 0 (0: until max_newton)"},
    {"value", 8, 11, true, "8, 9, 10 or 11 (the paper's equations)"},
    {"max_newton", 1, 1e6, true, "a whole number in [1, 1000000]"},
    {"max_states", 1, 1e9, true, "a whole number in [1, 1e9]"},
};

const SettingRange* findRange(const std::string& setting) {
    for (const SettingRange& r : kRanges)
        if (setting == r.setting) return &r;
    return nullptr;
}

// Throws std::invalid_argument when the value of KEY ("P.setting") is outside its setting's range.
void checkRange(const std::string& key, const std::string& setting, double value) {
    const SettingRange* r = findRange(setting);
    if (!r) throw std::logic_error("policy setting '" + setting + "' has no range in player/policy_registry.cpp");
    if (value >= r->low && value <= r->high && (!r->whole || value == std::floor(value))) return;
    std::ostringstream s;
    s << "policy setting " << key << "=" << value << " must be " << r->says;
    throw std::invalid_argument(s.str());
}

}  // namespace

std::string policySettingRange(const std::string& setting) {
    const SettingRange* r = findRange(setting);
    return r ? r->says : "";
}

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
        checkRange(key, key.substr(key.find('.') + 1), value);
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
    std::istringstream settings(p->settings);
    for (std::string setting; settings >> setting;)
        if (auto it = options.values.find(name + "." + setting); it != options.values.end()) checkRange(it->first, setting, it->second);
    return p->make(options);
}

}  // namespace hlod
