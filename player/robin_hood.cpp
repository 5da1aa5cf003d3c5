// Robin Hood's allocation, E. Hernández and B. Beneš, "Robin Hood's Algorithm for Time-Critical
// Level of Detail", 2005 (seed 004), §5. Each visible instance (here: block) gets a value (§5.4,
// eqs 8-11) and a share of the rendering time proportional to it (§5.2 eq. 2); instances are
// taken from simple to complex, each takes the most expensive representation that fits its
// share ("selects one representation which rendering time does not surpass t_i and minimizes the
// remaining time") and hands what it leaves to the instances after it (eqs 3-4, step 11). The
// rendering time comes from the frame time and the logic time by eqs 5-7.
#include "player/choice.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hlod {

double rhValue(RhValue f, double a, double z, double importance) {
    z = std::max(z, 1e-9);
    switch (f) {
    case RhValue::Eq8: return a / std::sqrt(z) * importance;        // eq. 8
    case RhValue::Eq9: return a / z * importance;                   // eq. 9
    case RhValue::Eq10: return a / (z * z) * importance;            // eq. 10
    case RhValue::Eq11: return std::sqrt(a / (z * z)) * importance; // eq. 11
    }
    return 0;
}

double rhRenderTime(double tl, double tf, double c) {
    double l = std::min(1.0, (tl / tf) * (tl / tf));  // eq. 5, "the maximum value of l is 1"
    double rho = 1 - l;                                // eq. 6
    return rho * rho * tf / c;                         // eq. 7
}

double fitRhConstant(std::span<const RhObservation> obs) {
    double num = 0, den = 0;  // minimise sum (k rho^2 t_f - t_r)^2 over k = 1/C
    for (const RhObservation& o : obs) {
        double x = rhRenderTime(o.logicMs, o.frameMs, 1);
        num += x * o.renderMs;
        den += x * x;
    }
    return num > 0 ? den / num : 1;
}

Choice robinHood(const ChoiceProblem& p, const RhOptions& opt, std::vector<RhTrace>* trace) {
    const size_t n = p.objects.size();
    Choice c;
    c.level.assign(n, kSkipped);
    // First cycle (steps 1-4): values, their total v_f (eq. 1), the rendering time t_r.
    std::vector<double> v(n);
    double vf = 0;
    for (size_t i = 0; i < n; ++i) {
        const ChoiceObject& o = p.objects[i];
        v[i] = rhValue(opt.value, o.pixels, o.distance, o.importance);
        vf += v[i];  // eq. 1
    }
    double tr = opt.frameMs > 0 ? rhRenderTime(opt.logicMs, opt.frameMs, opt.c) : p.budget;
    // Second cycle (steps 5-11), simple to complex.
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return p.objects[a].complexity < p.objects[b].complexity; });
    for (uint32_t i : order) {
        const ChoiceObject& o = p.objects[i];
        double ti = vf > 0 ? v[i] * tr / vf : 0;  // eq. 2 (the last instance gets all of t_r)
        double before = tr;
        tr -= ti;                                 // eq. 3
        vf -= v[i];                               // eq. 4
        int32_t pick = kSkipped;                  // the most expensive option within t_i
        for (size_t l = 0; l < o.options.size(); ++l)
            if (o.options[l].available && o.options[l].cost <= ti && (pick == kSkipped || o.options[l].cost > optionCost(o, pick)))
                pick = int32_t(l);
        // None fits: RH skips the instance ("rendered if this time is at least big enough for its
        // simplest acceptable representation"); hlod0 mandatory takes the cheapest and the
        // overrun is charged to the instances after it (negative remainder).
        if (pick == kSkipped && !p.allowSkip) pick = cheapestOption(o);
        double spent = optionCost(o, pick);
        tr += ti - spent;  // step 11: the remaining time, if any, back to t_r
        c.level[i] = pick;
        ++c.iterations;
        if (trace) trace->push_back({i, ti, spent, before});
    }
    totalChoice(p, c);
    return c;
}

}  // namespace hlod
