// Continuous resolutions by a barrier method, E. Gobbetti and E. Bouvier, "Time-Critical
// Multiresolution Scene Rendering", IEEE Visualization 1999, §4-5 (seed 001). Our copy of the
// paper lost its digits and formulas; every formula marked REBUILT is reconstructed from the
// surviving words and standard barrier-method theory (S. Boyd and L. Vandenberghe, Convex
// Optimization, 2004, §11.2-11.3; player/SOLVERS.md "gb" lists each with its evidence).
// Per visible object i: resolution r_i, cost linear in r_i above r_min_i (§4.1), benefit =
// importance_i x accuracy(r_i) with diminishing returns (§4.2); maximised subject to the frame's
// cost by sequential unconstrained minimisation of a logarithmic barrier with Newton steps (§5),
// warm-started from last frame's resolutions, stopped by the time budget or when the
// sub-optimality bound (2n+1) mu falls under the requested accuracy.
#include "player/choice.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace hlod {
namespace {

struct Cont {                        // the continuous problem over the objects that can vary
    std::vector<uint32_t> free;      // object indices
    std::vector<double> w, a, lo, n; // importance, cost at r = 1, r_min, samples at r = 1
    std::vector<double> r;           // per object (all of them)
    double budget = 0;               // for the free objects
};

int32_t finestOption(const ChoiceObject& o) {
    int32_t f = kSkipped;
    for (size_t l = 0; l < o.options.size(); ++l)
        if (o.options[l].available && (f == kSkipped || o.options[l].cost > optionCost(o, f))) f = int32_t(l);
    return f;
}

// REBUILT (§4.1): cost_i(r) = r x t_max,i for r >= r_min,i, t_max,i the finest cut's cost; r_min
// is where GB's per-pixel term would take over, here the coarsest cut (hlod0 is always drawn).
Cont continuous(const ChoiceProblem& p) {
    Cont c;
    c.budget = p.budget;
    c.r.assign(p.objects.size(), 1);
    for (uint32_t i = 0; i < p.objects.size(); ++i) {
        const ChoiceObject& o = p.objects[i];
        int32_t hi = finestOption(o), lo = cheapestOption(o);
        if (hi == kSkipped) continue;
        double a = optionCost(o, hi), rmin = a > 0 ? optionCost(o, lo) / a : 1;
        if (rmin >= 1 - 1e-12) {
            c.budget -= a;  // one cost only: fixed at r = 1
            continue;
        }
        c.free.push_back(i);
        c.w.push_back(o.importance * o.pixels);  // REBUILT (§4.2): importance = coverage x focus x semantics
        c.a.push_back(a);
        c.lo.push_back(rmin);
        c.n.push_back(std::max(1.0, o.options[size_t(hi)].samples));
    }
    return c;
}

// Weak-duality bound at x with multipliers mu / slack: sup over r > 0 of the Lagrangian, minus
// the benefit at x. Exactly (2n+1) mu at the central point.
double dualGap(const Cont& c, const std::vector<double>& x, double mu, double s) {
    double lc = mu / s, g = lc * c.budget, f = 0;
    for (size_t j = 0; j < x.size(); ++j) {
        double llo = mu / (x[j] - c.lo[j]), lhi = mu / (1 - x[j]);
        double k = lc * c.a[j] - llo + lhi;
        if (k <= 0) return std::numeric_limits<double>::infinity();
        double xs = std::pow(c.w[j] / (2 * std::sqrt(c.n[j]) * k), 2.0 / 3.0);
        g += c.w[j] * gbAccuracy(xs, c.n[j]) - k * xs - llo * c.lo[j] + lhi;
        f += c.w[j] * gbAccuracy(x[j], c.n[j]);
    }
    return g - f;
}

}  // namespace

// REBUILT (§4.2): accuracy = 1 - 1 / sqrt(r n_max), "diminishing returns at higher resolutions",
// "relates to the distance between samples on the surface" (~ 1 / sqrt(vertices) on a surface).
double gbAccuracy(double r, double n) { return 1 - 1 / std::sqrt(std::max(r * n, 1e-300)); }

