// Selection policies: the one interface through which the Player asks "which front this frame"
// (player/POLICIES.md). A policy chooses the front (a valid cut, player/front.h checkCut: no
// drawn node an ancestor of another, every drawn node resident, every visible root-to-leaf path
// meeting exactly one drawn node unless it sets PolicyFront::skipsBlocks), fills the priorities
// the loader uses (SelectionState::nodes[id].priority of every id it lists in
// PolicyFront::visited; level > 0 nodes are requested in that order, §4.3), and observes the
// measured frame time. Roles and §6.5 toggles are counted by the Player for every policy alike
// (accountFront); a policy never sets roles.
//
// HOW TO ADD A POLICY
//  1. Write a class deriving from SelectionPolicy in its own player/policy_NAME.cpp (header
//     comment naming the paper, section and equations), with a factory
//        std::unique_ptr<SelectionPolicy> makeNamePolicy(const PolicyOptions& options);
//     reading its settings with options.get("NAME.setting", default).
//  2. Declare the factory in player/policy_registry.cpp and add one row to the kPolicies
//     table there (solvers: below the "Solvers" marker lines): {"name", "one-line summary", "setting1 setting2", makeNamePolicy}.
//     The name is what `hlod play --policy` and `hlod compare --policies` accept. A setting name
//     that is new needs its range in kRanges there too (values outside it are refused).
//  3. Add the .cpp to player/CMakeLists.txt, its open choices to player/POLICIES.md, and a test
//     that its fronts pass checkCut (tests/player/test_policies.cpp) and of its defining property.
// select() may use frame.evaluate (the thesis §4.2 priority and frustumVis of a node) for the
// loader's priorities, and reads the budget as frame.targetMs, the cost estimate of a node as
// frame.vTime x cost_n (+ frame.overheadMs per frame), and the common benefit through
// frame.projection (player/benefit.h).
#pragma once

#include "formats/constants.h"
#include "formats/db.h"
#include "player/benefit.h"
#include "player/front.h"
#include "player/selection.h"

#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace hlod {

// What the Player tells a policy about this frame (read-only).
struct PolicyFrame {
    const Skeleton& skeleton;
    const Constants& constants;
    const Camera& camera;
    const View& view;                 // §4.2 view: eye, look-ahead point, frustum planes
    const Projection& projection;     // pixels of the viewport (player/benefit.h)
    const Evaluate& evaluate;         // §4.2 priority and frustumVis of one node
    std::span<const uint8_t> resident;
    uint64_t frame = 0;
    double targetMs = 0;              // c_targetTime
    double overheadMs = 0;            // fixed per-frame overhead (measured or calibrated)
    double vTime = 0;                 // ms per unit of cost_n, first feedback loop (before this frame's update)
    double hlod0ShareMs = 0;          // second feedback loop's shareTime of the hlod0 nodes
    bool requireLoadedChildren = false;  // §5.2 option
    double initialHyst = 0;           // first hysteresis counter of a node (player/SELECTION.md)
};

// What the Player measured after drawing the policy's front.
struct FrameOutcome {
    double actualMs = 0;     // measured (or modelled) frame time
    double estimateMs = 0;   // overhead + v_time x drawn cost, v_time before its update
    double targetMs = 0;
    double drawnCost = 0;    // sum of cost_n drawn
    double vTime = 0;        // v_time after this frame's update
};

// Numeric settings of the policies, "policy.setting" -> value (`--policy-set` of the CLI).
struct PolicyOptions {
    std::map<std::string, double> values;
    double get(const std::string& key, double fallback) const;
};

class SelectionPolicy {
public:
    virtual ~SelectionPolicy() = default;
    virtual const char* name() const = 0;
    // Chooses this frame's front. May update per-node state (priority, frustumVis, hyst,
    // timeSlice); must not set roles and must not advance state.frame.
    virtual PolicyFront select(const PolicyFrame& frame, SelectionState& state) = 0;
    // Called once per frame after the draw, before the next select().
    virtual void observe(const FrameOutcome&) {}
};

struct PolicyInfo {
    const char* name;
    const char* summary;
    const char* settings;  // space-separated setting names, each used as "name.setting"
    std::unique_ptr<SelectionPolicy> (*make)(const PolicyOptions&);
};

// Every registered policy, in registration order (the order policyNamesList and the help texts give).
std::span<const PolicyInfo> policyRegistry();
// The named policy; std::invalid_argument (naming the known ones) for an unknown name.
std::unique_ptr<SelectionPolicy> makePolicy(const std::string& name, const PolicyOptions& options = {});
// Throws std::invalid_argument when a key of `options` is not "P.setting" of one of `names`, or
// its value is outside the setting's range (policySettingRange). makePolicy checks the ranges of
// its own settings too.
void checkPolicySettings(std::span<const std::string> names, const PolicyOptions& options);
// What values a setting name ("max_states", the part after "P.") takes, e.g. "> 0"; "" for a
// name no policy has.
std::string policySettingRange(const std::string& setting);
std::string policyNamesList();  // "thesis, thesis-rh, none, ..."
// "P.NAME=VALUE" strings (`--policy-set`) as options; std::invalid_argument on a malformed one.
PolicyOptions parsePolicySettings(std::span<const std::string> settings);

}  // namespace hlod
