// Test fixture: random multiple-choice knapsack instances (player/choice.h) for the solver tests
// and the selection benchmark. Seeded, so every run sees the same instances.
#pragma once

#include "player/choice.h"

#include <algorithm>
#include <random>

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

}  // namespace hlod::test