double gbObjective(const ChoiceProblem& p, std::span<const double> r) {
    double b = 0;
    for (size_t i = 0; i < p.objects.size(); ++i) {
        const ChoiceObject& o = p.objects[i];
        int32_t hi = finestOption(o);
        if (hi != kSkipped) b += o.importance * o.pixels * gbAccuracy(r[i], std::max(1.0, o.options[size_t(hi)].samples));
    }
    return b;
}

GbResult gbBarrier(const ChoiceProblem& p, std::span<const double> warm, const GbOptions& opt) {
    auto start = std::chrono::steady_clock::now();
    Cont c = continuous(p);
    GbResult res;
    const size_t n = c.free.size();
    double minCost = 0, maxCost = 0, wsum = 0;
    for (size_t j = 0; j < n; ++j) minCost += c.a[j] * c.lo[j], maxCost += c.a[j], wsum += c.w[j];
    for (size_t j = 0; j < n; ++j) c.r[c.free[j]] = minCost >= c.budget ? c.lo[j] : 1;
    if (n == 0 || minCost >= c.budget || maxCost <= c.budget) {  // no interior: r_min or all at 1
        res.interior = false;
        res.resolution = c.r;
        res.benefit = gbObjective(p, res.resolution);
        return res;
    }
    // Strictly feasible start (§5 "generation of a feasible starting point is straightforward"):
    // last frame's resolutions moved strictly inside [r_min, 1], then shrunk toward r_min until
    // the cost has slack (REBUILT: the paper's factor and its benefit/cost order were lost; all
    // objects are shrunk by one factor here).
    std::vector<double> x(n);
    double excess = 0;
    for (size_t j = 0; j < n; ++j) {
        double wr = c.free[j] < warm.size() ? warm[c.free[j]] : c.lo[j];
        double eps = 1e-3 * (1 - c.lo[j]);
        x[j] = std::clamp(wr, c.lo[j] + eps, 1 - eps);
        excess += c.a[j] * (x[j] - c.lo[j]);
    }
    double room = c.budget - minCost;
    if (excess >= room) {
        double theta = 0.5 * room / excess;
        for (size_t j = 0; j < n; ++j) x[j] = c.lo[j] + theta * (x[j] - c.lo[j]);
    }
    auto slack = [&](const std::vector<double>& y) {
        double s = c.budget;
        for (size_t j = 0; j < n; ++j) s -= c.a[j] * y[j];
        return s;
    };
    // phi(x) = -sum w acc(x) - mu [log s + sum log(x - r_min) + sum log(1 - x)]   (REBUILT, §5)
    auto phi = [&](const std::vector<double>& y, double mu) {
        double s = slack(y), v = -mu * std::log(s);
        for (size_t j = 0; j < n; ++j)
            v += -c.w[j] * gbAccuracy(y[j], c.n[j]) - mu * (std::log(y[j] - c.lo[j]) + std::log(1 - y[j]));
        return v;
    };
    const double m = double(2 * n + 1);  // constraints: n lower, n upper bounds, one cost
    double mu = opt.mu0 > 0 ? opt.mu0 : wsum / m;  // REBUILT: initial gap bound = sum of importances
    if (!warm.empty() && opt.mu0 <= 0) {
        // REBUILT (warm start, §5 "start from the previously computed sub-optimal value"): the mu
        // for which last frame's point is most nearly central, argmin |grad f0 + mu grad barrier|.
        double s = slack(x), gh = 0, hh = 0;
        for (size_t j = 0; j < n; ++j) {
            double g0 = -c.w[j] * 0.5 / std::sqrt(c.n[j]) * std::pow(x[j], -1.5);
            double h = c.a[j] / s - 1 / (x[j] - c.lo[j]) + 1 / (1 - x[j]);
            gh += g0 * h;
            hh += h * h;
        }
        if (hh > 0 && -gh / hh > 0) mu = std::clamp(-gh / hh, opt.accuracy * wsum / m, mu);
    }
    std::vector<double> g(n), d(n), step(n), y(n);
    for (;;) {
        // centring: Newton steps on phi; Hessian = diag + (mu / s^2) a a^T, solved by Sherman-Morrison
        for (uint32_t it = 0; it < 50 && res.newtonSteps < opt.maxNewton; ++it) {
            double s = slack(x), ada = 0, adg = 0;
            for (size_t j = 0; j < n; ++j) {
                double sq = std::sqrt(c.n[j]), dl = x[j] - c.lo[j], dh = 1 - x[j];
                double acc1 = 0.5 / sq * std::pow(x[j], -1.5), acc2 = -0.75 / sq * std::pow(x[j], -2.5);
                g[j] = -c.w[j] * acc1 + mu * c.a[j] / s - mu / dl + mu / dh;
                d[j] = -c.w[j] * acc2 + mu / (dl * dl) + mu / (dh * dh);
                ada += c.a[j] * c.a[j] / d[j];
                adg += c.a[j] * g[j] / d[j];
            }
            double rho = mu / (s * s), coef = rho * adg / (1 + rho * ada), dec = 0;
            for (size_t j = 0; j < n; ++j) {
                step[j] = -(g[j] - coef * c.a[j]) / d[j];  // -H^-1 g
                dec -= g[j] * step[j];                     // Newton decrement^2
            }
            ++res.newtonSteps;
            if (dec / 2 <= 1e-9 * m * mu) break;  // centred: the gap is then (2n+1) mu to ~1e-4
            // the largest step that stays strictly feasible, then backtracking (0.25, 0.5)
            double tmax = 1, as = 0;
            for (size_t j = 0; j < n; ++j) {
                as += c.a[j] * step[j];
                if (step[j] < 0) tmax = std::min(tmax, 0.99 * (x[j] - c.lo[j]) / -step[j]);
                if (step[j] > 0) tmax = std::min(tmax, 0.99 * (1 - x[j]) / step[j]);
            }
            if (as > 0) tmax = std::min(tmax, 0.99 * s / as);
            double f0 = phi(x, mu), t = tmax;
            for (int k = 0; k < 60; ++k, t *= 0.5) {
                for (size_t j = 0; j < n; ++j) y[j] = x[j] + t * step[j];
                if (phi(y, mu) <= f0 - 0.25 * t * dec) break;
            }
            x = y;
        }
        double elapsed = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        // stop: (2n+1) mu under the accuracy, the time budget or the step cap. REBUILT (§5): at the
        // central point of weight mu the duality gap is exactly (m = 2n+1) x mu (Boyd & Vandenberghe
        // §11.2.2), so from mu0 with factor gamma the accuracy eps takes ceil(log(m mu0 / eps) /
        // log gamma) outer steps ("converges to accuracy ... in exactly ... log ... steps").
        if (m * mu <= opt.accuracy * wsum || res.newtonSteps >= opt.maxNewton ||
            (opt.timeBudgetMs > 0 && elapsed >= opt.timeBudgetMs))
            break;
        mu /= opt.muFactor;  // sequential unconstrained minimisation (REBUILT factor)
    }
    res.mu = mu;
    res.certifiedGap = dualGap(c, x, mu, slack(x));
    for (size_t j = 0; j < n; ++j) c.r[c.free[j]] = x[j];
    res.resolution = c.r;
    res.benefit = gbObjective(p, res.resolution);
    return res;
}

