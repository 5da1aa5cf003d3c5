// Greedy by Value over front nodes (player/fs_node.h): T. A. Funkhouser and C. H. Séquin,
// SIGGRAPH 1993, §6 ("add object tuples to S in descending order of Value (Benefit / Cost)
// until the maximum cost is completely claimed"), with the objects being the front's nodes and
// a tuple's increment one refinement (player/SOLVERS.md "fs-node"), kept in a priority queue.
#include "player/fs_node.h"

#include <algorithm>
#include <limits>
#include <queue>

namespace hlod {
namespace {

double valueOf(double benefit, double cost) {  // FS §6: Value = Benefit / Cost
    return cost > 0 ? benefit / cost : std::numeric_limits<double>::infinity();
}

// FS §4: the change of the block's Cost = max(per-primitive, per-pixel) when step s is taken.
double stepCost(const RefineStep& s, const BlockCost& block) {
    BlockCost after = block;
    after.drawn = true;
    after.primMs += s.primMs;
    return blockCostMs(after) - blockCostMs(block);
}

struct Entry {
    double value;
    uint32_t node, step;
    bool operator<(const Entry& o) const {  // max-heap on Value; ties: the lower node id first
        return value != o.value ? value < o.value : node > o.node;
    }
};

// The steps `step` needs, from its base-front ancestor down to itself.
std::vector<uint32_t> chainOf(const NodeProblem& p, uint32_t step) {
    std::vector<uint32_t> chain;
    for (uint32_t s = step; s != kNoStep; s = p.steps[s].parent) chain.push_back(s);
    std::reverse(chain.begin(), chain.end());
    return chain;
}

// The best single chain over the base (FS §6's bound needs "the best single item": here a popped
// step with the steps it needs); kNoStep when none gains more than `benefit` within the budget.
uint32_t bestSingleChain(const NodeProblem& p, const std::vector<uint32_t>& popped, double benefit) {
    const double base = problemCostMs(p);
    uint32_t best = kNoStep;
    for (uint32_t x : popped) {
        BlockCost b = p.blocks[p.steps[x].block];
        double gain = 0;
        for (uint32_t s : chainOf(p, x)) b.drawn = true, b.primMs += p.steps[s].primMs, gain += p.steps[s].benefit;
        double cost = base - blockCostMs(p.blocks[p.steps[x].block]) + blockCostMs(b);
        if (gain > benefit && (cost <= p.budget || cost <= base)) benefit = gain, best = x;
    }
    return best;
}

}  // namespace

double blockCostMs(const BlockCost& b) { return b.drawn ? std::max(b.primMs, b.pixelMs) : 0; }

double problemCostMs(const NodeProblem& p) {
    double sum = 0;
    for (const BlockCost& b : p.blocks) sum += blockCostMs(b);
    return sum;
}

NodeChoice fsNodeGreedy(NodeProblem& p, bool bestSingle) {
    NodeChoice c;
    std::vector<BlockCost> blocks = p.blocks;
    c.cost = problemCostMs(p);
    std::priority_queue<Entry> queue;
    std::vector<uint32_t> popped, dropped;
    size_t queued = 0;
    auto queueNew = [&] {  // a step that adds no benefit is never taken
        for (; queued < p.steps.size(); ++queued) {
            const RefineStep& s = p.steps[queued];
            if (s.benefit > 0) queue.push({valueOf(s.benefit, stepCost(s, blocks[s.block])), s.node, uint32_t(queued)});
        }
    };
    queueNew();
    while (!queue.empty()) {
        Entry e = queue.top();
        queue.pop();
        const RefineStep s = p.steps[e.step];  // a copy: expand appends to p.steps
        double dc = stepCost(s, blocks[s.block]);
        double value = valueOf(s.benefit, dc);
        if (value < e.value) {  // the block's per-pixel term took part of the cost change: re-queue
            queue.push({value, s.node, e.step});
            continue;
        }
        ++c.iterations;
        popped.push_back(e.step);
        if (dc > 0 && c.cost + dc > p.budget) {  // FS eq. 1: the sum of Cost stays within TargetFrameTime
            dropped.push_back(e.step);
            continue;
        }
        c.cost += dc;
        blocks[s.block].drawn = true;
        blocks[s.block].primMs += s.primMs;
        c.benefit += s.benefit;
        c.order.push_back(e.step);
        if (dc < 0) {  // the cost fell: the steps dropped as too dear may fit now
            for (uint32_t d : dropped) {
                const RefineStep& x = p.steps[d];
                queue.push({valueOf(x.benefit, stepCost(x, blocks[x.block])), x.node, d});
            }
            dropped.clear();
        }
        if (p.expand) p.expand(e.step, p);
        queueNew();
    }
    if (bestSingle) {
        uint32_t x = bestSingleChain(p, popped, c.benefit);
        if (x != kNoStep) {
            c.order = chainOf(p, x);
            c.benefit = 0;
            blocks = p.blocks;
            for (uint32_t s : c.order) {
                BlockCost& b = blocks[p.steps[s].block];
                b.drawn = true, b.primMs += p.steps[s].primMs, c.benefit += p.steps[s].benefit;
            }
            c.cost = 0;
            for (const BlockCost& b : blocks) c.cost += blockCostMs(b);
            c.bestSingleWon = true;
        }
    }
    c.taken.assign(p.steps.size(), 0);
    for (uint32_t s : c.order) c.taken[s] = 1;
    return c;
}

}  // namespace hlod
