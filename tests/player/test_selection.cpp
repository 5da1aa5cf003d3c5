// Selection (thesis §4.2) on small hand-built trees: exact fronts for given priorities and
// budgets, the up- and down-switch delays predicted by the hysteresis formula, the first
// counter value, the cumHyst sign rule, the loaded-children rule (§5.2), hlod0 never skipped,
// §6.5 toggle counting (culling excluded).
#include "player/selection.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

using namespace hlod;

namespace {

const Box3f kBox{{0, 0, 0}, {1, 1, 1}};

// Root R (0) with children 1..4; child k has leaves. All costs 100; v_time 0.01 -> 1 ms each.
struct Tree {
    Skeleton s;
    std::map<uint32_t, NodeEval> evals;
    std::vector<uint8_t> resident;
    SelectionParams params;
    SelectionState* state = nullptr;

    explicit Tree(uint32_t roots = 1, bool leaves = true) {
        for (uint32_t r = 0; r < roots; ++r) test::addNode(s, kNone, kBox, 100, 100);
        for (uint32_t r = 0; r < roots; ++r)
            for (int k = 0; k < 4; ++k) test::addNode(s, r, kBox, 100, 100);
        if (leaves) {
            uint32_t n = uint32_t(s.nodes.size());
            for (uint32_t c = roots; c < n; ++c)
                for (int k = 0; k < 4; ++k) test::addNode(s, c, kBox, 100, 100);
        }
        test::linkSkeleton(s);
        resident.assign(s.nodes.size(), 1);
        for (const Node& n : s.nodes) evals[n.id] = {1.0, 1.0};
        params.vTime = 0.01;
        params.hlod0Share = 100;
    }

    Selection run(SelectionState& st) {
        Evaluate e = [&](uint32_t id) { return evals.at(id); };
        return selectFront(s, params, e, st, resident);
    }

    std::set<uint32_t> front(const Selection& sel) const {
        std::set<uint32_t> f;
        for (const DrawItem& d : sel.drawn) f.insert(d.node);
        return f;
    }
};

// The first frame f (0-based) at which `siblings` equal counters, starting at `initial` and
// moving by `delta` per frame (the §4.2 hysteresis update, clamped to +-limit), have trunc-sum cumHyst >= 0
// (up: the children replace the parent) or < 0 (down: the parent replaces the children).
int predictedSwitchFrame(double initial, double delta, double limit, double hystSwitch, int siblings, bool up = true) {
    double h = initial;
    for (int f = 0; f < 100000; ++f) {
        h = std::clamp(h + delta, -limit, limit);
        long cumHyst = siblings * long(std::trunc(h / hystSwitch));
        if (up ? cumHyst >= 0 : cumHyst < 0) return f;
    }
    return -1;
}

}  // namespace

TEST(Hysteresis, UpdateIsNormalisedDifferenceClamped) {
    EXPECT_DOUBLE_EQ(updateHysteresis(0, 3, 1, 4510), 2);     // (3 - 1) / 1
    EXPECT_DOUBLE_EQ(updateHysteresis(10, 0.5, 1, 4510), 9.5);
    EXPECT_DOUBLE_EQ(updateHysteresis(4500, 100, 1, 4510), 4510);
    EXPECT_DOUBLE_EQ(updateHysteresis(-4510, 0, 1, 4510), -4510);
}

TEST(Hysteresis, CumulativeTruncatesTowardZero) {
    std::vector<double> a{1499, -1499};
    EXPECT_EQ(cumulativeHysteresis(a, 1500), 0);
    std::vector<double> b{-1500, 0};
    EXPECT_EQ(cumulativeHysteresis(b, 1500), -1);
    std::vector<double> c{3000, -1600};
    EXPECT_EQ(cumulativeHysteresis(c, 1500), 1);
    std::vector<double> d{-4510, 3100, 1500};
    EXPECT_EQ(cumulativeHysteresis(d, 1500), 0);
}

