// Node hierarchy traversal of thesis §4.2: breadth-first and top-down; time slicing by eq. 4.1
// (timeSlice_n = shareTime_n * priority_n / sum of the visible siblings' priorities); the
// hysteresis counter and the cumulative hysteresis rule (cumHyst < 0 draws the parent,
// otherwise all the siblings are visited); a visible sibling that is not loaded forces the
// parent; §5.2 option: switch to children only when all of them are loaded. Toggles are
// counted by the rule of §6.5, without the switches that culling causes (player/STATS.md), by
// the accounting every policy shares (player/front.cpp).
#include "player/selection.h"

#include "player/front.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace hlod {

SelectionState::SelectionState(const Skeleton& skeleton) : nodes(skeleton.nodes.size()) {
    for (const Node& n : skeleton.nodes)
        if (n.parent == kNone) roots.push_back(n.id);
}

DrawState SelectionState::role(uint32_t node) const {
    const NodeState& s = nodes[node];
    return frame > 0 && s.roleFrame == frame - 1 ? s.role : DrawState::None;
}

SelectionParams selectionParams(const Constants& c, double hlod0Share, double vTime, bool requireLoadedChildren) {
    SelectionParams p;
    p.hlod0Share = hlod0Share;
    p.vTime = vTime;
    p.hystSwitch = c.hystSwitch;
    p.hystLimit = c.hystLimit;
    p.initialHyst = -c.hystSwitch;
    p.requireLoadedChildren = requireLoadedChildren;
    return p;
}

long cumulativeHysteresis(std::span<const double> hysts, double hystSwitch) {
    long sum = 0;
    for (double h : hysts) sum += long(std::trunc(h / hystSwitch));
    return sum;
}

double updateHysteresis(double hyst, double timeSlice, double timeNeeded, double hystLimit) {
    return std::clamp(hyst + (timeSlice - timeNeeded) / timeNeeded, -hystLimit, hystLimit);
}

namespace {

struct Traversal {
    const Skeleton& skeleton;
    const SelectionParams& params;
    const Evaluate& evaluate;
    SelectionState& state;
    std::span<const uint8_t> resident;
    PolicyFront out;
    std::deque<uint32_t> pending;  // visible nodes whose children are to be considered (FIFO)
    std::vector<uint32_t> siblings;
    std::vector<double> hysts;

    double timeNeeded(uint32_t id) const {  // timeNeeded_n = v_time * cost_n
        return params.vTime * std::max(double(skeleton.nodes[id].cost), 1.0);
    }

    void draw(uint32_t id, DrawReason reason) {
        out.drawn.push_back({id, reason});
        if (params.passRemainders) passRemainder(id);
    }

    // thesis-rh (§6.6 future work, "accumulate unused time slices and give it to other nodes"; the
    // passing rule of Hernández & Beneš, Robin Hood, §5 eqs 2-4): a drawn node leaves
    // timeSlice - timeNeeded unused; it goes to the next sibling of its set still to be
    // considered (the front of the FIFO when it shares the parent). The last sibling's
    // remainder is lost. A refined node passes nothing: its children split its slice.
    void passRemainder(uint32_t id) {
        if (pending.empty() || skeleton.nodes[pending.front()].parent != skeleton.nodes[id].parent) return;
        double left = state.nodes[id].timeSlice - timeNeeded(id);
        if (left <= 0) return;
        NodeState& next = state.nodes[pending.front()];
        next.timeSlice += left;
        next.received += left;
    }

    // Robin Hood processes instances "from simple to complex" (§5): thesis-rh orders each visible
    // sibling set by timeNeeded, ascending (ties by id), before it joins the FIFO.
    void orderSiblings() {
        if (!params.passRemainders) return;
        std::stable_sort(siblings.begin(), siblings.end(), [&](uint32_t a, uint32_t b) { return timeNeeded(a) < timeNeeded(b); });
    }

    // Evaluates one node's priority; a visible node joins `siblings`. Returns the priority it
    // adds to the visible siblings' sum (0 when not visible).
    double visit(uint32_t id) {
        NodeEval e = evaluate(id);
        NodeState& s = state.nodes[id];
        s.priority = e.priority;
        s.frustumVis = e.frustumVis;
        out.visited.push_back(id);
        if (e.frustumVis < 1) return 0;
        siblings.push_back(id);
        return e.priority;
    }