std::vector<double> gbWaterFilling(const ChoiceProblem& p) {
    Cont c = continuous(p);
    const size_t n = c.free.size();
    // KKT: w acc'(r) = lambda a  =>  r(lambda) = (w / (2 sqrt(n) lambda a))^(2/3), clipped to [r_min, 1]
    auto cost = [&](double lambda) {
        double s = 0;
        for (size_t j = 0; j < n; ++j) {
            double r = std::pow(c.w[j] / (2 * std::sqrt(c.n[j]) * lambda * c.a[j]), 2.0 / 3.0);
            c.r[c.free[j]] = std::clamp(r, c.lo[j], 1.0);
            s += c.a[j] * c.r[c.free[j]];
        }
        return s;
    };
    double minCost = 0, maxCost = 0;
    for (size_t j = 0; j < n; ++j) minCost += c.a[j] * c.lo[j], maxCost += c.a[j];
    if (n == 0 || minCost >= c.budget || maxCost <= c.budget) {
        for (size_t j = 0; j < n; ++j) c.r[c.free[j]] = minCost >= c.budget ? c.lo[j] : 1;
        return c.r;
    }
    double lo = -700, hi = 700;  // log(lambda): cost falls as lambda rises
    for (int k = 0; k < 200; ++k) {
        double mid = 0.5 * (lo + hi);
        (cost(std::exp(mid)) > c.budget ? lo : hi) = mid;
    }
    cost(std::exp(hi));  // the feasible side
    return c.r;
}

