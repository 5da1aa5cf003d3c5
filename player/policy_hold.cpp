// `hold`: the project's own node-granular policy (player/DEFAULT_POLICY.md). The thesis's
// breadth-first traversal (§4.2) with a per-node refine flag kept across frames in place of time
// slices and hysteresis counters, and the flags changed by the two steps of Funkhouser &
// Séquin's incremental optimisation (SIGGRAPH 1993 §6), one sibling set at a time, against the
// thesis's own estimate (v_time x sum of cost_n + overhead, §4.2 eq. 3.1):
//  - lower: while the estimate exceeds target x (1 + overrun), coarsen the sibling set of lowest
//    Value (FS §6: "decrements the accuracy attributes of the object tuples with the lowest current
//    Value until the cumulative cost ... is less than the target frame time");
//  - raise: while a refinement fits under target x (1 - headroom), refine the front node of
//    highest Value (FS §6's increment step). A node refined under the headroom is coarsened again
//    only after the estimate has grown past target x (1 + overrun): a dead band, the same on the way up and
//    on the way down (symmetric hysteresis; the thesis's own is per node and asymmetric);
//  - exchange: while the best refinement's Value exceeds the worst coarsening's by more than
//    `exchange_gain` (a fraction) and both fit together, do both (what holding alone would never
//    undo: detail left where the view no longer wants it).
// Value = gain in the common benefit's accuracy over the visible children's size (player/benefit.h)
// per ms of estimated cost. Each node is refined by at most one level a frame (its children's
// children are evaluated next frame), as in the thesis's traversal.
#include "player/policy.h"
#include "player/rule_traversal.h"

#include <algorithm>
#include <limits>

namespace hlod {
namespace {

class HoldPolicy final : public SelectionPolicy {
public:
    explicit HoldPolicy(const PolicyOptions& o)
        : headroom_(o.get("hold.headroom", 0.03)), overrun_(o.get("hold.overrun", 0.03)),
          exchangeGain_(o.get("hold.exchange_gain", 1)) {}  // ranges checked by makePolicy
    const char* name() const override { return "hold"; }

    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        const Skeleton& s = f.skeleton;
        if (refine_.size() != s.nodes.size()) refine_.assign(s.nodes.size(), 0);
        auto rule = [&](uint32_t id) { return refine_[id] != 0; };
        PolicyFront first = traverseByRule(f, state, rule);
        double cost = 0;
        for (const DrawnNode& d : first.drawn) cost += s.nodes[d.node].cost;
        const double ms = f.vTime, budget = f.targetMs - f.overheadMs, raiseTo = budget * (1 - headroom_);
        // Candidates. Up: a node drawn by a detail decision (visible children, all resident).
        // Down: a refined node whose visible children are all drawn.
        std::vector<Step> up, down;
        drawnChildren_.assign(s.nodes.size(), 0);
        for (const DrawnNode& d : first.drawn) {
            if (d.reason == DrawReason::Hysteresis) {
                Step x = step(f, state, d.node);
                if (x.ready) up.push_back(x);
            }
            uint32_t p = s.nodes[d.node].parent;
            if (p != kNone && ++drawnChildren_[p] == visibleChildren(s, state, p)) down.push_back(step(f, state, p));
        }
        std::sort(up.begin(), up.end(), [](const Step& a, const Step& b) { return a.value > b.value; });
        std::sort(down.begin(), down.end(), [](const Step& a, const Step& b) { return a.value < b.value; });
        size_t u = 0, d = 0;
        uint32_t steps = 0;
        while (ms * cost > budget * (1 + overrun_) && d < down.size()) {  // lower
            refine_[down[d].node] = 0, cost -= down[d].dc, ++d, ++steps;
        }
        auto parentKept = [&](uint32_t id) { return s.nodes[id].parent == kNone || refine_[s.nodes[id].parent]; };
        for (; u < up.size(); ++u) {  // raise, highest Value first, each that fits
            if (ms * (cost + up[u].dc) > raiseTo || !parentKept(up[u].node)) continue;
            refine_[up[u].node] = 1, cost += up[u].dc, ++steps;
            up[u].dc = std::numeric_limits<double>::infinity();  // taken
        }
        for (size_t a = 0, b = d; a < up.size() && b < down.size(); ++a) {  // exchange
            if (up[a].dc == std::numeric_limits<double>::infinity() || !parentKept(up[a].node)) continue;
            if (s.nodes[up[a].node].parent == down[b].node) continue;
            if (up[a].value <= down[b].value * (1 + exchangeGain_)) break;
            if (ms * (cost + up[a].dc - down[b].dc) > raiseTo) continue;
            refine_[up[a].node] = 1, refine_[down[b].node] = 0, cost += up[a].dc - down[b].dc, ++b, steps += 2;
        }
        if (steps == 0) return finish(first, 0);
        PolicyFront out = traverseByRule(f, state, rule);  // the changed flags' front
        return finish(out, steps);
    }

private:
    struct Step {
        uint32_t node;
        double dc;     // cost_n units: visible children's cost - the node's
        double value;  // accuracy gain x size over the visible children, per unit of cost
        bool ready;    // every visible child resident
    };

    static uint32_t visibleChildren(const Skeleton& s, const SelectionState& state, uint32_t p) {
        uint32_t n = 0;
        for (uint32_t c = s.nodes[p].firstChild; c != kNone && s.nodes[c].parent == p; c = s.nodes[c].nextSibling)
            n += state.nodes[c].frustumVis >= 1;
        return n;
    }

    // Refining `p` into its visible children (evaluated this frame by the traversal).
    static Step step(const PolicyFrame& f, const SelectionState& state, uint32_t p) {
        const Skeleton& s = f.skeleton;
        const Node& n = s.nodes[p];
        double accP = 1 / (1 + projectedErrorPx(n, f.projection)), dc = -double(n.cost), db = 0;
        bool ready = true;
        for (uint32_t c = n.firstChild; c != kNone && s.nodes[c].parent == p; c = s.nodes[c].nextSibling) {
            if (state.nodes[c].frustumVis < 1) continue;
            const Node& k = s.nodes[c];
            double accC = 1 / (1 + projectedErrorPx(k, f.projection));
            ready = ready && f.resident[c];
            dc += k.cost;
            db += nodeBenefit(s, k, f.projection) * (1 - accP / accC);  // size_c x (acc_c - acc_p)
        }
        return {p, dc, dc > 0 ? db / dc : std::numeric_limits<double>::infinity(), ready};
    }

    static PolicyFront finish(PolicyFront& front, uint32_t steps) {
        front.iterations = steps;
        return std::move(front);
    }

    double headroom_, overrun_, exchangeGain_;
    std::vector<uint8_t> refine_;          // per node: refine when its children allow (kept across frames)
    std::vector<uint32_t> drawnChildren_;  // scratch
};

}  // namespace

std::unique_ptr<SelectionPolicy> makeNodeHoldPolicy(const PolicyOptions& o) { return std::make_unique<HoldPolicy>(o); }

}  // namespace hlod
