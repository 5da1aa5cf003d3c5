// Role and toggle accounting shared by every selection policy (thesis §6.5 counting rule, as
// player/STATS.md reads it: culling excluded) and the valid-cut check of player/policy.h.
#include "player/front.h"

namespace hlod {
namespace {

// §6.5: "we count each time a node gets upgraded to its children between successive frames
// [...] each downgrade from sibling nodes to a parent node. We do not count nodes that are
// culled away between frames." An up toggle is Drawn -> Refined from a countable Drawn; a down
// toggle is Refined -> Drawn by a detail decision (the Hysteresis reason) only. `reason` is why
// a Drawn node is drawn (unused for Refined).
void setRole(SelectionState& state, FrontAccount& out, uint32_t id, DrawState role, DrawReason reason) {
    NodeState& s = state.nodes[id];
    DrawState previous = state.role(id);
    const bool up = previous == DrawState::Drawn && role == DrawState::Refined && s.upCountable;
    const bool down = previous == DrawState::Refined && role == DrawState::Drawn && reason == DrawReason::Hysteresis;
    out.upToggles += up, out.downToggles += down;
    if (up || down) {
        out.reversals += s.toggledTo == previous && state.frame - s.toggleFrame <= kReversalWindow;
        s.toggledTo = role;
        s.toggleFrame = state.frame;
    }
    if (role == DrawState::Drawn) {
        const bool missContinues = previous == DrawState::Refined || (previous == DrawState::Drawn && !s.upCountable);
        s.upCountable = reason == DrawReason::Hysteresis || (reason == DrawReason::Miss && !missContinues);
    }
    s.role = role;
    s.roleFrame = state.frame;
}

}  // namespace

FrontAccount accountFront(const Skeleton& skeleton, SelectionState& state, std::span<const DrawnNode> drawn) {
    FrontAccount out;
    out.items.reserve(drawn.size());
    for (const DrawnNode& d : drawn) {
        const Node& n = skeleton.nodes[d.node];
        setRole(state, out, d.node, DrawState::Drawn, d.reason);
        out.items.push_back({d.node, n.level});
        out.drawnCost += n.cost;
        // Every ancestor of a drawn node is refined this frame; stop at one already marked.
        for (uint32_t p = n.parent; p != kNone; p = skeleton.nodes[p].parent) {
            const NodeState& ps = state.nodes[p];
            if (ps.roleFrame == state.frame && ps.role == DrawState::Refined) break;
            setRole(state, out, p, DrawState::Refined, DrawReason::Leaf);
        }
    }
    ++state.frame;
    return out;
}

DrawReason deriveReason(const Skeleton& skeleton, uint32_t node, const std::function<bool(uint32_t)>& visible,
                        std::span<const uint8_t> resident) {
    uint32_t first = skeleton.nodes[node].firstChild;
    if (first == kNone) return DrawReason::Leaf;
    bool anyVisible = false, missing = false;
    for (uint32_t c = first; c != kNone && skeleton.nodes[c].parent == node; c = skeleton.nodes[c].nextSibling)
        if (visible(c)) {
            anyVisible = true;
            missing |= !resident[c];
        }
    if (!anyVisible) return DrawReason::Culled;
    return missing ? DrawReason::Miss : DrawReason::Hysteresis;
}

std::string checkCut(const Skeleton& skeleton, std::span<const DrawnNode> drawn, std::span<const uint8_t> resident,
                     const std::function<bool(uint32_t)>& visible, bool skipsAllowed) {
    std::vector<uint8_t> isDrawn(skeleton.nodes.size(), 0);
    for (const DrawnNode& d : drawn) {
        if (d.node >= skeleton.nodes.size()) return "node " + std::to_string(d.node) + " does not exist";
        if (isDrawn[d.node]) return "node " + std::to_string(d.node) + " is drawn twice";
        if (!resident[d.node]) return "node " + std::to_string(d.node) + " is drawn but not resident";
        isDrawn[d.node] = 1;
    }
    for (const DrawnNode& d : drawn)
        for (uint32_t p = skeleton.nodes[d.node].parent; p != kNone; p = skeleton.nodes[p].parent)
            if (isDrawn[p]) return "node " + std::to_string(p) + " and its descendant " + std::to_string(d.node) + " are both drawn";
    if (skipsAllowed) return "";
    // Every path of visible nodes from a visible root must reach a drawn node.
    std::vector<uint32_t> stack;
    for (const Node& n : skeleton.nodes)
        if (n.parent == kNone && visible(n.id)) stack.push_back(n.id);
    while (!stack.empty()) {
        uint32_t id = stack.back();
        stack.pop_back();
        if (isDrawn[id]) continue;
        bool anyVisible = false;
        for (uint32_t c = skeleton.nodes[id].firstChild; c != kNone && skeleton.nodes[c].parent == id;
             c = skeleton.nodes[c].nextSibling)
            if (visible(c)) {
                anyVisible = true;
                stack.push_back(c);
            }
        if (!anyVisible) return "visible node " + std::to_string(id) + " is neither drawn nor covered by drawn descendants";
    }
    return "";
}

}  // namespace hlod
