// The frame's selection as a multiple-choice knapsack (T. A. Funkhouser and C. H. Séquin,
// "Adaptive Display Algorithm for Interactive Frame Rates During Visualization of Complex
// Virtual Environments", SIGGRAPH 1993, §3 eq. 1: maximise the sum of Benefit subject to the
// sum of Cost <= TargetFrameTime, one tuple per object), as plain data, and the solvers of the
// seed papers over it (player/SOLVERS.md):
//   fsGreedy       FS §6 greedy by value (fs_greedy.cpp)
//   fsIncremental  FS §6 incremental raise/lower from last frame's choice (fs_incremental.cpp)
//   robinHood      Hernández & Beneš 2005 ("Robin Hood's Algorithm for Time-Critical Level of
//                  Detail") §5, eqs 1-11 (robin_hood.cpp)
//   gbBarrier      Gobbetti & Bouvier 1999 ("Time-Critical Multiresolution Scene Rendering") §4-5,
//                  continuous resolutions by a barrier method (gb_barrier.cpp)
//   oracleChoice   the exact optimum by dynamic programming over non-dominated states with an
//                  LP bound (choice_oracle.cpp)
// Objects are blocks (their hlod0 roots); an object's options are its cuts at each depth (the
// faithful FS mapping, "levels of detail"), option 0 the block's hlod0 alone. The mapping from a
// skeleton and a view is in choice_map.cpp. No threads, no I/O, deterministic.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace hlod {

struct ChoiceOption {
    double cost = 0;        // ms: v_time x sum of the cut's node costs (+ per-pixel term)
    double benefit = 0;     // the benefit the solvers maximise (the common measure, or FS's own)
    double samples = 0;     // triangles of the cut: FS Samples(L, R), GB resolution r x n_max
    bool available = true;  // every node of the cut is resident
};

struct ChoiceObject {
    std::vector<ChoiceOption> options;  // by depth: 0 = hlod0 alone, then ever finer cuts
    uint32_t id = 0;                    // the block (hlod0 node id in the mapping)
    double pixels = 1;                  // projected area: FS Size(O), GB coverage, RH a_i
    double distance = 1;                // eye to object: RH z_i
    double importance = 1;              // semantics x focus (FS Importance x Focus, GB, RH I)
    double complexity = 0;              // RH's simple-to-complex order key (finest cut's cost)
};

struct ChoiceProblem {
    std::vector<ChoiceObject> objects;
    double budget = 0;        // ms the objects may cost together (target minus fixed overhead)
    bool allowSkip = false;   // FS skips objects; the thesis never skips hlod0 (default)
};

inline constexpr int32_t kSkipped = -1;

// One option per object (kSkipped: not drawn), with its totals.
struct Choice {
    std::vector<int32_t> level;
    double cost = 0;
    double benefit = 0;
    uint32_t iterations = 0;  // the solver's unit of work (tuples considered, Newton steps, DP states)
};

// Totals of `level` over `problem` (a skipped object adds nothing).
void totalChoice(const ChoiceProblem& problem, Choice& choice);
// The cheapest available option of an object (ties: the coarser), or kSkipped if none.
int32_t cheapestOption(const ChoiceObject& object);

// Cost and benefit of option `level` of an object (kSkipped: 0).
inline double optionCost(const ChoiceObject& o, int32_t level) { return level < 0 ? 0 : o.options[size_t(level)].cost; }
inline double optionBenefit(const ChoiceObject& o, int32_t level) {
    return level < 0 ? 0 : o.options[size_t(level)].benefit;
}
// Benefit gained per unit of cost going from option `from` to `to` (+inf when it costs nothing more).
inline double optionSlope(const ChoiceObject& o, int32_t from, int32_t to) {
    const double dc = optionCost(o, to) - optionCost(o, from), db = optionBenefit(o, to) - optionBenefit(o, from);
    return dc > 0 ? db / dc : std::numeric_limits<double>::infinity();
}
// The option every solution starts from: kSkipped when skipping is allowed, else the cheapest.
inline int32_t baseOption(const ChoiceProblem& p, const ChoiceObject& o) { return p.allowSkip ? kSkipped : cheapestOption(o); }
// The budget left when every object takes its base option (negative: even the bases do not fit).
double budgetAboveBases(const ChoiceProblem& problem);
// The upper convex hull of (cost, benefit) over an object's available options above `base`,
// dropping options that cost more than maxExtraCost over it or give no more benefit: option
// indices in increasing cost and benefit and decreasing slope (the base itself not included).
// The increments along it are the LP relaxation's (Sinha & Zoltners 1979, FS §6 [6]).
std::vector<int32_t> upperHull(const ChoiceObject& object, int32_t base, double maxExtraCost);

