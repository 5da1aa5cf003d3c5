// The frame's front as every selection policy hands it to the Player (player/policy.h): the
// drawn nodes with the reason each was drawn, and what is shared by all policies so that their
// §6.5 counts compare: the role and toggle accounting (player/STATS.md "Toggles") and the
// check that a front is a valid cut of the hierarchy.
#pragma once

#include "player/selection.h"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace hlod {

struct DrawnNode {
    uint32_t node = 0;
    // Why the node is drawn rather than its children (selection.h). A policy that decides by
    // detail (hysteresis, a threshold, a budget) says Hysteresis; Leaf, Culled and Miss follow
    // the tree, culling and loading. deriveReason() gives the usual one.
    DrawReason reason = DrawReason::Leaf;
};

// What a policy chose for one frame.
struct PolicyFront {
    std::vector<DrawnNode> drawn;    // the cut, in drawing order
    std::vector<uint32_t> visited;   // nodes whose SelectionState::nodes[id].priority was set this
                                     // frame: the loader requests these by that priority (§4.3)
    uint32_t misses = 0;             // visible children wanted but not loaded
    uint32_t refused = 0;            // all-loaded sibling sets refused by a detail decision (thesis: cumHyst < 0)
    uint32_t iterations = 0;         // the policy's unit of work (nodes considered, solver iterations)
    double optimisationMs = -1;      // time of the optimisation proper; < 0: the whole select() call
    bool skipsBlocks = false;        // some visible root-to-leaf paths meet no drawn node, on purpose
};

// Roles (Drawn, Refined = an ancestor of a drawn node) of one frame and the §6.5 toggles against
// the previous frame's roles, by the rule of player/STATS.md; advances state.frame.
struct FrontAccount {
    std::vector<DrawItem> items;     // the drawn nodes for the renderer, in the front's order
    double drawnCost = 0;            // sum of cost_n over drawn nodes
    uint32_t upToggles = 0, downToggles = 0, reversals = 0;
};
FrontAccount accountFront(const Skeleton& skeleton, SelectionState& state, std::span<const DrawnNode> drawn);

// The reason a node drawn by a detail decision is drawn, from the tree alone: Leaf (no
// children), Culled (no visible child), Miss (a visible child is not resident), else Hysteresis.
DrawReason deriveReason(const Skeleton& skeleton, uint32_t node, const std::function<bool(uint32_t)>& visible,
                        std::span<const uint8_t> resident);

// A valid cut: no node drawn twice, no drawn node an ancestor of another, every drawn node
// resident, and (unless skipsAllowed) every root-to-leaf path of visible nodes meets a drawn
// node. Returns "" or the first violation, in words.
std::string checkCut(const Skeleton& skeleton, std::span<const DrawnNode> drawn, std::span<const uint8_t> resident,
                     const std::function<bool(uint32_t)>& visible, bool skipsAllowed);

}  // namespace hlod