    // Computes priorities of a sibling set; returns the visible ones in `siblings`.
    double evaluateSiblings(uint32_t first) {
        siblings.clear();
        double sum = 0;
        for (uint32_t id = first; id != kNone; id = skeleton.nodes[id].nextSibling) {
            if (skeleton.nodes[id].parent != skeleton.nodes[first].parent) break;  // hlod0 chain guard
            sum += visit(id);
        }
        return sum;
    }

    // eq. 4.1 and the hysteresis update for the visible siblings sharing `shareTime`.
    void sliceTime(double shareTime, double prioritySum) {
        for (uint32_t id : siblings) {
            NodeState& s = state.nodes[id];
            s.timeSlice = prioritySum > 0 ? shareTime * s.priority / prioritySum : shareTime / siblings.size();
            s.received = 0;
            if (!s.evaluated) {
                s.hyst = params.initialHyst;
                s.evaluated = true;
            }
            s.hyst = updateHysteresis(s.hyst, s.timeSlice, timeNeeded(id), params.hystLimit);
        }
    }

    // `parent` is visible and drawable: draw it, or descend into all its visible children.
    void consider(uint32_t parent) {
        uint32_t first = skeleton.nodes[parent].firstChild;
        if (first == kNone) return draw(parent, DrawReason::Leaf);
        double sum = evaluateSiblings(first);
        if (siblings.empty()) return draw(parent, DrawReason::Culled);  // visible box, no visible child
        sliceTime(state.nodes[parent].timeSlice, sum);
        hysts.clear();
        uint32_t unloaded = 0;
        for (uint32_t id : siblings) {
            hysts.push_back(state.nodes[id].hyst);
            unloaded += !resident[id];
        }
        if (params.requireLoadedChildren)
            for (uint32_t id = first; id != kNone; id = skeleton.nodes[id].nextSibling)
                unloaded += !resident[id] && state.nodes[id].frustumVis < 1;
        if (cumulativeHysteresis(hysts, params.hystSwitch) < 0) {
            out.refused += unloaded == 0;
            return draw(parent, DrawReason::Hysteresis);
        }
        if (unloaded > 0) {
            out.misses += unloaded;
            return draw(parent, DrawReason::Miss);
        }
        orderSiblings();
        pending.insert(pending.end(), siblings.begin(), siblings.end());
    }

    void run() {
        const auto& roots = state.roots;
        if (!roots.empty()) {
            double sum = evaluateRoots();
            sliceTime(params.hlod0Share, sum);  // shareTime = the hlod0 share at the roots
            orderSiblings();
            pending.assign(siblings.begin(), siblings.end());
        }
        while (!pending.empty()) {
            uint32_t id = pending.front();
            pending.pop_front();
            ++out.iterations;
            consider(id);
        }
    }

    double evaluateRoots() {
        siblings.clear();
        double sum = 0;
        for (uint32_t id : state.roots) {
            sum += visit(id);
        }
        return sum;
    }
};

}  // namespace

PolicyFront traverseThesis(const Skeleton& skeleton, const SelectionParams& params, const Evaluate& evaluate,
                           SelectionState& state, std::span<const uint8_t> resident) {
    Traversal t{skeleton, params, evaluate, state, resident, {}, {}, {}, {}};
    t.run();
    return std::move(t.out);
}

Selection selectFront(const Skeleton& skeleton, const SelectionParams& params, const Evaluate& evaluate,
                      SelectionState& state, std::span<const uint8_t> resident) {
    PolicyFront front = traverseThesis(skeleton, params, evaluate, state, resident);
    FrontAccount account = accountFront(skeleton, state, front.drawn);
    Selection sel;
    sel.drawn = std::move(account.items);
    sel.visited = std::move(front.visited);
    sel.drawnCost = account.drawnCost;
    sel.upToggles = account.upToggles;
    sel.downToggles = account.downToggles;
    sel.reversals = account.reversals;
    sel.misses = front.misses;
    sel.refused = front.refused;
    return sel;
}

}  // namespace hlod