TEST(Selection, HysteresisDelaysSwitchByPredictedFrames) {
    Tree t(1, false);  // R with 4 leaves: 25 ms slices, 1 ms needed -> +24 per frame
    t.params.initialHyst = -4510;  // counters starting at -c_hystLimit
    SelectionState st(t.s);
    int expected = predictedSwitchFrame(t.params.initialHyst, 24, 4510, 1500, 4);
    ASSERT_EQ(expected, 125);  // -4510 + 24 * 126 = -1486 > -1500
    int switched = -1;
    for (int f = 0; f < 200 && switched < 0; ++f) {
        Selection sel = t.run(st);
        if (sel.drawn.size() == 4) {
            switched = f;
            EXPECT_EQ(sel.upToggles, 1u);
        } else {
            ASSERT_EQ(t.front(sel), std::set<uint32_t>{0});
            EXPECT_EQ(sel.refused, 1u);
        }
    }
    EXPECT_EQ(switched, expected);
}

// The default first counter, -c_hystSwitch: a new sibling set switches on its first frame when
// every slice exceeds timeNeeded, and is refused from the first frame when the slices fall short.
TEST(Selection, FirstCounterAtSwitchThresholdDecidesByPlainRule) {
    Tree t(1, false);
    ASSERT_EQ(t.params.initialHyst, -t.params.hystSwitch);
    SelectionState st(t.s);
    EXPECT_EQ(t.run(st).drawn.size(), 4u);  // 25 ms slices > 1 ms needed: children at once
    Tree u(1, false);
    u.params.hlod0Share = 3.6;  // 0.9 ms slices < 1 ms needed: the parent, frame after frame
    SelectionState su(u.s);
    for (int f = 0; f < 100; ++f) {
        Selection sel = u.run(su);
        ASSERT_EQ(u.front(sel), std::set<uint32_t>{0}) << f;
        ASSERT_EQ(sel.refused, 1u);
    }
    EXPECT_NEAR(su.nodes[1].hyst, -1500 - 100 * 0.1, 1e-6);  // -0.1 per frame
}

TEST(Selection, ExactFrontForPrioritiesAndBudget) {
    // Two roots sharing 20 ms: R0 priority 9 -> 18 ms (children 4.5 ms each, +3.5 per frame),
    // R1 priority 1 -> 2 ms (children 0.5 ms each, -0.5 per frame). Leaves under R0's
    // children get 1.125 ms (+0.125 per frame: far too slow to switch within the run).
    Tree t(2, true);
    t.params.hlod0Share = 20;
    t.params.initialHyst = -4510;
    t.evals[0].priority = 9;
    SelectionState st(t.s);
    int switchAt = predictedSwitchFrame(-4510, 3.5, 4510, 1500, 4);
    ASSERT_EQ(switchAt, 860);
    Selection sel;
    int switched = -1;
    for (int f = 0; f < 1000; ++f) {
        sel = t.run(st);
        std::set<uint32_t> front = t.front(sel);
        if (switched < 0 && front.count(2)) {
            switched = f;
            EXPECT_EQ(sel.upToggles, 1u);
        }
        if (switched < 0) {
            ASSERT_EQ(front, (std::set<uint32_t>{0, 1})) << f;  // both roots until then
        }
    }
    EXPECT_EQ(switched, switchAt);
    std::set<uint32_t> expected{1, 2, 3, 4, 5};  // R1 and R0's children
    EXPECT_EQ(t.front(sel), expected);
    // A bigger budget lets R1 refine as well (its children then get 22.5 ms, +21.5 per frame:
    // frame 140); the leaves below (5.6 ms, +4.6 per frame) are not reached within 200 frames.
    t.params.hlod0Share = 180;
    t.evals[0].priority = 1;
    SelectionState st2(t.s);
    for (int f = 0; f < 200; ++f) sel = t.run(st2);
    EXPECT_EQ(t.front(sel).size(), 8u);
    for (uint32_t id : t.front(sel)) EXPECT_EQ(t.s.nodes[id].level, 1u);
}

