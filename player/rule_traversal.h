// A breadth-first, top-down traversal like the thesis's (§4.2) that refines a node by a
// per-node rule instead of time slices and hysteresis: the frame of the threshold policies
// (none, static, feedback: Funkhouser & Séquin 1993 §7; sse, sse-budget: screen-space error).
// A visible node is drawn when it has no children (Leaf), no visible child (Culled), the rule
// declines (Hysteresis: a detail decision, toggles count), or a visible child is not resident
// (Miss; with requireLoadedChildren any child not resident); otherwise its visible children are
// considered. Every child of a considered node is evaluated (§4.2 priority), so the loader
// fetches the children of the front by priority as the thesis does.
#pragma once

#include "player/policy.h"

#include <functional>

namespace hlod {

using RefineRule = std::function<bool(uint32_t node)>;

PolicyFront traverseByRule(const PolicyFrame& frame, SelectionState& state, const RefineRule& refine);

}  // namespace hlod
