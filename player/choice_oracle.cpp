// The exact optimum of the frame's multiple-choice knapsack (player/choice.h; T. A. Funkhouser
// and C. H. Séquin, SIGGRAPH 1993, §3 eq. 1 and §6), by depth-first branch-and-bound with the
// LP-relaxation bound of the multiple-choice knapsack (R. Sinha and A. A. Zoltners, "The
// Multiple-Choice Knapsack Problem", Operations Research 27(3), 1979: the relaxation takes the
// increments of every object's upper convex hull in descending slope, the last one fractionally).
// Costs are real numbers: no discretisation. A yardstick, run offline by `hlod compare`.
#include "player/choice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace hlod {
namespace {

struct Inc {
    double dc, db, slope;
};

struct Search {
    const ChoiceProblem& p;
    std::vector<uint32_t> order;                  // objects in branching order
    std::vector<std::vector<int32_t>> cands;      // per object: options above the base, best benefit first
    std::vector<std::vector<Inc>> suffix;         // per branching position: LP increments of the rest, by slope
    std::vector<int32_t> base, cur, best;
    double bestBenefit = 0;
    uint64_t nodes = 0, maxNodes = 0;
    bool aborted = false;

    double bound(size_t k, double cap) const {  // LP relaxation of objects order[k..] over their bases
        double b = 0;
        for (const Inc& x : suffix[k]) {
            if (x.dc <= cap) {
                cap -= x.dc;
                b += x.db;
            } else {
                return b + x.db * (cap / x.dc);
            }
        }
        return b;
    }

    void dfs(size_t k, double cap, double gained) {
        if (aborted) return;
        if (++nodes > maxNodes) {
            aborted = true;
            return;
        }
        if (gained > bestBenefit) {
            bestBenefit = gained;
            best = cur;
        }
        if (k == order.size()) return;
        if (gained + bound(k, cap) <= bestBenefit * (1 + 1e-12)) return;
        uint32_t i = order[k];
        const ChoiceObject& o = p.objects[i];
        for (int32_t l : cands[i]) {
            double dc = optionCost(o, l) - optionCost(o, base[i]);
            if (dc > cap) continue;
            cur[i] = l;
            dfs(k + 1, cap - dc, gained + optionBenefit(o, l) - optionBenefit(o, base[i]));
        }
        cur[i] = base[i];
        dfs(k + 1, cap, gained);
    }
};

}  // namespace

OracleResult oracleChoice(const ChoiceProblem& p, const OracleOptions& opt) {
    const size_t n = p.objects.size();
    Search s{p, {}, std::vector<std::vector<int32_t>>(n), {}, {}, {}, {}, 0, 0, opt.maxNodes, false};
    for (const ChoiceObject& o : p.objects) s.base.push_back(baseOption(p, o));
    const double cap = budgetAboveBases(p);
    OracleResult r;
    std::vector<std::vector<Inc>> incs(n);
    std::vector<double> spread(n, 0);
    for (size_t i = 0; i < n; ++i) {
        const ChoiceObject& o = p.objects[i];
        double c0 = optionCost(o, s.base[i]), b0 = optionBenefit(o, s.base[i]);
        for (size_t l = 0; l < o.options.size(); ++l) {
            const ChoiceOption& x = o.options[l];
            if (x.available && x.benefit > b0 && x.cost - c0 <= cap) s.cands[i].push_back(int32_t(l));
        }
        std::sort(s.cands[i].begin(), s.cands[i].end(),
                  [&](int32_t a, int32_t b) { return optionBenefit(o, a) > optionBenefit(o, b); });
        double pc = c0, pb = b0;
        for (int32_t l : upperHull(o, s.base[i], cap)) {
            double dc = optionCost(o, l) - pc, db = optionBenefit(o, l) - pb;
            incs[i].push_back({dc, db, dc > 0 ? db / dc : std::numeric_limits<double>::infinity()});
            pc = optionCost(o, l);
            pb = optionBenefit(o, l);
            spread[i] = pb - b0;
        }
    }
    for (size_t i = 0; i < n; ++i)
        if (!s.cands[i].empty()) s.order.push_back(uint32_t(i));
    std::stable_sort(s.order.begin(), s.order.end(), [&](uint32_t a, uint32_t b) { return spread[a] > spread[b]; });
    s.suffix.resize(s.order.size() + 1);
    for (size_t k = s.order.size(); k-- > 0;) {
        s.suffix[k] = s.suffix[k + 1];
        for (const Inc& x : incs[s.order[k]]) s.suffix[k].push_back(x);
        std::stable_sort(s.suffix[k].begin(), s.suffix[k].end(), [](const Inc& a, const Inc& b) { return a.slope > b.slope; });
    }
    s.cur = s.best = s.base;
    if (cap >= 0) {
        r.upperBound = s.bound(0, cap);
        Choice greedy = fsGreedy(p);  // the incumbent to beat
        s.bestBenefit = greedy.benefit;
        for (size_t i = 0; i < n; ++i) s.bestBenefit -= optionBenefit(p.objects[i], s.base[i]);
        s.best = greedy.level;
        s.dfs(0, cap, 0);
    }
    r.proven = !s.aborted;
    r.choice.level = s.best;
    r.choice.iterations = uint32_t(std::min<uint64_t>(s.nodes, UINT32_MAX));
    totalChoice(p, r.choice);
    double baseBenefit = 0;
    for (size_t i = 0; i < n; ++i) baseBenefit += optionBenefit(p.objects[i], s.base[i]);
    r.upperBound = cap >= 0 ? baseBenefit + r.upperBound : r.choice.benefit;
    return r;
}

Choice bruteForceChoice(const ChoiceProblem& p) {
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

}  // namespace hlod
