// Greedy selection by value, T. A. Funkhouser and C. H. Séquin, "Adaptive Display Algorithm for
// Interactive Frame Rates During Visualization of Complex Virtual Environments", SIGGRAPH 1993,
// §6: "add object tuples to S in descending order of Value (Benefit / Cost) until the maximum
// cost is completely claimed ... only the object tuple with the maximum benefit of the two is
// retained". Two readings (player/SOLVERS.md "fs-greedy"):
// - hull (default): each object's tuples reduced to the upper convex hull of (cost, benefit)
//   above its base (the cheapest option, or nothing when skipping is allowed), the increments
//   taken in descending value until the first that does not fit. With the best single tuple also
//   considered this is at least half the optimum (FS §6, "at least half as good as the optimal
//   solution [6]": the LP relaxation is the taken prefix plus a fraction of the first increment
//   that did not fit, and that increment's tuple alone is a feasible solution).
// - literal: tuples in descending Benefit / Cost, each replacing its object's tuple when its
//   benefit is larger, until the first that does not fit. No constant bound holds for it.
#include "player/choice.h"

#include <algorithm>
#include <limits>

namespace hlod {
namespace {

struct Step {
    uint32_t object;
    int32_t to;      // option taken by this step
    double dc;       // cost over the object's previous hull option (hull reading)
    double value;    // FS §6 Value of the step
    uint32_t order;  // position along the object's hull (keeps ties in order)
};

double valueOf(double db, double dc) { return dc > 0 ? db / dc : std::numeric_limits<double>::infinity(); }

bool byValue(const Step& a, const Step& b) {
    if (a.value != b.value) return a.value > b.value;
    if (a.object != b.object) return a.object < b.object;
    return a.order < b.order;
}

// The best solution with one object above its base: the "best single item" of the bound.
Choice bestSingle(const ChoiceProblem& p, const std::vector<int32_t>& base, double left) {
    Choice single;
    single.level = base;
    double best = 0;
    for (uint32_t i = 0; i < p.objects.size(); ++i) {
        const ChoiceObject& o = p.objects[i];
        for (size_t l = 0; l < o.options.size(); ++l) {
            const ChoiceOption& x = o.options[l];
            double db = x.benefit - optionBenefit(o, base[i]);
            if (x.available && x.cost - optionCost(o, base[i]) <= left && db > best) {
                best = db;
                single.level = base;
                single.level[i] = int32_t(l);
            }
        }
    }
    totalChoice(p, single);
    return single;
}

}  // namespace

Choice fsGreedy(const ChoiceProblem& p, const FsGreedyOptions& opt) {
    Choice c;
    for (const ChoiceObject& o : p.objects) c.level.push_back(baseOption(p, o));
    const std::vector<int32_t> base = c.level;
    const double leftAtBase = budgetAboveBases(p);
    double left = leftAtBase;
    std::vector<Step> steps;
    for (uint32_t i = 0; i < p.objects.size(); ++i) {
        const ChoiceObject& o = p.objects[i];
        if (!opt.literal) {
            double pc = optionCost(o, base[i]), pb = optionBenefit(o, base[i]);
            std::vector<int32_t> hull = upperHull(o, base[i], left);
            for (uint32_t k = 0; k < hull.size(); ++k) {
                const ChoiceOption& x = o.options[size_t(hull[k])];
                steps.push_back({i, hull[k], x.cost - pc, valueOf(x.benefit - pb, x.cost - pc), k});
                pc = x.cost;
                pb = x.benefit;
            }
            continue;
        }
        for (size_t l = 0; l < o.options.size(); ++l) {  // literal: every tuple that can fit at all
            const ChoiceOption& x = o.options[l];
            if (x.available && int32_t(l) != base[i] && x.cost - optionCost(o, base[i]) <= left)
                steps.push_back({i, int32_t(l), 0, valueOf(x.benefit, x.cost), 0});  // the tuple's own value
        }
    }
    std::sort(steps.begin(), steps.end(), byValue);
    for (const Step& s : steps) {
        const ChoiceObject& o = p.objects[s.object];
        int32_t& cur = c.level[s.object];
        ++c.iterations;
        if (opt.literal && optionBenefit(o, s.to) <= optionBenefit(o, cur)) continue;  // keep the larger benefit
        double dc = opt.literal ? optionCost(o, s.to) - optionCost(o, cur) : s.dc;
        if (dc > left) break;  // "until the maximum cost is completely claimed"
        left -= dc;
        cur = s.to;
    }
    totalChoice(p, c);
    if (opt.bestSingle) {
        Choice single = bestSingle(p, base, leftAtBase);
        if (single.benefit > c.benefit) {
            single.iterations = c.iterations;
            c = std::move(single);
        }
    }
    return c;
}

}  // namespace hlod
