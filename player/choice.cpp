// Totals and validity of a choice over the frame's multiple-choice knapsack (player/choice.h),
// and the benefit of T. A. Funkhouser and C. H. Séquin, SIGGRAPH 1993, §5.
#include "player/choice.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace hlod {

void totalChoice(const ChoiceProblem& problem, Choice& choice) {
    choice.cost = choice.benefit = 0;
    for (size_t i = 0; i < problem.objects.size(); ++i) {
        int32_t l = choice.level[i];
        if (l == kSkipped) continue;
        const ChoiceOption& o = problem.objects[i].options[size_t(l)];
        choice.cost += o.cost;
        choice.benefit += o.benefit;
    }
}

int32_t cheapestOption(const ChoiceObject& object) {
    int32_t best = kSkipped;
    for (size_t l = 0; l < object.options.size(); ++l)
        if (object.options[l].available && (best == kSkipped || object.options[l].cost < object.options[size_t(best)].cost))
            best = int32_t(l);
    return best;
}

double budgetAboveBases(const ChoiceProblem& p) {
    double left = p.budget;
    for (const ChoiceObject& o : p.objects) left -= optionCost(o, baseOption(p, o));
    return left;
}

std::vector<int32_t> upperHull(const ChoiceObject& o, int32_t base, double maxExtraCost) {
    double c0 = optionCost(o, base), b0 = optionBenefit(o, base);
    std::vector<int32_t> pts;
    for (size_t l = 0; l < o.options.size(); ++l) {
        const ChoiceOption& x = o.options[l];
        if (x.available && int32_t(l) != base && x.benefit > b0 && x.cost - c0 <= maxExtraCost) pts.push_back(int32_t(l));
    }
    std::sort(pts.begin(), pts.end(), [&](int32_t a, int32_t b) {
        const ChoiceOption &x = o.options[size_t(a)], &y = o.options[size_t(b)];
        return x.cost != y.cost ? x.cost < y.cost : x.benefit > y.benefit;
    });
    std::vector<int32_t> hull;
    double lastBenefit = b0;
    for (int32_t l : pts) {
        const ChoiceOption& x = o.options[size_t(l)];
        if (x.benefit <= lastBenefit) continue;  // costs no less, gives no more: dominated
        while (!hull.empty()) {
            int32_t a = hull.back(), q = hull.size() > 1 ? hull[hull.size() - 2] : base;
            double ca = optionCost(o, a), ba = optionBenefit(o, a), cq = optionCost(o, q), bq = optionBenefit(o, q);
            // a on or below the chord from its predecessor q to x: not on the upper hull
            if ((ba - bq) * (x.cost - cq) <= (x.benefit - bq) * (ca - cq)) hull.pop_back();
            else break;
        }
        hull.push_back(l);
        lastBenefit = x.benefit;
    }
    return hull;
}

// FS §5: Accuracy(O, L, R) = 1 - BaseError / Samples(L, R)^m, Samples never more than #pixels.
double fsAccuracy(double samples, double pixels, const FsBenefitFactors& f) {
    double s = std::max(1.0, std::min(samples, std::max(pixels, 1.0)));
    return 1 - f.baseError / std::pow(s, f.exponent);
}

// FS §5: Benefit = Size(O) x Accuracy(O, L, R) x Importance(O) x Focus(O) x Motion(O) x
// Hysteresis(O, L, R), each qualitative factor a multiplier in [0, 1] "reducing the benefit by an
// amount proportional to" its quantity (forms: player/SOLVERS.md).
double fsBenefit(const FsObjectView& o, double samples, int32_t level, int32_t previousLevel, int32_t levels,
                 const FsBenefitFactors& f) {
    auto unit = [](double x) { return std::clamp(x, 0.0, 1.0); };
    double focus = unit(1 - f.focusWeight * o.offCentre);
    double motion = unit(1 - f.motionWeight * o.speedPx / std::max(o.polygonPx, 1e-9));
    double hyst = 1;
    if (previousLevel != kSkipped && levels > 0)
        hyst = unit(1 - f.hystWeight * std::abs(level - previousLevel) / double(levels));
    return o.pixels * fsAccuracy(samples, o.pixels, f) * o.importance * focus * motion * hyst;
}

}  // namespace hlod
