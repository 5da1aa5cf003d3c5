// Test fixture: random multiple-choice knapsack instances (player/choice.h) for the solver tests
// and the selection benchmark, seeded, so every run sees the same instances; and the references
// the solvers are checked against (validity, every combination).
#pragma once

#include "player/choice.h"

#include <algorithm>
#include <random>
#include <vector>

namespace hlod::test {

struct RandomChoiceSpec {
    uint32_t objects = 6;
    uint32_t maxOptions = 4;      // 1..maxOptions options per object
    bool concave = false;         // benefit increments fall with cost (FS's "diminishing returns")
    double unavailable = 0;       // probability that an option above 0 is not resident
    bool allowSkip = false;
    double budgetPosition = -1;   // in [0, 1] between the bases' cost and the finest cost; < 0: random
};

// Options of increasing cost (finer cuts cost more); benefits random (or concave), positive.
inline ChoiceProblem randomChoiceProblem(std::mt19937_64& rng, const RandomChoiceSpec& spec) {
    std::uniform_real_distribution<double> u(0, 1);
    ChoiceProblem p;
    p.allowSkip = spec.allowSkip;
    double minCost = 0, maxCost = 0;
    for (uint32_t i = 0; i < spec.objects; ++i) {
        ChoiceObject o;
        o.id = i;
        o.pixels = 100 + 10000 * u(rng);
        o.distance = 1 + 200 * u(rng);
        o.importance = 0.5 + u(rng);
        uint32_t k = 1 + uint32_t(u(rng) * spec.maxOptions) % spec.maxOptions;
        double cost = 0.1 + u(rng), benefit = 1 + 10 * u(rng), slope = 0.5 + 5 * u(rng), samples = 100;
        for (uint32_t l = 0; l < k; ++l) {
            ChoiceOption x;
            x.cost = cost;
            x.benefit = benefit;
            x.samples = samples;
            x.available = l == 0 || u(rng) >= spec.unavailable;
            o.options.push_back(x);
            double dc = 0.2 + 3 * u(rng);
            cost += dc;
            samples *= 4;
            if (spec.concave) {
                slope *= 0.2 + 0.7 * u(rng);
                benefit += slope * dc;
            } else {
                benefit = std::max(0.5, benefit + 12 * (u(rng) - 0.3));
            }
        }
        o.complexity = o.options.back().cost;
        minCost += o.options[0].cost;
        maxCost += o.options.back().cost;
        p.objects.push_back(std::move(o));
    }
    double t = spec.budgetPosition >= 0 ? spec.budgetPosition : u(rng);
    p.budget = (spec.allowSkip ? 0 : minCost) + t * (maxCost - (spec.allowSkip ? 0 : minCost));
    return p;
}

// Every level names an available option (or kSkipped where skipping is allowed, or where the
// object has no available option at all).
inline bool choiceIsValid(const ChoiceProblem& problem, const Choice& choice) {
    if (choice.level.size() != problem.objects.size()) return false;
    for (size_t i = 0; i < problem.objects.size(); ++i) {
        const ChoiceObject& o = problem.objects[i];
        int32_t l = choice.level[i];
        if (l == kSkipped) {
            if (!problem.allowSkip && cheapestOption(o) != kSkipped) return false;
            continue;
        }
        if (l < 0 || size_t(l) >= o.options.size() || !o.options[size_t(l)].available) return false;
    }
    return true;
}

// The best of every combination (at most ~10^7 of them), the exact solvers' reference.
inline Choice bruteForceChoice(const ChoiceProblem& p) {
    const size_t n = p.objects.size();
    std::vector<std::vector<int32_t>> alts(n);
    for (size_t i = 0; i < n; ++i) {
        const ChoiceObject& o = p.objects[i];
        if (p.allowSkip || cheapestOption(o) == kSkipped) alts[i].push_back(kSkipped);
        for (size_t l = 0; l < o.options.size(); ++l)
            if (o.options[l].available) alts[i].push_back(int32_t(l));
    }
    Choice best, c;
    for (const ChoiceObject& o : p.objects) best.level.push_back(baseOption(p, o));  // when nothing fits
    totalChoice(p, best);
    bool found = false;
    std::vector<size_t> idx(n, 0);
    c.level.resize(n);
    for (;;) {
        for (size_t i = 0; i < n; ++i) c.level[i] = alts[i][idx[i]];
        totalChoice(p, c);
        if (c.cost <= p.budget && (!found || c.benefit > best.benefit)) {
            best = c;
            found = true;
        }
        size_t i = 0;
        while (i < n && ++idx[i] == alts[i].size()) idx[i++] = 0;
        if (i == n) break;
    }
    return best;
}

}  // namespace hlod::test