// Children -> parent: the counters fall by at most 1 per frame ((timeSlice - timeNeeded) /
// timeNeeded >= -1), so from +c_hystLimit a down-switch takes the frames the formula predicts.
TEST(Selection, DownSwitchDelayedByPredictedFrames) {
    Tree t(1, false);
    SelectionState st(t.s);
    for (int f = 0; f < 300; ++f) t.run(st);  // 25 ms slices: the counters saturate
    for (uint32_t c = 1; c <= 4; ++c) ASSERT_EQ(st.nodes[c].hyst, 4510);
    t.params.hlod0Share = 2;  // 0.5 ms slices for 1 ms needed: -0.5 per frame
    int expected = predictedSwitchFrame(4510, -0.5, 4510, 1500, 4, false);
    ASSERT_EQ(expected, 12019);  // 4510 - 0.5 * 12020 = -1500: trunc -1 each
    int switched = -1;
    for (int f = 0; f < 13000 && switched < 0; ++f) {
        Selection sel = t.run(st);
        if (sel.drawn.size() == 1) {
            switched = f;
            EXPECT_EQ(sel.drawn[0].node, 0u);
            EXPECT_EQ(sel.downToggles, 1u);
        } else {
            ASSERT_EQ(sel.drawn.size(), 4u) << f;
            ASSERT_EQ(sel.downToggles, 0u);
        }
    }
    EXPECT_EQ(switched, expected);
}

TEST(Selection, CumHystSignRuleDecidesParentOrChildren) {
    Tree t(1, false);
    t.params.hlod0Share = 4;  // 1 ms slices = 1 ms needed: counters stay where they are
    SelectionState st(t.s);
    auto preset = [&](std::vector<double> h) {
        for (int k = 0; k < 4; ++k) {
            st.nodes[1 + k].hyst = h[k];
            st.nodes[1 + k].evaluated = true;
        }
    };
    preset({3100, -1600, 0, 0});  // cumHyst = 2 - 1 = 1 >= 0: children
    EXPECT_EQ(t.run(st).drawn.size(), 4u);
    preset({3100, -3100, 0, 0});  // 2 - 2 = 0: still children
    EXPECT_EQ(t.run(st).drawn.size(), 4u);
    preset({3100, -4510, 0, 0});  // 2 - 3 = -1 < 0: the parent
    Selection sel = t.run(st);
    ASSERT_EQ(sel.drawn.size(), 1u);
    EXPECT_EQ(sel.drawn[0].node, 0u);
    EXPECT_EQ(sel.downToggles, 1u);
}

// The four children of root 0 with counters at `hyst`; at +c_hystLimit their set switches
// whenever it may, at -c_hystLimit the parent is drawn (cumHyst < 0).
void presetChildren(SelectionState& st, double hyst) {
    for (int k = 0; k < 4; ++k) {
        st.nodes[1 + k].hyst = hyst;
        st.nodes[1 + k].evaluated = true;
    }
}
void saturateChildren(SelectionState& st) { presetChildren(st, 4510); }

TEST(Selection, VisibleUnloadedSiblingForcesParent) {
    Tree t(1, false);
    SelectionState st(t.s);
    saturateChildren(st);
    t.resident[3] = 0;
    Selection sel = t.run(st);
    EXPECT_EQ(t.front(sel), std::set<uint32_t>{0});
    EXPECT_EQ(sel.misses, 1u);
    // An invisible unloaded child does not block the switch (it is culled)...
    t.evals[3].frustumVis = 0.5;
    sel = t.run(st);
    EXPECT_EQ(t.front(sel), (std::set<uint32_t>{1, 2, 4}));
    // ... unless all children must be loaded (§5.2 option).
    t.params.requireLoadedChildren = true;
    sel = t.run(st);
    EXPECT_EQ(t.front(sel), std::set<uint32_t>{0});
}

