// The greedy over front nodes (player/fs_node.h) on hand-built step trees: it takes the steps in
// Value order (a hand-computed case), never exceeds the budget, takes the best single chain where
// FS's half-optimality needs it, holds that bound against brute force when Values do not rise
// down the tree, and has no constant bound when they do.
#include "player/fs_node.h"

#include <gtest/gtest.h>

#include <random>

using namespace hlod;

namespace {

// A step tree as a table: entry k refines node k; parent: the table entry taken first (-1: base).
struct TableStep {
    int parent;
    uint32_t block;
    double primMs, benefit;
};

// The problem over `table`, the base steps present and the rest appended by expand.
NodeProblem fromTable(const std::vector<TableStep>& table, std::vector<BlockCost> blocks, double budget) {
    NodeProblem p;
    p.blocks = std::move(blocks);
    p.budget = budget;
    auto add = [&table](NodeProblem& q, uint32_t k, uint32_t parent) {
        q.steps.push_back({k, parent, table[k].block, table[k].primMs, table[k].benefit, false});
    };
    for (uint32_t k = 0; k < table.size(); ++k)
        if (table[k].parent < 0) add(p, k, kNoStep);
    p.expand = [&table, add](uint32_t taken, NodeProblem& q) {
        uint32_t node = q.steps[taken].node;
        for (uint32_t k = 0; k < table.size(); ++k)
            if (table[k].parent == int(node)) add(q, k, taken);
    };
    return p;
}

std::vector<uint32_t> takenNodes(const NodeProblem& p, const NodeChoice& c) {
    std::vector<uint32_t> nodes;
    for (uint32_t s : c.order) nodes.push_back(p.steps[s].node);
    return nodes;
}

// The exact optimum over every parent-closed set of table steps (cost with the blocks' FS §4 max).
double bruteForce(const std::vector<TableStep>& table, const std::vector<BlockCost>& blocks, double budget) {
    double best = 0;
    for (uint32_t set = 0; set < (1u << table.size()); ++set) {
        std::vector<BlockCost> b = blocks;
        double benefit = 0, cost = 0;
        bool closed = true;
        for (uint32_t k = 0; k < table.size(); ++k) {
            if (!(set >> k & 1)) continue;
            closed = closed && (table[k].parent < 0 || (set >> table[k].parent & 1));
            b[table[k].block].primMs += table[k].primMs;
            benefit += table[k].benefit;
        }
        for (const BlockCost& x : b) cost += blockCostMs(x);
        if (closed && cost <= budget + 1e-12) best = std::max(best, benefit);
    }
    return best;
}

}  // namespace

// Two blocks of base cost 1. Values: A 10/2 = 5, B 3/1 = 3; A's children A1 4/1 = 4, A2 4/4 = 1.
// Budget 6 = the base 2 + A 2 + A1 1 + B 1: the greedy takes A, A1, B and drops A2 (4 > 0 left).
TEST(FsNode, RefinesInValueOrder) {
    std::vector<TableStep> table = {{-1, 0, 2, 10}, {-1, 1, 1, 3}, {0, 0, 1, 4}, {0, 0, 4, 4}};
    NodeProblem p = fromTable(table, {{1, 0}, {1, 0}}, 6);
    NodeChoice c = fsNodeGreedy(p);
    EXPECT_EQ(takenNodes(p, c), (std::vector<uint32_t>{0, 2, 1}));
    EXPECT_DOUBLE_EQ(c.cost, 6);
    EXPECT_DOUBLE_EQ(c.benefit, 17);
    EXPECT_EQ(c.iterations, 4u);  // A2 popped and dropped
    EXPECT_FALSE(c.bestSingleWon);
    // With the budget for A2 too, everything is taken, A2 last (lowest Value).
    NodeProblem all = fromTable(table, {{1, 0}, {1, 0}}, 10);
    EXPECT_EQ(takenNodes(all, fsNodeGreedy(all)), (std::vector<uint32_t>{0, 2, 1, 3}));
}

// FS §4's per-pixel term: a block whose pixels cost 3 ms makes its first 2 ms of refinement free
// (Value +inf), then only the part above the pixel cost counts.
TEST(FsNode, CostIsTheMaximumOfThePerPrimitiveAndPerPixelTerms) {
    std::vector<TableStep> table = {{-1, 0, 2, 1}, {0, 0, 2, 1}, {-1, 1, 1, 1.5}};
    NodeProblem p = fromTable(table, {{1, 3}, {1, 0}}, 5);  // base: max(1, 3) + 1 = 4
    NodeChoice c = fsNodeGreedy(p);
    // step 0 costs max(3, 3) - 3 = 0 (+inf); then step 2 (1.5 / 1) before step 1 (1 / 2); step 1 does not fit.
    EXPECT_EQ(takenNodes(p, c), (std::vector<uint32_t>{0, 2}));
    EXPECT_DOUBLE_EQ(c.cost, 5);
}

