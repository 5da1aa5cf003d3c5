// Funkhouser & Séquin's selection with front nodes as its objects (T. A. Funkhouser and C. H.
// Séquin, "Adaptive Display Algorithm for Interactive Frame Rates During Visualization of Complex
// Virtual Environments", SIGGRAPH 1993, §3 eq. 1, §4 Cost, §5 Benefit, §6 greedy by Value), in
// the node-granular form of hierarchical LOD selection (Mason & Blake 1997, "Automatic
// Hierarchical Level of Detail Optimization in Computer Animation", Eurographics; not among the
// seed papers): the front starts at the visible hlod0 nodes and a step refines one front node,
// replacing it by its visible children (player/SOLVERS.md "fs-node"). The steps form a tree
// knapsack: a node's refinement is a candidate only after its parent's was taken. Plain data;
// the policy (player/policy_fs_node.cpp) builds the steps from a skeleton lazily, through
// `expand`, so only the children of front nodes are ever evaluated.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace hlod {

inline constexpr uint32_t kNoStep = 0xFFFFFFFFu;

// One block's FS §4 Cost: max(per-primitive, per-pixel) while drawn, 0 when skipped.
struct BlockCost {
    double primMs = 0;   // v_time x sum of cost_n of the block's front nodes
    double pixelMs = 0;  // FS §4 C3 Pix(O): pixel_ms x the block root's projected pixels
    bool drawn = true;   // false: the block is skipped (allow_skip) until a step inserts its root
};
double blockCostMs(const BlockCost& block);

// One item of the frame's tree knapsack.
struct RefineStep {
    uint32_t node = 0;          // the front node this step refines (or the root it inserts)
    uint32_t parent = kNoStep;  // the step that must be taken first; kNoStep: `node` is in the base front
    uint32_t block = 0;         // index into NodeProblem::blocks
    double primMs = 0;          // change of the block's primMs (children's cost - the node's)
    double benefit = 0;         // change of the common benefit (children's - the node's)
    bool inserts = false;       // draws a skipped block's root instead of refining a node
};

struct NodeProblem {
    std::vector<BlockCost> blocks;  // the base front's blocks
    std::vector<RefineStep> steps;  // the base front's steps; expand appends the rest
    double budget = 0;              // ms the blocks may cost together (target minus overhead)
    // Called when step `taken` is taken: appends the steps of the front nodes it creates (each
    // with parent = taken). Steps without a gain (benefit <= 0) may be appended; they are never taken.
    std::function<void(uint32_t taken, NodeProblem&)> expand;
};

struct NodeChoice {
    std::vector<uint8_t> taken;   // per step of the problem
    std::vector<uint32_t> order;  // the steps taken, in the order taken
    double cost = 0;              // sum of the blocks' FS §4 costs after the steps
    double benefit = 0;           // benefit gained over the base
    uint32_t iterations = 0;      // steps popped from the priority queue
    bool bestSingleWon = false;   // the best single chain replaced the greedy's steps
};

double problemCostMs(const NodeProblem& problem);  // sum of blockCostMs (the base's cost)

// Greedy by Value (FS §6): pops the candidate step of highest Value = benefit / cost change
// (+inf when it costs nothing) from a priority queue, takes it when the cost stays within the
// budget (or does not grow) and skips it otherwise, then pushes the steps it makes possible;
// stops when the queue is empty. With bestSingle, the best single chain (one popped step with
// the steps it needs, alone over the base) replaces the greedy's steps when it gains more: FS
// §6's "at least half as good as the optimal solution" then holds when Values do not rise from
// a step to the steps below it (player/SOLVERS.md "fs-node").
NodeChoice fsNodeGreedy(NodeProblem& problem, bool bestSingle = true);

}  // namespace hlod
