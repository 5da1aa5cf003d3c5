// The solver policies (player/policy_solvers.cpp, player/policy_fs_node.cpp) on hand-built trees:
// the mapping's cuts are the thesis's cuts at each depth, every solver's front is a valid cut
// (also when blocks may be skipped), within the budget where the solver promises it, and never
// better than the block oracle's on the same frame, except fs-node's, whose fronts are not
// limited to whole depth cuts: on one block it beats fs-greedy between two depth cuts and it
// reaches full detail when the budget allows.
#include "player/camera_path.h"
#include "player/choice_map.h"
#include "player/front.h"
#include "player/policy.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

using namespace hlod;

namespace {

struct Frame {
    View view;
    Projection projection;
    Evaluate evaluate;
    Frame(const Skeleton& s, const Constants& c, const Camera& cam) {
        double velocity[3] = {0, 0, 0};
        view = makeView(cam, velocity, 0.5);
        projection = makeProjection(cam, 720);
        evaluate = [&s, &c, this](uint32_t id) {
            double fv = frustumVis(view, s.nodes[id].bounds);
            return NodeEval{nodePriority(s.nodes[id], view, c, fv), fv};
        };
    }
};

const char* kSolvers[] = {"fs-greedy", "fs-incremental", "fs-hold", "rh", "gb", "fs-node", "fs-node-inc", "oracle"};

// One frame of `policy` over `s` with everything resident: the drawn nodes, their cost (ms) and benefit.
struct Drawn {
    std::vector<uint32_t> nodes;
    double ms = 0, benefit = 0;
};
Drawn drawOnce(const Skeleton& s, const char* policy, const Camera& cam, double budgetMs, double vTime) {
    Constants c;
    Frame fr(s, c, cam);
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    SelectionState state(s);
    PolicyFrame pf{s, c, cam, fr.view, fr.projection, fr.evaluate, resident, 0, budgetMs + 2, 2, vTime, budgetMs, false,
                   -c.hystSwitch};
    PolicyFront f = makePolicy(policy)->select(pf, state);
    auto visible = [&](uint32_t id) { return frustumVis(fr.view, s.nodes[id].bounds) >= 1; };
    EXPECT_EQ(checkCut(s, f.drawn, resident, visible, f.skipsBlocks), "") << policy;
    FrontAccount a = accountFront(s, state, f.drawn);
    Drawn d{{}, vTime * a.drawnCost, frontBenefit(s, a.items, fr.projection, visible)};
    for (const DrawnNode& n : f.drawn) d.nodes.push_back(n.node);
    std::sort(d.nodes.begin(), d.nodes.end());
    return d;
}

}  // namespace

TEST(ChoiceMap, OptionsAreTheCutsAtEachDepth) {
    Skeleton s = test::errorGridSkeleton(2, 1, 3);  // per block: 1 + 4 + 16 nodes, all visible from above
    Constants c;
    Camera cam;
    cam.position[0] = 50, cam.position[1] = 25, cam.position[2] = 400;  // above the z = 0 ground, looking down
    Frame fr(s, c, cam);
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    SelectionState state(s);
    ChoiceMap m = mapChoice(s, fr.projection, fr.evaluate, resident, state, {.budgetMs = 10, .vTime = 0.001});
    ASSERT_EQ(m.problem.objects.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        const ChoiceObject& o = m.problem.objects[i];
        ASSERT_EQ(o.options.size(), 3u);
        for (uint32_t d = 0; d < 3; ++d) {
            EXPECT_EQ(m.cuts[i][d].size(), size_t(std::pow(4, d)));  // c_levelFactor 4 children a node
            for (uint32_t id : m.cuts[i][d]) EXPECT_EQ(s.nodes[id].level, d);
            EXPECT_NEAR(o.options[d].cost, 0.001 * 512 * std::pow(4, d), 1e-9);
            EXPECT_DOUBLE_EQ(o.options[d].samples, 512 * std::pow(4, d));
        }
        EXPECT_LT(o.options[0].benefit, o.options[2].benefit);  // finer cuts: smaller projected error
    }
    resident[m.cuts[0][2][5]] = 0;  // one leaf missing: that cut is not available
    SelectionState st2(s);
    ChoiceMap m2 = mapChoice(s, fr.projection, fr.evaluate, resident, st2, {.budgetMs = 10, .vTime = 0.001});
    EXPECT_FALSE(m2.problem.objects[0].options[2].available);
    EXPECT_TRUE(m2.problem.objects[0].options[1].available);
    EXPECT_TRUE(m2.problem.objects[1].options[2].available);
}