Choice gbRound(const ChoiceProblem& p, std::span<const double> r) {
    Choice c;
    c.level.assign(p.objects.size(), kSkipped);
    struct Up {
        double frac;
        uint32_t i;
        int32_t next;
    };
    std::vector<Up> ups;
    double used = 0;
    for (uint32_t i = 0; i < p.objects.size(); ++i) {
        const ChoiceObject& o = p.objects[i];
        int32_t hi = finestOption(o);
        if (hi == kSkipped) continue;
        double target = r[i] * optionCost(o, hi);
        int32_t fl = cheapestOption(o), next = kSkipped;
        for (size_t l = 0; l < o.options.size(); ++l) {  // floor: the finest option within r x t_max
            const ChoiceOption& x = o.options[l];
            if (x.available && x.cost <= target * (1 + 1e-12) && x.cost > optionCost(o, fl)) fl = int32_t(l);
        }
        for (size_t l = 0; l < o.options.size(); ++l) {  // the next dearer option
            const ChoiceOption& x = o.options[l];
            if (x.available && x.cost > optionCost(o, fl) && (next == kSkipped || x.cost < optionCost(o, next)))
                next = int32_t(l);
        }
        c.level[i] = fl;
        used += optionCost(o, fl);
        if (next != kSkipped)
            ups.push_back({(target - optionCost(o, fl)) / (optionCost(o, next) - optionCost(o, fl)), i, next});
    }
    // greedy fill: the leftover to the largest fractional parts, each while it fits
    std::stable_sort(ups.begin(), ups.end(), [](const Up& a, const Up& b) { return a.frac > b.frac; });
    for (const Up& u : ups) {
        const ChoiceObject& o = p.objects[u.i];
        double dc = optionCost(o, u.next) - optionCost(o, c.level[u.i]);
        if (used + dc <= p.budget) {
            used += dc;
            c.level[u.i] = u.next;
        }
    }
    // GB never skips an object; where skipping is allowed and even r_min does not fit, the
    // objects of least importance per ms are dropped until it does (FS's skip, player/SOLVERS.md).
    if (p.allowSkip && used > p.budget) {
        std::vector<uint32_t> drop;
        for (uint32_t i = 0; i < p.objects.size(); ++i)
            if (c.level[i] != kSkipped) drop.push_back(i);
        auto worth = [&](uint32_t i) {
            const ChoiceObject& o = p.objects[i];
            return o.importance * o.pixels / std::max(optionCost(o, c.level[i]), 1e-12);
        };
        std::stable_sort(drop.begin(), drop.end(), [&](uint32_t a, uint32_t b) { return worth(a) < worth(b); });
        for (size_t k = 0; k < drop.size() && used > p.budget; ++k) {
            used -= optionCost(p.objects[drop[k]], c.level[drop[k]]);
            c.level[drop[k]] = kSkipped;
        }
    }
    totalChoice(p, c);
    return c;
}

}  // namespace hlod
