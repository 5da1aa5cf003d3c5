// Node selection of the rendering thread (thesis §4.2, §5.2): priority heuristics, time
// slicing (eq. 4.1), hysteresis and the cumulative hysteresis rule. Plain data and free
// functions; no threads, no I/O, deterministic.
#pragma once

#include "formats/constants.h"
#include "formats/db.h"
#include "player/renderer.h"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace hlod {

// What the camera means to the priority of a node (§4.2 "Priority Heuristics").
struct View {
    double eye[3] = {0, 0, 0};
    double ahead[3] = {0, 0, 0};     // eye + velocity * lookahead: the velocity adjustment
    double forward[3] = {0, 0, -1};  // unit viewing direction
    double planes[6][4] = {};        // frustum planes, inward normals: n.p + d >= 0 inside
    double falloff = 0.5;            // frustumVis reaches 0 this far outside (radians, ~angle)
};

View makeView(const Camera& camera, const double velocity[3], double lookaheadSeconds);

// 1 when the box meets the frustum; else falls linearly to 0 with the angle by which the box
// lies outside (its distance behind the worst plane over its distance to the eye).
double frustumVis(const View& view, const Box3f& box);

// priority_n = staticBenefit_n * vis_n * foreshorten_n / (cost_n * distance_n^2)   (§4.2)
double nodePriority(const Node& node, const View& view, const Constants& c, double frustumVisibility);

// What the traversal needs to know of a node this frame.
struct NodeEval {
    double priority = 0;
    double frustumVis = 0;  // > 0 ... 1; the node is visible (drawable) only when == 1
};
using Evaluate = std::function<NodeEval(uint32_t node)>;

enum class DrawState : uint8_t { None, Drawn, Refined };

// Why a node was drawn rather than refined (the branch of §4.2's traversal that drew it).
// Only Hysteresis is a detail decision; the others follow culling and loading (§6.5 counting,
// player/STATS.md).
enum class DrawReason : uint8_t {
    Leaf,        // no children
    Culled,      // none of its children is visible
    Hysteresis,  // cumHyst < 0 (§4.2)
    Miss,        // cumHyst >= 0 but a visible child is not loaded
};

// Per-node state kept across frames by the render thread.
struct NodeState {
    double hyst = 0;         // hysteresis_n (§4.2), in [-c_hystLimit, c_hystLimit]
    double priority = 0;     // last computed priority
    double frustumVis = 0;   // last computed frustumVis
    double timeSlice = 0;    // eq. 4.1, last frame it was evaluated (thesis-rh: plus `received`)
    double received = 0;     // thesis-rh: time passed on by the previous sibling this frame
    bool evaluated = false;  // hyst has been initialised
    DrawState role = DrawState::None;  // role in frame `roleFrame`
    uint64_t roleFrame = 0;
    // Drawn: whether switching to the children next is a §6.5 toggle. False after a culling
    // branch (Leaf, Culled) and for a Miss that follows Refined or a not-countable Drawn
    // (a newly visible child not loaded yet); true after Hysteresis and other Misses.
    bool upCountable = false;
    DrawState toggledTo = DrawState::None;  // role its last toggle switched it to, in frame `toggleFrame`
    uint64_t toggleFrame = 0;
};

// A toggle that undoes the same node's previous toggle within this many frames counts as a
// reversal: the flicker the thesis's hysteresis prevents ("we do not get successive up and
// down toggles", §6.5; 35 frames is its moving-average window).
inline constexpr uint64_t kReversalWindow = 35;

struct SelectionState {
    std::vector<NodeState> nodes;  // one per skeleton node
    std::vector<uint32_t> roots;   // hlod0 nodes, in id order
    uint64_t frame = 0;            // frames selected so far (roles of frame - 1 are "previous")
    explicit SelectionState(const Skeleton& skeleton);
    DrawState role(uint32_t node) const;  // role in the last selected frame
};

struct SelectionParams {
    double hlod0Share = Constants{}.targetTimeMs;  // shareTime of the hlod0 nodes, ms (second feedback loop)
    double vTime = 0.001;        // ms per unit of cost (first feedback loop)
    double hystSwitch = Constants{}.hystSwitch;
    double hystLimit = Constants{}.hystLimit;
    // hysteresis_n of a node evaluated for the first time (left open by the thesis): -c_hystSwitch,
    // the switching threshold. A new sibling set then switches on its first frame when every
    // visible sibling's timeSlice exceeds its timeNeeded (the plain rule of §4.2, unless one
    // sibling's surplus exceeds c_hystSwitch x timeNeeded), and the counters' hysteresis governs
    // every later switch (player/SELECTION.md).
    double initialHyst = -Constants{}.hystSwitch;
    bool requireLoadedChildren = false;
    // thesis-rh: a drawn node passes its unused slice on to the next sibling of its set, siblings
    // taken from simple to complex (thesis §6.6 future work; Robin Hood §5). Off: the thesis.
    bool passRemainders = false;
};

SelectionParams selectionParams(const Constants& c, double hlod0Share, double vTime, bool requireLoadedChildren);

struct Selection {
    std::vector<DrawItem> drawn;     // the front, in traversal (breadth-first) order
    std::vector<uint32_t> visited;   // every node whose priority was computed this frame
    double drawnCost = 0;            // sum of cost_n over drawn nodes
    uint32_t upToggles = 0, downToggles = 0;  // §6.5 counting rule, culling excluded (player/STATS.md)
    uint32_t reversals = 0;          // toggles undoing the node's previous one within kReversalWindow
    uint32_t misses = 0;             // visible children wanted but not loaded
    uint32_t refused = 0;            // all-loaded sibling sets refused because cumHyst < 0
};

struct PolicyFront;  // player/front.h

// One breadth-first, top-down traversal (§4.2): the front and each drawn node's reason, the
// visited nodes (their priorities set in `state`); hysteresis and time slices are updated,
// roles are not (accountFront does that for every policy). `resident` (one byte per node) tells
// which nodes may be drawn.
PolicyFront traverseThesis(const Skeleton& skeleton, const SelectionParams& params, const Evaluate& evaluate,
                           SelectionState& state, std::span<const uint8_t> resident);

// traverseThesis, then accountFront (roles, toggles; advances state.frame).
Selection selectFront(const Skeleton& skeleton, const SelectionParams& params, const Evaluate& evaluate,
                      SelectionState& state, std::span<const uint8_t> resident);

// cumHyst = sum over siblings of trunc(hyst_i / c_hystSwitch)   (§4.2)
long cumulativeHysteresis(std::span<const double> hysts, double hystSwitch);

// hysteresis += (timeSlice - timeNeeded) / timeNeeded, clamped to +-c_hystLimit   (§4.2)
double updateHysteresis(double hyst, double timeSlice, double timeNeeded, double hystLimit);

}  // namespace hlod
