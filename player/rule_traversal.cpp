// The rule-driven traversal of player/rule_traversal.h (thesis §4.2 order: breadth-first,
// top-down, every hlod0 node considered; never skips a visible hlod0 node).
#include "player/rule_traversal.h"

#include <deque>

namespace hlod {

PolicyFront traverseByRule(const PolicyFrame& f, SelectionState& state, const RefineRule& refine) {
    PolicyFront out;
    const Skeleton& s = f.skeleton;
    auto visit = [&](uint32_t id) {
        NodeEval e = f.evaluate(id);
        state.nodes[id].priority = e.priority;
        state.nodes[id].frustumVis = e.frustumVis;
        out.visited.push_back(id);
        return e.frustumVis >= 1;
    };
    std::deque<uint32_t> pending;
    for (uint32_t root : state.roots)
        if (visit(root)) pending.push_back(root);
    std::vector<uint32_t> visible;
    while (!pending.empty()) {
        uint32_t id = pending.front();
        pending.pop_front();
        ++out.iterations;
        uint32_t first = s.nodes[id].firstChild;
        if (first == kNone) {
            out.drawn.push_back({id, DrawReason::Leaf});
            continue;
        }
        visible.clear();
        uint32_t unloaded = 0;
        for (uint32_t c = first; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling) {
            bool v = visit(c);
            if (v) visible.push_back(c);
            unloaded += !f.resident[c] && (v || f.requireLoadedChildren);
        }
        if (visible.empty()) {
            out.drawn.push_back({id, DrawReason::Culled});
        } else if (!refine(id)) {
            out.refused += unloaded == 0;
            out.drawn.push_back({id, DrawReason::Hysteresis});
        } else if (unloaded > 0) {
            out.misses += unloaded;
            out.drawn.push_back({id, DrawReason::Miss});
        } else {
            pending.insert(pending.end(), visible.begin(), visible.end());
        }
    }
    return out;
}

}  // namespace hlod