// ---- FS §5: Benefit(O, L, R) = Size x Accuracy x Importance x Focus x Motion x Hysteresis ----
struct FsBenefitFactors {
    double baseError = 0.5;  // FS §5 BaseError ("arbitrarily set to 0.5")
    double exponent = 1;     // FS §5 m: flat = 1 (Samples = polygons), Gouraud = 2 (vertices)
    double focusWeight = 0;  // Focus = 1 - focusWeight x (off-centre angle / half field of view)
    double motionWeight = 0; // Motion = 1 - motionWeight x (apparent speed / average polygon size)
    double hystWeight = 0;   // Hysteresis = 1 - hystWeight x |L - L_previous| / levels
};
struct FsObjectView {
    double pixels = 0;        // Size(O)
    double importance = 1;    // Importance(O), semantics
    double offCentre = 0;     // angle from the screen centre over the half field of view, >= 0
    double speedPx = 0;       // apparent speed, pixels per frame
    double polygonPx = 1;     // average polygon size, pixels
};
// FS §5 Accuracy = 1 - BaseError / Samples^m, Samples never more than #pixels.
double fsAccuracy(double samples, double pixels, const FsBenefitFactors& f);
double fsBenefit(const FsObjectView& o, double samples, int32_t level, int32_t previousLevel, int32_t levels,
                 const FsBenefitFactors& f);

// ---- FS §6 greedy ----
struct FsGreedyOptions {
    // The tuples' Value (FS §6: Benefit / Cost). Hull (default): values of the increments along
    // each object's upper convex hull of (cost, benefit), the form of the greedy whose
    // "at least half as good as the optimal solution" FS quote from [6]. Literal: each tuple's
    // own Benefit / Cost, taking tuples in that order and keeping the object's larger-benefit
    // tuple (FS's text); it has no such bound (tests/player/test_choice.cpp gives a 1/3 case).
    bool literal = false;
    // Also consider the best single tuple and keep it if better (the half-optimal guarantee).
    bool bestSingle = true;
};
Choice fsGreedy(const ChoiceProblem& problem, const FsGreedyOptions& options = {});

// ---- FS §6 incremental ----
struct FsIncrementalOptions {
    uint32_t maxIterations = 0;  // 0: 4 x the number of options (a cold start needs one per raise)
};
// Starts from `previous` (one level per object; a level out of range or unavailable starts at the
// cheapest option), raises the object whose next tuple has the highest value (hull increments, as
// fsGreedy's default), then lowers the lowest-value tuples until the cost fits; stops when the
// same tuple is raised and lowered in one iteration (FS §6).
Choice fsIncremental(const ChoiceProblem& problem, std::span<const int32_t> previous,
                     const FsIncrementalOptions& options = {});

// ---- fs-hold: FS §6's steps with symmetric hysteresis (choice_hold.cpp) ----
struct HoldOptions {
    double headroom = 0.05;  // raise only while the cost stays under budget x (1 - headroom); lower above budget
    double swapGain = 0.02;  // take fsGreedy's choice (under the same headroom) when its benefit is this much
                             // higher (fraction); < 0: never
};
// Keeps `previous` (one level per object; off the hull or unavailable: the dearest hull option
// that costs no more, a new object its base), lowers the lowest-Value increments while over the
// budget, raises the highest-Value ones while they fit under budget x (1 - headroom), then swaps
// to the greedy's choice if it is better by more than swapGain.
Choice holdChoice(const ChoiceProblem& problem, std::span<const int32_t> previous, const HoldOptions& options = {});

