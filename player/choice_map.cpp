// Skeleton + view + resident set -> the frame's multiple-choice knapsack (player/choice_map.h).
// Funkhouser & Séquin 1993 §3 (objects and their levels of detail), §4 (cost: the maximum of
// the per-primitive and per-pixel stages); benefit: player/benefit.h.
#include "player/choice_map.h"

#include <algorithm>

namespace hlod {

ChoiceMap mapChoice(const Skeleton& s, const Projection& proj, const Evaluate& evaluate, std::span<const uint8_t> resident,
                    SelectionState& state, const ChoiceMapOptions& opt) {
    ChoiceMap m;
    m.problem.budget = opt.budgetMs;
    m.problem.allowSkip = opt.allowSkip;
    auto visit = [&](uint32_t id) {
        NodeEval e = evaluate(id);
        state.nodes[id].priority = e.priority;
        state.nodes[id].frustumVis = e.frustumVis;
        m.visited.push_back(id);
        return e.frustumVis >= 1;
    };
    std::vector<uint32_t> visibleRoots;
    for (uint32_t r : state.roots)
        if (visit(r)) visibleRoots.push_back(r);
    std::vector<uint32_t> level, next, kids;
    std::vector<uint8_t> fin, nextFin;  // 1: stays in every deeper cut (leaf, or no visible child)
    for (uint32_t r : visibleRoots) {
        ChoiceObject o;
        o.id = r;
        const Node& root = s.nodes[r];
        o.pixels = std::max(projectedAreaPx(root, proj), 1.0);
        o.distance = projectionDistance(root, proj);
        std::vector<std::vector<uint32_t>> cuts;
        level.assign(1, r);
        fin.assign(1, 0);
        for (;;) {
            // the next option: the current cut, one level deeper than the option before
            ChoiceOption x;
            double cost = 0;
            for (uint32_t id : level) {
                const Node& n = s.nodes[id];
                cost += n.cost;
                x.benefit += nodeBenefit(s, n, proj);
                x.samples += n.triangles();
                x.available = x.available && resident[id];
            }
            x.cost = std::max(opt.vTime * cost, opt.pixelMs * o.pixels);  // FS §4: max of the two stages
            o.options.push_back(x);
            cuts.push_back(level);
            // the next cut: every node with visible children replaced by them
            next.clear();
            nextFin.clear();
            bool deeper = false;
            for (size_t k = 0; k < level.size(); ++k) {
                uint32_t id = level[k];
                kids.clear();
                if (!fin[k])
                    for (uint32_t c = s.nodes[id].firstChild; c != kNone; c = s.nodes[c].nextSibling)
                        if (visit(c)) kids.push_back(c);
                if (kids.empty()) {
                    next.push_back(id);
                    nextFin.push_back(1);
                } else {
                    next.insert(next.end(), kids.begin(), kids.end());
                    nextFin.insert(nextFin.end(), kids.size(), 0);
                    deeper = true;
                }
            }
            if (!deeper) break;
            level.swap(next);
            fin.swap(nextFin);
        }
        o.complexity = o.options.back().cost;
        m.problem.objects.push_back(std::move(o));
        m.cuts.push_back(std::move(cuts));
    }
    return m;
}

}  // namespace hlod
