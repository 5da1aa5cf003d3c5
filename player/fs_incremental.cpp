// Incremental optimisation, T. A. Funkhouser and C. H. Séquin, "Adaptive Display Algorithm for
// Interactive Frame Rates During Visualization of Complex Virtual Environments", SIGGRAPH 1993,
// §6: "each object is assigned the LOD chosen in the previous frame, or the lowest LOD if the
// object is newly visible. In each iteration, the algorithm first increments the accuracy
// attribute of the object that has the highest subsequent Value. It then decrements the
// accuracy attributes of the object tuples with the lowest current Value until the cumulative
// cost of all object tuples in S is less than the target frame time. The algorithm terminates
// when the same accuracy attribute of the same object tuple is both incremented and decremented
// in the same iteration." Values are those of the increments along each object's upper convex
// hull (as fsGreedy's default), so that a tuple's Value falls as its accuracy rises (FS's
// "diminishing returns" condition) and the fixed point is the greedy's taken prefix; as in the
// greedy, tuples that cannot fit even with every other object at its base are left out.
#include "player/choice.h"

#include <limits>

namespace hlod {
namespace {

struct Ladder {
    std::vector<int32_t> rung;  // rung 0: the base, then the hull's options
    uint32_t at = 0;
};

}  // namespace

Choice fsIncremental(const ChoiceProblem& p, std::span<const int32_t> previous, const FsIncrementalOptions& opt) {
    const size_t n = p.objects.size();
    std::vector<Ladder> ladders(n);
    double cost = 0, room = budgetAboveBases(p);
    size_t options = 0;
    for (size_t i = 0; i < n; ++i) {
        const ChoiceObject& o = p.objects[i];
        Ladder& L = ladders[i];
        L.rung.push_back(baseOption(p, o));
        for (int32_t l : upperHull(o, L.rung[0], room)) L.rung.push_back(l);  // tuples that can fit at all
        options += L.rung.size();
        // last frame's tuple, or the nearest hull rung below it in cost; the base if new
        int32_t prev = i < previous.size() ? previous[i] : kSkipped;
        if (prev >= 0 && size_t(prev) < o.options.size() && o.options[size_t(prev)].available)
            for (uint32_t k = 1; k < L.rung.size(); ++k)
                if (optionCost(o, L.rung[k]) <= o.options[size_t(prev)].cost) L.at = k;
        cost += optionCost(o, L.rung[L.at]);
    }
    uint32_t maxIterations = opt.maxIterations ? opt.maxIterations : uint32_t(4 * options + 4);
    Choice c;
    for (c.iterations = 0; c.iterations < maxIterations; ++c.iterations) {
        // increment the object with the highest subsequent Value
        size_t up = n;
        double best = -std::numeric_limits<double>::infinity();
        for (size_t i = 0; i < n; ++i) {
            const Ladder& L = ladders[i];
            if (L.at + 1 >= L.rung.size()) continue;
            double v = optionSlope(p.objects[i], L.rung[L.at], L.rung[L.at + 1]);
            if (v > best) best = v, up = i;
        }
        if (up < n) {
            Ladder& L = ladders[up];
            cost += optionCost(p.objects[up], L.rung[L.at + 1]) - optionCost(p.objects[up], L.rung[L.at]);
            ++L.at;
        }
        // decrement the lowest current Values until the cost fits
        bool undone = false;
        while (cost > p.budget) {
            size_t down = n;
            double worst = std::numeric_limits<double>::infinity();
            for (size_t i = 0; i < n; ++i) {
                const Ladder& L = ladders[i];
                if (L.at == 0) continue;
                double v = optionSlope(p.objects[i], L.rung[L.at - 1], L.rung[L.at]);
                if (v < worst || (v == worst && i == up)) worst = v, down = i;
            }
            if (down == n) break;  // every object at its base: the bases alone exceed the budget
            Ladder& L = ladders[down];
            cost -= optionCost(p.objects[down], L.rung[L.at]) - optionCost(p.objects[down], L.rung[L.at - 1]);
            --L.at;
            if (down == up && !undone) undone = true;
        }
        if (up == n || undone) {
            ++c.iterations;
            break;
        }
    }
    for (const Ladder& L : ladders) c.level.push_back(L.rung[L.at]);
    totalChoice(p, c);
    return c;
}

}  // namespace hlod