// An up toggle undone by a down toggle within kReversalWindow frames is a reversal (flicker);
// the same pair farther apart is not.
TEST(Selection, ReversalsCountTogglesUndoneWithinTheWindow) {
    Tree t(1, false);
    SelectionState st(t.s);
    presetChildren(st, -4510);
    ASSERT_EQ(t.front(t.run(st)), std::set<uint32_t>{0});  // first frame: no previous role, no toggle
    saturateChildren(st);
    Selection up = t.run(st);
    ASSERT_EQ(t.front(up), (std::set<uint32_t>{1, 2, 3, 4}));
    EXPECT_EQ(up.upToggles, 1u);
    EXPECT_EQ(up.reversals, 0u);  // the node's first toggle
    presetChildren(st, -4510);  // the hysteresis rule brings the parent back
    Selection down = t.run(st);
    EXPECT_EQ(down.downToggles, 1u);
    EXPECT_EQ(down.reversals, 1u);
    for (uint64_t f = 0; f < kReversalWindow; ++f) EXPECT_EQ(t.run(st).downToggles, 0u);
    saturateChildren(st);
    Selection late = t.run(st);
    EXPECT_EQ(late.upToggles, 1u);
    EXPECT_EQ(late.reversals, 0u);  // the down toggle was kReversalWindow + 1 frames before
}

// §6.5 "We do not count nodes that are culled away between frames": a parent drawn because none
// of its children is visible, or because a newly visible child is not loaded yet, and its return
// to the children, are not toggles; the same switches made by the hysteresis rule are.
TEST(Selection, CullingAndNewlyVisibleUnloadedChildrenAreNotToggles) {
    Tree t(1, false);
    SelectionState st(t.s);
    saturateChildren(st);
    ASSERT_EQ(t.front(t.run(st)).size(), 4u);  // first frame: refined, no previous role
    auto setVisible = [&](std::vector<uint32_t> ids, double vis) {
        for (uint32_t id : ids) t.evals[id].frustumVis = vis;
    };
    setVisible({1, 2, 3, 4}, 0.5);  // every child culled: the parent is drawn
    Selection culled = t.run(st);
    ASSERT_EQ(t.front(culled), std::set<uint32_t>{0});
    EXPECT_EQ(culled.downToggles, 0u);
    setVisible({1, 2, 3, 4}, 1);  // back in view: the children again
    Selection back = t.run(st);
    ASSERT_EQ(t.front(back).size(), 4u);
    EXPECT_EQ(back.upToggles, 0u);
    setVisible({3}, 0.5);  // one child leaves the view and is evicted ...
    ASSERT_EQ(t.front(t.run(st)), (std::set<uint32_t>{1, 2, 4}));
    t.resident[3] = 0;
    setVisible({3}, 1);  // ... and comes back before it is loaded: the parent for now
    Selection miss = t.run(st);
    ASSERT_EQ(t.front(miss), std::set<uint32_t>{0});
    EXPECT_EQ(miss.misses, 1u);
    EXPECT_EQ(miss.downToggles, 0u);
    EXPECT_EQ(t.run(st).upToggles + t.run(st).downToggles, 0u);  // still waiting: nothing counted
    t.resident[3] = 1;  // loaded: the children again, not a toggle either
    Selection loaded = t.run(st);
    ASSERT_EQ(t.front(loaded).size(), 4u);
    EXPECT_EQ(loaded.upToggles, 0u);
    presetChildren(st, -4510);  // the hysteresis rule: counted both ways
    EXPECT_EQ(t.run(st).downToggles, 1u);
    saturateChildren(st);
    EXPECT_EQ(t.run(st).upToggles, 1u);
}

