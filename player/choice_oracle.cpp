// The exact optimum of the frame's multiple-choice knapsack (player/choice.h; T. A. Funkhouser
// and C. H. Séquin, SIGGRAPH 1993, §3 eq. 1 and §6), by dynamic programming over the
// non-dominated (cost, benefit) states of the objects taken so far (G. L. Nemhauser and
// Z. Ullmann, "Discrete Dynamic Programming and Capital Allocation", Management Science 15(9),
// 1969), pruned by the LP-relaxation bound of the multiple-choice knapsack (R. Sinha and
// A. A. Zoltners, "The Multiple-Choice Knapsack Problem", Operations Research 27(3), 1979: the
// increments of every remaining object's upper convex hull in descending slope, the last one
// fractionally). Costs are real numbers: no discretisation. A yardstick, run offline by `hlod compare`.
#include "player/choice.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hlod {
namespace {

struct Inc {
    double dc, db, slope;
};

struct State {
    double cost, benefit;  // above the bases
    uint32_t prev;         // index in the previous layer
    int32_t option;        // this layer's object's option
};

// LP relaxation of the objects whose increments are `incs` (sorted by slope), capacity `cap`.
double lpBound(const std::vector<Inc>& incs, double cap) {
    double b = 0;
    for (const Inc& x : incs) {
        if (x.dc > cap) return b + x.db * (cap / x.dc);
        cap -= x.dc;
        b += x.db;
    }
    return b;
}

}  // namespace

OracleResult oracleChoice(const ChoiceProblem& p, const OracleOptions& opt) {
    const size_t n = p.objects.size();
    std::vector<int32_t> base;
    for (const ChoiceObject& o : p.objects) base.push_back(baseOption(p, o));
    const double cap = budgetAboveBases(p);
    double baseBenefit = 0;
    for (size_t i = 0; i < n; ++i) baseBenefit += optionBenefit(p.objects[i], base[i]);
    OracleResult r;
    Choice greedy = fsGreedy(p);  // the incumbent to beat
    r.choice = greedy;
    if (cap < 0) {  // even the bases do not fit: the cheapest choice
        r.choice.level = base;
        totalChoice(p, r.choice);
        r.upperBound = r.choice.benefit;
        return r;
    }
    // Candidate options per object (above the base, fitting alone), hull increments for the bound.
    std::vector<uint32_t> order;
    std::vector<std::vector<Inc>> incs(n);
    std::vector<double> spread(n, 0);
    for (size_t i = 0; i < n; ++i) {
        const ChoiceObject& o = p.objects[i];
        double pc = optionCost(o, base[i]), pb = optionBenefit(o, base[i]);
        for (int32_t l : upperHull(o, base[i], cap)) {
            double dc = optionCost(o, l) - pc, db = optionBenefit(o, l) - pb;
            incs[i].push_back({dc, db, dc > 0 ? db / dc : std::numeric_limits<double>::infinity()});
            pc = optionCost(o, l);
            pb = optionBenefit(o, l);
        }
        spread[i] = pb - optionBenefit(o, base[i]);
        if (!incs[i].empty()) order.push_back(uint32_t(i));
    }
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return spread[a] > spread[b]; });
    // suffix[k]: the increments of order[k..], by slope
    std::vector<std::vector<Inc>> suffix(order.size() + 1);
    for (size_t k = order.size(); k-- > 0;) {
        suffix[k] = suffix[k + 1];
        suffix[k].insert(suffix[k].end(), incs[order[k]].begin(), incs[order[k]].end());
        std::inplace_merge(suffix[k].begin(), suffix[k].end() - long(incs[order[k]].size()), suffix[k].end(),
                           [](const Inc& a, const Inc& b) { return a.slope > b.slope; });
    }
    r.upperBound = baseBenefit + lpBound(suffix[0], cap);
    double incumbent = greedy.benefit - baseBenefit;
    std::vector<std::vector<State>> layers(1, std::vector<State>{{0, 0, 0, kSkipped}});
    std::vector<State> next;
    uint64_t states = 1;
    for (size_t k = 0; k < order.size(); ++k) {
        const ChoiceObject& o = p.objects[order[k]];
        int32_t b = base[order[k]];
        next.clear();
        const std::vector<State>& prev = layers.back();
        for (uint32_t s = 0; s < prev.size(); ++s) {
            next.push_back({prev[s].cost, prev[s].benefit, s, b});
            for (size_t l = 0; l < o.options.size(); ++l) {
                const ChoiceOption& x = o.options[l];
                double dc = x.cost - optionCost(o, b), db = x.benefit - optionBenefit(o, b);
                if (x.available && int32_t(l) != b && db > 0 && prev[s].cost + dc <= cap)
                    next.push_back({prev[s].cost + dc, prev[s].benefit + db, s, int32_t(l)});
            }
        }
        // keep the non-dominated states (cheaper or better) that can still beat the incumbent
        std::sort(next.begin(), next.end(), [](const State& a, const State& c) {
            return a.cost != c.cost ? a.cost < c.cost : a.benefit > c.benefit;
        });
        std::vector<State> kept;
        double bestSoFar = -1;
        for (const State& st : next) {
            if (st.benefit <= bestSoFar) continue;  // dominated
            bestSoFar = st.benefit;
            incumbent = std::max(incumbent, st.benefit);  // the rest at their bases is feasible
            kept.push_back(st);
        }
        std::erase_if(kept, [&](const State& st) {
            return st.benefit + lpBound(suffix[k + 1], cap - st.cost) < incumbent * (1 - 1e-12) && st.benefit < incumbent;
        });
        if (kept.size() > opt.maxStates) {  // give up the proof: keep the most promising
            r.proven = false;
            std::nth_element(kept.begin(), kept.begin() + long(opt.maxStates), kept.end(), [&](const State& a, const State& c) {
                return a.benefit + lpBound(suffix[k + 1], cap - a.cost) > c.benefit + lpBound(suffix[k + 1], cap - c.cost);
            });
            kept.resize(opt.maxStates);
        }
        states += kept.size();
        layers.push_back(std::move(kept));
    }
    // the best final state, traced back through the layers
    const std::vector<State>& last = layers.back();
    uint32_t best = 0;
    for (uint32_t s = 1; s < last.size(); ++s)
        if (last[s].benefit > last[best].benefit) best = s;
    Choice c;
    c.level = base;
    for (size_t k = order.size(); k > 0; --k) {
        const State& st = layers[k][best];
        c.level[order[k - 1]] = st.option;
        best = st.prev;
    }
    totalChoice(p, c);
    c.iterations = uint32_t(std::min<uint64_t>(states, UINT32_MAX));
    if (c.benefit >= greedy.benefit) r.choice = c;
    else r.choice.iterations = c.iterations;
    return r;
}

}  // namespace hlod
