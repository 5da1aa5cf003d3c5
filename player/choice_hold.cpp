// Selection with symmetric hysteresis over the frame's multiple-choice knapsack (player/choice.h;
// the project's own policy `fs-hold`, player/DEFAULT_POLICY.md). It keeps last
// frame's choice and changes it only when it must or when it gains enough:
//  - lower: while the cost exceeds the budget, lower the object whose current increment has the
//    lowest Value (Funkhouser & Séquin 1993 §6, the decrement step of their incremental
//    optimisation: "decrements the accuracy attributes of the object tuples with the lowest
//    current Value until the cumulative cost ... is less than the target frame time");
//  - raise: while an increment fits under budget x (1 - headroom), raise the object whose next
//    increment has the highest Value (FS §6, the increment step). A raised object is lowered
//    again only after the cost has grown by the headroom: the dead band is the hysteresis, the
//    same on the way up and on the way down;
//  - swap: when FS's greedy (§6, fsGreedy) under budget x (1 - headroom) beats the held choice
//    by more than `swapGain` of its benefit, take the greedy's choice (bounds the drift from the
//    optimum that holding allows).
// Values are the increments along each object's upper convex hull above its base, as fsGreedy's
// and fsIncremental's.
#include "player/choice.h"

#include <algorithm>
#include <limits>

namespace hlod {
Choice holdChoice(const ChoiceProblem& p, std::span<const int32_t> previous, const HoldOptions& opt) {
    const size_t n = p.objects.size();
    const double raiseTo = p.budget * (1 - opt.headroom);
    const double room = budgetAboveBases(p);
    std::vector<std::vector<int32_t>> ladder(n);  // rung 0: the base, then the hull's options
    for (size_t i = 0; i < n; ++i) {
        ladder[i].push_back(baseOption(p, p.objects[i]));
        for (int32_t l : upperHull(p.objects[i], ladder[i][0], std::max(room, 0.0))) ladder[i].push_back(l);
    }
    // From `levels` (last frame's, or the greedy's): each object on the dearest rung that costs no
    // more than its level (a new object: the base; a non-resident option: the dearest resident rung
    // under it), then lowered while over the budget and raised while under budget x (1 - headroom).
    auto settle = [&](std::span<const int32_t> levels) {
        std::vector<uint32_t> at(n, 0);
        double cost = 0;
        for (size_t i = 0; i < n; ++i) {
            const ChoiceObject& o = p.objects[i];
            int32_t l = i < levels.size() ? levels[i] : kSkipped;
            if (l >= 0 && size_t(l) < o.options.size())
                for (uint32_t k = 1; k < ladder[i].size(); ++k)
                    if (optionCost(o, ladder[i][k]) <= optionCost(o, l)) at[i] = k;
            cost += optionCost(o, ladder[i][at[i]]);
        }
        auto move = [&](size_t i, int step) {
            cost -= optionCost(p.objects[i], ladder[i][at[i]]);
            at[i] = uint32_t(int(at[i]) + step);
            cost += optionCost(p.objects[i], ladder[i][at[i]]);
        };
        uint32_t steps = 0;
        while (cost > p.budget) {  // lower: the lowest-Value current increment first (FS §6)
            size_t worst = n;
            double value = std::numeric_limits<double>::infinity();
            for (size_t i = 0; i < n; ++i)
                if (at[i] > 0) {
                    double v = optionSlope(p.objects[i], ladder[i][at[i] - 1], ladder[i][at[i]]);
                    if (v < value) value = v, worst = i;
                }
            if (worst == n) break;  // every object at its base
            move(worst, -1), ++steps;
        }
        for (;;) {  // raise: the highest-Value next increment that fits under the headroom (FS §6)
            size_t best = n;
            double value = -std::numeric_limits<double>::infinity();
            for (size_t i = 0; i < n; ++i) {
                if (at[i] + 1 >= ladder[i].size()) continue;
                const ChoiceObject& o = p.objects[i];
                double dc = optionCost(o, ladder[i][at[i] + 1]) - optionCost(o, ladder[i][at[i]]);
                double v = optionSlope(o, ladder[i][at[i]], ladder[i][at[i] + 1]);
                if (cost + dc <= raiseTo && v > value) value = v, best = i;
            }
            if (best == n) break;
            move(best, +1), ++steps;
        }
        Choice c;
        for (size_t i = 0; i < n; ++i) c.level.push_back(ladder[i][at[i]]);
        totalChoice(p, c);
        c.iterations = steps;
        return c;
    };
    Choice held = settle(previous);
    if (opt.swapGain >= 0) {  // the greedy's choice under the headroom, settled the same way
        ChoiceProblem tight = p;
        tight.budget = raiseTo;
        Choice greedy = settle(fsGreedy(tight, {}).level);
        if (greedy.benefit > held.benefit * (1 + opt.swapGain)) {
            greedy.iterations += held.iterations;
            return greedy;
        }
    }
    return held;
}

}  // namespace hlod