TEST(SolverPolicies, ValidCutsWithinBudgetAndNeverAboveTheOracle) {
    Skeleton s = test::errorGridSkeleton(3, 3, 4);
    PathOptions po;
    po.kind = PathKind::Walk;
    CameraPath path = generatePath(s, po);
    Constants c;
    for (bool skip : {false, true}) {
        PolicyOptions opt;
        for (const char* n : kSolvers) opt.values[std::string(n) + ".allow_skip"] = skip;
        std::vector<std::unique_ptr<SelectionPolicy>> policies;
        std::vector<SelectionState> states;
        for (const char* n : kSolvers) policies.push_back(makePolicy(n, opt)), states.emplace_back(s);
        std::vector<uint8_t> resident(s.nodes.size(), 0);  // hlod0 resident, the rest loads as visited
        for (const Node& n : s.nodes) resident[n.id] = n.parent == kNone;
        const double vTime = 0.001, overhead = 2, target = skip ? 3 : 12;  // skip: even hlod0 does not fit
        uint64_t frame = 0, belowOracle = 0, nodeAboveOracle = 0;
        for (double t = 0; t < path.duration() && frame < 400; t += 0.05, ++frame) {
            Camera cam = sampleCameraPath(path, t, 16.0 / 9.0);
            Frame fr(s, c, cam);
            auto visible = [&](uint32_t id) { return frustumVis(fr.view, s.nodes[id].bounds) >= 1; };
            PolicyFrame pf{s, c, cam, fr.view, fr.projection, fr.evaluate, resident, frame, target, overhead, vTime,
                           target, false, -c.hystSwitch};
            std::vector<double> benefit, cost;
            std::vector<uint32_t> visited;
            for (size_t k = 0; k < policies.size(); ++k) {
                PolicyFront f = policies[k]->select(pf, states[k]);
                ASSERT_EQ(checkCut(s, f.drawn, resident, visible, f.skipsBlocks), "") << kSolvers[k] << " frame " << frame;
                EXPECT_TRUE(skip || !f.skipsBlocks);
                FrontAccount a = accountFront(s, states[k], f.drawn);
                benefit.push_back(frontBenefit(s, a.items, fr.projection, visible));
                cost.push_back(vTime * a.drawnCost);
                if (k == 0) visited = f.visited;
            }
            double budget = target - overhead, oracle = benefit.back();
            EXPECT_LE(cost.back(), budget + 1e-9) << frame;
            for (size_t k = 0; k + 1 < policies.size(); ++k) {
                if (std::string(kSolvers[k]) != "rh") {  // rh may overrun where hlod0 is forced
                    EXPECT_LE(cost[k], budget + 1e-9) << kSolvers[k] << " frame " << frame;
                }
                if (std::string(kSolvers[k]).starts_with("fs-node")) {  // not limited to the oracle's depth cuts
                    nodeAboveOracle += benefit[k] > oracle * (1 + 1e-9);
                } else if (cost[k] <= budget + 1e-9) {
                    EXPECT_LE(benefit[k], oracle * (1 + 1e-12)) << kSolvers[k] << " frame " << frame;
                }
                belowOracle += benefit[k] < oracle * (1 - 1e-9);
            }
            uint32_t loads = 3;  // a stand-in loader: 3 visible nodes a frame, in visit order
            for (uint32_t id : visited)
                if (loads && !resident[id] && visible(id)) resident[id] = 1, --loads;
        }
        EXPECT_GT(belowOracle, 0u);  // the solvers do fall short of the optimum on some frames
        EXPECT_TRUE(skip || nodeAboveOracle > 0);  // with skips only whole hlod0 nodes fit: no refinement does
    }
}

// One block of 1 + 4 + 16 + 64 nodes of 512 triangles, all visible: its depth cuts cost 0.512,
// 2.048, 8.192 and 32.768 ms at 1 us a triangle. With 5 ms fs-greedy (and the block oracle) stop
// at depth 1; fs-node refines one more depth-1 node (2.048 + 1.536 ms) and draws more benefit.
TEST(SolverPolicies, FsNodeBeatsFsGreedyBetweenTwoDepthCutsOfOneBlock) {
    Skeleton s = test::errorGridSkeleton(1, 1, 4);
    Camera cam;
    cam.position[0] = 25, cam.position[1] = 25, cam.position[2] = 200;  // above the block, looking down
    Drawn greedy = drawOnce(s, "fs-greedy", cam, 5, 0.001), node = drawOnce(s, "fs-node", cam, 5, 0.001);
    EXPECT_EQ(greedy.nodes.size(), 4u);
    EXPECT_NEAR(greedy.ms, 2.048, 1e-9);
    EXPECT_EQ(node.nodes.size(), 7u);
    EXPECT_NEAR(node.ms, 3.584, 1e-9);
    EXPECT_GT(node.benefit, greedy.benefit * 1.01);
    EXPECT_EQ(drawOnce(s, "oracle", cam, 5, 0.001).nodes, greedy.nodes);
}

// With a budget over full detail, fs-node draws what `none` draws: every visible leaf.
TEST(SolverPolicies, FsNodeReachesFullDetailWhenTheBudgetAllows) {
    Skeleton s = test::errorGridSkeleton(2, 2, 4);
    Camera cam;
    cam.position[0] = 50, cam.position[1] = 50, cam.position[2] = 300;
    Drawn none = drawOnce(s, "none", cam, 1000, 0.001), node = drawOnce(s, "fs-node", cam, 1000, 0.001);
    EXPECT_EQ(none.nodes.size(), 4u * 64);
    EXPECT_EQ(node.nodes, none.nodes);
    Drawn tight = drawOnce(s, "fs-node", cam, 130, 0.001);  // full detail is 131.072 ms
    EXPECT_LT(tight.nodes.size(), none.nodes.size());
    EXPECT_LE(tight.ms, 130);
}

