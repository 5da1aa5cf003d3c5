// The frame's multiple-choice knapsack (player/choice.h) from a skeleton, a view and the resident
// set: objects are the visible blocks (hlod0 roots with frustumVis = 1), an object's options its
// cuts at each depth (the faithful mapping of Funkhouser & Séquin 1993 §3: "levels of detail"):
// the cut at depth d descends from the root into visible children only, stopping at depth d, at
// leaves and at nodes with no visible child, exactly as the thesis traversal draws (§4.2). Each
// option's cost is FS §4's max(per-primitive, per-pixel) estimate, its benefit the common
// measure (player/benefit.h) summed over the cut, available when every node of it is resident.
#pragma once

#include "formats/db.h"
#include "player/benefit.h"
#include "player/choice.h"
#include "player/selection.h"

#include <span>
#include <vector>

namespace hlod {

struct ChoiceMapOptions {
    double budgetMs = 0;   // the objects' budget: c_targetTime minus the fixed overhead
    double vTime = 0.001;  // ms per unit of cost_n (first feedback loop)
    double pixelMs = 0;    // FS §4 C3 / GB t_pix, ms per covered pixel (0 on the cost model)
    bool allowSkip = false;
};

struct ChoiceMap {
    ChoiceProblem problem;
    // Per object, per option: the cut's nodes, in breadth-first order. cuts[i][l] for option l.
    std::vector<std::vector<std::vector<uint32_t>>> cuts;
    // Every node evaluated (priority and frustumVis written to the SelectionState), breadth-first:
    // the roots, then the visible blocks' nodes to their deepest cut.
    std::vector<uint32_t> visited;
};

// Evaluates the roots and the visible blocks' subtrees (state.nodes[id].priority, .frustumVis),
// and builds the problem. Cost of option l of block b:
//   max(vTime x sum over the cut of cost_n, pixelMs x projected pixels of the block's root).
ChoiceMap mapChoice(const Skeleton& skeleton, const Projection& projection, const Evaluate& evaluate,
                    std::span<const uint8_t> resident, SelectionState& state, const ChoiceMapOptions& options);

}  // namespace hlod