// The textbook case for "the best single item" (FS §6, [6]): a cheap step of Value 2 takes the
// budget from a dear step of Value 1 that alone would fill it. Greedy alone: 0.2 of 10.
TEST(FsNode, TakesTheBestSingleChainWhenItGainsMore) {
    std::vector<TableStep> table = {{-1, 0, 0.1, 0.2}, {-1, 1, 1, 1}, {1, 1, 9, 9}};  // the dear chain: 1 then 2
    NodeProblem p = fromTable(table, {{0, 0}, {0, 0}}, 10);
    NodeChoice greedy = fsNodeGreedy(p, false);
    EXPECT_DOUBLE_EQ(greedy.benefit, 1.2);  // step 0, then 1; 2 no longer fits (0.1 + 1 + 9 > 10)
    NodeProblem q = fromTable(table, {{0, 0}, {0, 0}}, 10);
    NodeChoice best = fsNodeGreedy(q, true);
    EXPECT_TRUE(best.bestSingleWon);
    EXPECT_EQ(takenNodes(q, best), (std::vector<uint32_t>{1, 2}));
    EXPECT_DOUBLE_EQ(best.benefit, 10);
    EXPECT_DOUBLE_EQ(best.cost, 10);
}

// Random step trees (up to 14 steps, 1-3 blocks, sometimes a per-pixel term): the cost never
// exceeds the budget when the base fits, and where no step's Value exceeds its parent's (FS §6's
// "diminishing returns") greedy + best single chain >= half the brute-force optimum; without
// best single it falls under half on some instance.
TEST(FsNode, WithinBudgetAndHalfTheOptimumWhenValuesDoNotRise) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    uint32_t underHalfWithout = 0;
    for (int trial = 0; trial < 600; ++trial) {
        uint32_t n = 1 + trial % 14, nb = 1 + trial % 3;
        std::vector<BlockCost> blocks(nb);
        for (BlockCost& b : blocks) b = {0.5 + u(rng), trial % 4 == 0 ? 3 * u(rng) : 0};
        std::vector<TableStep> table;
        for (uint32_t k = 0; k < n; ++k) {
            int parent = k == 0 || u(rng) < 0.3 ? -1 : int(u(rng) * k);
            uint32_t block = parent < 0 ? uint32_t(u(rng) * nb) : table[size_t(parent)].block;
            double cost = 0.05 + 3 * u(rng) * u(rng), value = 0.1 + 5 * u(rng);
            if (parent >= 0) value = std::min(value, table[size_t(parent)].benefit / table[size_t(parent)].primMs);
            table.push_back({parent, block, cost, value * cost});
        }
        double base = 0, all = 0;
        for (const BlockCost& b : blocks) base += blockCostMs(b);
        for (const TableStep& t : table) all += t.primMs;
        double budget = base + all * u(rng);
        double opt = bruteForce(table, blocks, budget);
        NodeProblem p = fromTable(table, blocks, budget);
        NodeChoice c = fsNodeGreedy(p);
        ASSERT_LE(c.cost, budget + 1e-9) << trial;
        EXPECT_LE(c.benefit, opt + 1e-9) << trial;
        EXPECT_GE(c.benefit, 0.5 * opt - 1e-9) << trial;
        NodeProblem q = fromTable(table, blocks, budget);
        underHalfWithout += fsNodeGreedy(q, false).benefit < 0.5 * opt;
    }
    EXPECT_GT(underHalfWithout, 0u);
}

// A step of low Value hiding a step of high Value below it (Values rising down the tree): the
// greedy spends the budget on a middling step, and no single chain helps. Greedy 2 of 100.1.
TEST(FsNode, NoConstantBoundWhenValuesRiseDownTheTree) {
    std::vector<TableStep> table = {{-1, 0, 1, 0.1}, {0, 0, 1, 100}, {-1, 1, 2, 2}};
    std::vector<BlockCost> blocks = {{0, 0}, {0, 0}};
    NodeProblem p = fromTable(table, blocks, 2);
    NodeChoice c = fsNodeGreedy(p);
    EXPECT_DOUBLE_EQ(c.benefit, 2);
    EXPECT_DOUBLE_EQ(bruteForce(table, blocks, 2), 100.1);
}