TEST(SolverPolicies, SettingsAreCheckedAndBadValuesRefused) {
    std::vector<std::string> names = {"rh"};
    PolicyOptions bad;
    bad.values["rh.value"] = 12;
    EXPECT_THROW(makePolicy("rh", bad), std::invalid_argument);
    PolicyOptions unknown;
    unknown.values["gb.nothing"] = 1;
    std::string gb[] = {"gb"};
    EXPECT_THROW(checkPolicySettings(gb, unknown), std::invalid_argument);
    PolicyOptions ok;
    ok.values["gb.opt_ms"] = 0.2;
    EXPECT_NO_THROW(checkPolicySettings(gb, ok));
}

// Every setting has a range, checked by checkPolicySettings (before a run) and by makePolicy;
// before stop 36 oracle.max_states=1e20 crashed play (size_t overflow) and negatives ran.
TEST(SolverPolicies, SettingsOutsideTheirRangeAreRefused) {
    for (const PolicyInfo& p : policyRegistry()) {
        std::istringstream settings(p.settings);
        for (std::string setting; settings >> setting;) EXPECT_NE(policySettingRange(setting), "") << p.name << "." << setting;
    }
    const std::pair<const char*, double> refused[] = {
        {"oracle.max_states", 1e20}, {"oracle.max_states", 0},   {"oracle.max_states", 2.5}, {"static.pixels", -1},
        {"sse.tolerance", -1},        {"gb.max_newton", -1},      {"gb.opt_ms", -1},          {"rh.logic_ms", -1},
        {"rh.value", 12},            {"rh.c", 0},                {"hold.exchange_gain", -1}, {"hold.headroom", 1},
        {"fs-node.pixel_ms", -1},    {"fs-greedy.allow_skip", 5}, {"fs-hold.headroom", -0.1},
    };
    for (const auto& [key, value] : refused) {
        PolicyOptions o;
        o.values[key] = value;
        const std::string name = std::string(key).substr(0, std::string(key).find('.'));
        const std::string names[] = {name};
        EXPECT_THROW(checkPolicySettings(names, o), std::invalid_argument) << key << "=" << value;
        EXPECT_THROW(makePolicy(name, o), std::invalid_argument) << key << "=" << value;
    }
    PolicyOptions edge;  // the ends of the ranges are accepted
    edge.values = {{"oracle.max_states", 1e9}, {"oracle.allow_skip", 1}, {"oracle.pixel_ms", 0}};
    const std::string oracle[] = {"oracle"};
    EXPECT_NO_THROW(checkPolicySettings(oracle, edge));
    EXPECT_NO_THROW(makePolicy("oracle", edge));
    PolicyOptions big;
    big.values["oracle.max_states"] = 1e20;
    try {
        checkPolicySettings(oracle, big);
        ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "policy setting oracle.max_states=1e+20 must be a whole number in [1, 1e9]");
    }
}

// fs-node-inc on a still view with everything resident: from hlod0 it settles within two
// frames (FS §6's coherence), then each frame is one iteration (a raise undone by a merge) with no
// toggles, within the budget and within 0.1 % of fs-node's greedy benefit.
TEST(SolverPolicies, FsNodeIncrementalSettlesOnTheGreedyOnAStillView) {
    Skeleton s = test::errorGridSkeleton(3, 3, 4);
    Camera cam;
    cam.position[0] = 75, cam.position[1] = 75, cam.position[2] = 150;  // above the grid's centre, looking down
    Constants c;
    Frame fr(s, c, cam);
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    auto visible = [&](uint32_t id) { return frustumVis(fr.view, s.nodes[id].bounds) >= 1; };
    for (double budget : {5.0, 12.0, 30.0, 80.0}) {
        SelectionState a(s), b(s);
        auto incremental = makePolicy("fs-node-inc"), greedy = makePolicy("fs-node");
        for (uint64_t frame = 0; frame < 8; ++frame) {
            PolicyFrame pf{s, c, cam, fr.view, fr.projection, fr.evaluate, resident, frame, budget + 2, 2, 0.001, budget,
                           false, -c.hystSwitch};
            PolicyFront fi = incremental->select(pf, a), fg = greedy->select(pf, b);
            FrontAccount ai = accountFront(s, a, fi.drawn), ag = accountFront(s, b, fg.drawn);
            EXPECT_LE(0.001 * ai.drawnCost, budget + 1e-9);
            if (frame < 2) continue;
            double bi = frontBenefit(s, ai.items, fr.projection, visible);
            double bg = frontBenefit(s, ag.items, fr.projection, visible);
            EXPECT_NEAR(bi, bg, 1e-3 * bg) << budget;
            EXPECT_EQ(fi.iterations, 1u) << budget;
            EXPECT_EQ(ai.upToggles + ai.downToggles, 0u) << budget;
        }
    }
}
