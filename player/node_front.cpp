// The shared steps of the node-granular Funkhouser & Séquin policies (player/node_front.h):
// FS 1993 §4 per-primitive cost, the common benefit (player/benefit.h), the front from the
// refined nodes in the thesis's breadth-first order (thesis §4.2).
#include "player/node_front.h"

#include <algorithm>

namespace hlod {

bool evaluateNode(const PolicyFrame& f, SelectionState& state, uint32_t id, std::vector<uint32_t>& visited) {
    NodeEval e = f.evaluate(id);
    state.nodes[id].priority = e.priority;
    state.nodes[id].frustumVis = e.frustumVis;
    visited.push_back(id);
    return e.frustumVis >= 1;
}

BlockCost rootBlockCost(const PolicyFrame& f, uint32_t root, double pixelMs) {
    const Node& n = f.skeleton.nodes[root];  // FS §4: Cost = max(C1 Poly + C2 Vert, C3 Pix)
    return {f.vTime * n.cost, pixelMs * std::max(projectedAreaPx(n, f.projection), 1.0), true};
}

NodeRefinement evaluateRefinement(const PolicyFrame& f, SelectionState& state, uint32_t id, std::vector<uint32_t>& visited) {
    const Skeleton& s = f.skeleton;
    const Node& n = s.nodes[id];
    NodeRefinement x{-f.vTime * n.cost, -nodeBenefit(s, n, f.projection), false};
    bool any = false, ready = true;
    for (uint32_t c = n.firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling) {
        bool v = evaluateNode(f, state, c, visited);
        ready = ready && (f.resident[c] || (!v && !f.requireLoadedChildren));
        if (!v) continue;
        any = true;
        x.primMs += f.vTime * s.nodes[c].cost;  // FS §4: C1 Poly(O, L), as v_time x cost_n (eq. 3.1)
        x.benefit += nodeBenefit(s, s.nodes[c], f.projection);
    }
    x.possible = any && ready;
    return x;
}

std::vector<uint32_t> emitNodeFront(const PolicyFrame& f, const SelectionState& state, std::vector<uint32_t> pending,
                                    const std::vector<uint8_t>& refined, PolicyFront& out) {
    const Skeleton& s = f.skeleton;
    auto visible = [&](uint32_t id) { return state.nodes[id].frustumVis >= 1; };
    size_t roots = 0;
    for (uint32_t r : state.roots) roots += visible(r);
    out.skipsBlocks = pending.size() < roots;
    std::vector<uint32_t> interior;
    for (size_t i = 0; i < pending.size(); ++i) {  // breadth-first, as the thesis draws
        uint32_t id = pending[i];
        bool refine = refined[id] != 0;
        for (uint32_t c = s.nodes[id].firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling) {
            if (!visible(c)) continue;
            if (refine) pending.push_back(c);
            else out.misses += !f.resident[c];
        }
        if (refine) interior.push_back(id);
        else out.drawn.push_back({id, deriveReason(s, id, visible, f.resident)});
    }
    return interior;
}

}  // namespace hlod