// A set the hysteresis rule accepts but whose visible child is still loading keeps the parent;
// when the child arrives the switch is an up toggle (a detail decision delayed by loading).
TEST(Selection, SwitchDelayedByLoadingIsAnUpToggle) {
    Tree t(1, false);
    SelectionState st(t.s);
    presetChildren(st, -4510);
    ASSERT_EQ(t.front(t.run(st)), std::set<uint32_t>{0});
    saturateChildren(st);
    t.resident[2] = 0;
    Selection waiting = t.run(st);
    ASSERT_EQ(t.front(waiting), std::set<uint32_t>{0});
    EXPECT_EQ(waiting.misses, 1u);
    t.resident[2] = 1;
    EXPECT_EQ(t.run(st).upToggles, 1u);
}

TEST(Selection, Hlod0NeverSkippedEvenWithTinyBudget) {
    Tree t(6, true);
    t.params.hlod0Share = 1e-6;
    t.evals[5].frustumVis = 0.3;  // outside the frustum: culled, not skipped
    SelectionState st(t.s);
    for (int f = 0; f < 50; ++f) {
        Selection sel = t.run(st);
        EXPECT_EQ(t.front(sel), (std::set<uint32_t>{0, 1, 2, 3, 4}));
    }
}

TEST(Selection, VisitsChildrenOfDrawnNodesForPrefetch) {
    Tree t(1, true);
    t.params.hlod0Share = 2;  // 0.5 ms slices for 1 ms needed: the root is drawn
    SelectionState st(t.s);
    Selection sel = t.run(st);
    EXPECT_EQ(t.front(sel), std::set<uint32_t>{0});
    std::set<uint32_t> visited(sel.visited.begin(), sel.visited.end());
    EXPECT_EQ(visited, (std::set<uint32_t>{0, 1, 2, 3, 4}));  // root drawn, its children evaluated
}

TEST(Priority, FrustumVisibilityAndForeshortening) {
    Camera cam;  // at the origin looking down -Z, 60 degrees
    double v0[3] = {0, 0, 0};
    View view = makeView(cam, v0, 0.5);
    Box3f ahead{{-1, -1, -11}, {1, 1, -9}};
    Box3f behind{{-1, -1, 9}, {1, 1, 11}};
    Box3f nearEdge{{13, -1, -11}, {14, 1, -9}};  // just outside the right plane
    EXPECT_EQ(frustumVis(view, ahead), 1.0);
    EXPECT_EQ(frustumVis(view, behind), 0.0);
    double edge = frustumVis(view, nearEdge);
    EXPECT_GT(edge, 0.0);
    EXPECT_LT(edge, 1.0);

    Constants c;
    Node facing;
    facing.bounds = ahead;
    facing.cost = 100;
    facing.staticBenefit = 1000;
    facing.avgNormal = {0, 0, 1};  // towards the camera
    Node away = facing;
    away.avgNormal = {0, 0, -1};
    double pf = nodePriority(facing, view, c, 1), pa = nodePriority(away, view, c, 1);
    EXPECT_NEAR(pf / pa, (1 + c.fore) / (1 - c.fore), 1e-9);
    // priority = benefit * (1 + c_vis) * (1 + c_fore) / (cost * distance^2), distance 9
    EXPECT_NEAR(pf, 1000 * (1 + c.vis) * (1 + c.fore) / (100 * 81.0), 1e-9);
    EXPECT_NEAR(nodePriority(facing, view, c, 0) / pf, 1 / (1 + c.vis), 1e-12);
}

TEST(Priority, VelocityBringsNodesAheadCloser) {
    Camera cam;
    double still[3] = {0, 0, 0}, moving[3] = {0, 0, -10};
    Node n;
    n.bounds = {{-1, -1, -21}, {1, 1, -19}};
    n.cost = 1;
    n.staticBenefit = 1;
    Constants c;
    double p0 = nodePriority(n, makeView(cam, still, 0.5), c, 1);
    double p1 = nodePriority(n, makeView(cam, moving, 0.5), c, 1);
    EXPECT_NEAR(p1 / p0, (19.0 * 19.0) / (14.0 * 14.0), 1e-9);
}
