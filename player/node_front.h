// What the node-granular Funkhouser & Séquin policies (`fs-node`, `fs-node-inc`;
// player/SOLVERS.md "fs-node") share: one front node's refinement step, with FS 1993 §4's
// per-primitive cost change and the common benefit's change (player/benefit.h), and the
// front as drawn nodes from the set of refined nodes.
#pragma once

#include "player/fs_node.h"
#include "player/policy.h"

#include <cstdint>
#include <vector>

namespace hlod {

struct NodeRefinement {
    double primMs = 0;   // v_time x (sum of the visible children's cost_n - the node's)
    double benefit = 0;  // sum of the visible children's common benefit - the node's
    bool possible = false;  // the node has visible children and they are resident (with
                            // requireLoadedChildren: every child is)
};

// Evaluates node `id` (thesis §4.2 priority and frustumVis into `state`, the id appended to `visited`);
// true when it is visible (frustumVis = 1).
bool evaluateNode(const PolicyFrame& frame, SelectionState& state, uint32_t id, std::vector<uint32_t>& visited);

// A drawn block's FS §4 Cost terms for hlod0 node `root` alone: v_time x cost_n and, as the block
// solvers' (player/choice_map.cpp), pixelMs x the root's projected pixels (at least 1).
BlockCost rootBlockCost(const PolicyFrame& frame, uint32_t root, double pixelMs);

// Evaluates every child of `id` (thesis §4.2 priority and frustumVis into `state`, ids appended to
// `visited`, so the loader fetches them by priority) and returns the step that replaces `id` by
// its visible children.
NodeRefinement evaluateRefinement(const PolicyFrame& frame, SelectionState& state, uint32_t id,
                                  std::vector<uint32_t>& visited);

// The front: breadth-first from `drawnRoots` (visible hlod0 nodes drawn or refined), each node
// with refined[id] != 0 replaced by its visible children (evaluated this frame). Fills drawn
// (with deriveReason), misses (visible non-resident children of drawn nodes) and skipsBlocks (a
// visible root not among drawnRoots). Returns the refined nodes it passed (the front's interior).
std::vector<uint32_t> emitNodeFront(const PolicyFrame& frame, const SelectionState& state,
                                    std::vector<uint32_t> drawnRoots, const std::vector<uint8_t>& refined,
                                    PolicyFront& out);

}  // namespace hlod