// ---- Robin Hood §5 ----
enum class RhValue { Eq8, Eq9, Eq10, Eq11 };
// eqs 8-11: v_i = a_i / sqrt(z_i) I, a_i / z_i I, a_i / z_i^2 I, sqrt(a_i / z_i^2) I
double rhValue(RhValue function, double area, double depth, double importance);
// eqs 5-7: l = (t_l / t_f)^2, rho = 1 - l, t_r = rho^2 t_f / C.
double rhRenderTime(double logicMs, double frameMs, double c);
// Least-squares C of eq. 7 over observations (t_l, t_f, t_r): 1/C = sum(rho^2 t_f t_r) / sum((rho^2 t_f)^2).
struct RhObservation {
    double logicMs, frameMs, renderMs;
};
double fitRhConstant(std::span<const RhObservation> observations);
struct RhOptions {
    RhValue value = RhValue::Eq8;  // the paper's §7.1 runs use eq. 8
    double frameMs = 0;            // t_f; 0: t_r = problem.budget (no logic-time estimate)
    double logicMs = 0;            // t_l
    double c = 1;                  // eq. 7 constant (player/SOLVERS.md "rh": what was fitted)
};
struct RhTrace {                   // per object in processing order, for tests and plots
    uint32_t object;
    double share;                  // t_i (eq. 2)
    double spent;                  // cost of the option taken
    double remainingBefore;        // t_r before this object
};
// Allocates t_r (eq. 7 from t_f, t_l, C; or problem.budget) in proportion to value, simple to complex.
Choice robinHood(const ChoiceProblem& problem, const RhOptions& options, std::vector<RhTrace>* trace = nullptr);

// ---- Gobbetti & Bouvier 1999 ----
struct GbOptions {
    double mu0 = 0;            // first barrier weight; 0: sum of importances / (2n+1) (REBUILT)
    double muFactor = 10;      // mu <- mu / muFactor per outer step (REBUILT: the digit was lost)
    double accuracy = 1e-6;    // stop when (2n+1) mu <= accuracy x sum of importances
    uint32_t maxNewton = 200;  // Newton steps in all (the time budget's stand-in in tests)
    double timeBudgetMs = 0;   // > 0: stop at the first outer step finished after this time
};
struct GbResult {
    std::vector<double> resolution;  // per object, in [r_min, 1] (1: the finest option)
    double benefit = 0;              // sum importance x accuracy(r) (the continuous objective)
    double mu = 0;                   // last barrier weight
    double certifiedGap = 0;         // dual bound - benefit (weak duality at the last iterate)
    uint32_t newtonSteps = 0;
    bool interior = true;            // false: r_min or r = 1 was the answer (no barrier run)
};
// The continuous problem: resolution r_i in [r_min_i, 1] with cost r_i x (finest available
// option's cost), r_min_i = cheapest option's cost / finest cost, n_i = finest option's samples,
// maximise sum importance_i x (1 - 1 / sqrt(r_i n_i)) subject to sum cost <= budget.
GbResult gbBarrier(const ChoiceProblem& problem, std::span<const double> warmStart, const GbOptions& options = {});
// Maps the resolutions onto the options: floor (the finest option whose cost <= r x finest
// cost), then a greedy fill of the leftover by the largest fractional part (player/SOLVERS.md "gb").
Choice gbRound(const ChoiceProblem& problem, std::span<const double> resolution);
// GB accuracy, REBUILT: 1 - 1 / sqrt(r n) (diminishing returns; "distance between samples").
double gbAccuracy(double resolution, double maxSamples);
// Independent exact optimum of the continuous problem: KKT water-filling by bisection on the
// Lagrange multiplier of the cost constraint.
std::vector<double> gbWaterFilling(const ChoiceProblem& problem);
double gbObjective(const ChoiceProblem& problem, std::span<const double> resolution);

// ---- the exact optimum ----
struct OracleOptions {
    size_t maxStates = 1'000'000;  // non-dominated states kept per object before giving up the proof
};
struct OracleResult {
    Choice choice;          // iterations: states kept in all
    bool proven = true;     // false: the state limit was hit; choice is the best found
    double upperBound = 0; // LP bound at the root (>= the optimum)
};
OracleResult oracleChoice(const ChoiceProblem& problem, const OracleOptions& options = {});

}  // namespace hlod
