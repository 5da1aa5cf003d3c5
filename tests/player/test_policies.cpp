// Selection policies (player/policy.h): the thesis through the interface equals the direct
// traversal frame by frame; every policy yields a valid cut on hand-built trees while the camera
// moves and nodes load; thesis-rh passes remainders in order and conserves time.
#include "player/camera_path.h"
#include "player/front.h"
#include "player/policy.h"
#include "tests/support/trees.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace hlod;

namespace {

// One policy frame over `s` from `camera`, the way the Player builds it.
struct Harness {
    const Skeleton& s;
    Constants c;
    std::vector<uint8_t> resident;
    double vTime = 0.001, share = 28, overhead = 2;
    bool requireLoaded = false;
    explicit Harness(const Skeleton& sk) : s(sk), resident(sk.nodes.size(), 0) {
        for (const Node& n : s.nodes) resident[n.id] = n.parent == kNone;
    }
    template <class F>
    auto withFrame(const Camera& camera, uint64_t frame, F&& f) {
        double velocity[3] = {0, 0, 0};
        View view = makeView(camera, velocity, 0.5);
        Projection projection = makeProjection(camera, 720);
        Evaluate evaluate = [&](uint32_t id) {
            double fv = frustumVis(view, s.nodes[id].bounds);
            return NodeEval{nodePriority(s.nodes[id], view, c, fv), fv};
        };
        PolicyFrame pf{s, c, camera, view, projection, evaluate, resident, frame, c.targetTimeMs, overhead, vTime, share,
                       requireLoaded, -c.hystSwitch};
        auto visible = [&](uint32_t id) { return frustumVis(view, s.nodes[id].bounds) >= 1; };
        return f(pf, evaluate, visible);
    }
    // Loads up to `n` visited non-resident nodes (a stand-in for the loader), in list order.
    void load(const std::vector<uint32_t>& visited, uint32_t n) {
        for (uint32_t id : visited)
            if (n && !resident[id]) resident[id] = 1, --n;
    }
};

CameraPath walk(const Skeleton& s) {
    PathOptions o;
    o.kind = PathKind::Walk;
    return generatePath(s, o);
}

}  // namespace

TEST(Policies, RegistryKnowsThesisAndRejectsUnknownNames) {
    EXPECT_STREQ(makePolicy("thesis")->name(), "thesis");
    EXPECT_STREQ(makePolicy("thesis-rh")->name(), "thesis-rh");
    EXPECT_THROW(makePolicy("no-such-policy"), std::invalid_argument);
    std::string names[] = {"thesis"};
    PolicyOptions bad;
    bad.values["thesis.nothing"] = 1;
    EXPECT_THROW(checkPolicySettings(names, bad), std::invalid_argument);
    std::string ok[] = {"x.y=1.5"};
    EXPECT_EQ(parsePolicySettings(ok).get("x.y", 0), 1.5);
    for (const std::string text : {"x.y=abc", "x.y=nan", "x.y=inf", "x.y=-inf", "x.y=1e999"}) {
        const std::string malformed[] = {text};
        EXPECT_THROW(parsePolicySettings(malformed), std::invalid_argument) << text;
    }
}

// The thesis through the interface (policy select + shared accounting) against selectFront with
// the parameters the Player used before the interface: same front, visits, priorities,
// toggles, misses and refusals on every frame of a walk with nodes loading as they are visited.
TEST(Policies, ThesisThroughInterfaceEqualsDirectTraversal) {
    Skeleton s = test::errorGridSkeleton(3, 3, 4);
    CameraPath path = walk(s);
    Harness h(s);
    SelectionState direct(s), viaPolicy(s);
    auto policy = makePolicy("thesis");
    uint64_t frames = 0, toggles = 0;
    for (double t = 0; t < path.duration() && frames < 1500; t += 0.03, ++frames) {
        Camera cam = sampleCameraPath(path, t, 16.0 / 9.0);
        h.share = 20 + 10 * std::sin(t);  // the second loop moves the share; both sides see the same
        h.withFrame(cam, frames, [&](const PolicyFrame& pf, const Evaluate& evaluate, auto&) {
            SelectionParams params = selectionParams(h.c, h.share, h.vTime, false);
            params.initialHyst = -h.c.hystSwitch;
            Selection a = selectFront(s, params, evaluate, direct, h.resident);
            PolicyFront f = policy->select(pf, viaPolicy);
            FrontAccount b = accountFront(s, viaPolicy, f.drawn);
            ASSERT_EQ(a.drawn.size(), b.items.size()) << "frame " << frames;
            for (size_t i = 0; i < a.drawn.size(); ++i) EXPECT_EQ(a.drawn[i].node, b.items[i].node);
            EXPECT_EQ(a.visited, f.visited);
            for (uint32_t id : a.visited) EXPECT_EQ(direct.nodes[id].priority, viaPolicy.nodes[id].priority);
            EXPECT_EQ(a.drawnCost, b.drawnCost);
            EXPECT_EQ(a.upToggles, b.upToggles);
            EXPECT_EQ(a.downToggles, b.downToggles);
            EXPECT_EQ(a.reversals, b.reversals);
            EXPECT_EQ(a.misses, f.misses);
            EXPECT_EQ(a.refused, f.refused);
            toggles += a.upToggles + a.downToggles;
            h.load(a.visited, 2);
        });
    }
    EXPECT_GT(toggles, 0u);  // the walk exercised the toggle accounting
}

// Every registered policy: a valid cut on every frame of a walk while nodes load (2 a frame),
// and with everything resident.
TEST(Policies, EveryPolicyYieldsAValidCut) {
    Skeleton s = test::errorGridSkeleton(3, 3, 4);
    CameraPath path = walk(s);
    for (const PolicyInfo& info : policyRegistry()) {
        for (bool preload : {false, true}) {
            Harness h(s);
            if (preload) h.resident.assign(s.nodes.size(), 1);
            SelectionState state(s);
            auto policy = makePolicy(info.name);
            uint64_t frame = 0;
            for (double t = 0; t < path.duration() && frame < 600; t += 0.05, ++frame) {
                Camera cam = sampleCameraPath(path, t, 16.0 / 9.0);
                h.withFrame(cam, frame, [&](const PolicyFrame& pf, const Evaluate&, auto& visible) {
                    PolicyFront f = policy->select(pf, state);
                    std::string problem = checkCut(s, f.drawn, h.resident, visible, f.skipsBlocks);
                    ASSERT_EQ(problem, "") << info.name << " frame " << frame;
                    FrontAccount a = accountFront(s, state, f.drawn);
                    policy->observe(FrameOutcome{h.overhead + h.vTime * a.drawnCost, h.overhead + h.vTime * a.drawnCost,
                                                 h.c.targetTimeMs, a.drawnCost, h.vTime});
                    h.load(f.visited, 2);
                });
            }
        }
    }
}

TEST(Policies, CheckCutFindsEachViolation) {
    Skeleton s = test::errorGridSkeleton(1, 1, 3);  // node 0, children 1..4, grandchildren 5..20
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    auto all = [](uint32_t) { return true; };
    std::vector<DrawnNode> ok = {{1}, {2}, {3}, {4}};
    EXPECT_EQ(checkCut(s, ok, resident, all, false), "");
    std::vector<DrawnNode> nested = {{0}, {1}};
    EXPECT_NE(checkCut(s, nested, resident, all, false).find("both drawn"), std::string::npos);
    std::vector<DrawnNode> hole = {{1}, {2}, {3}};
    EXPECT_NE(checkCut(s, hole, resident, all, false).find("neither drawn"), std::string::npos);
    EXPECT_EQ(checkCut(s, hole, resident, all, true), "");  // a policy that skips says so
    resident[2] = 0;
    EXPECT_NE(checkCut(s, ok, resident, all, false).find("not resident"), std::string::npos);
    auto only1 = [](uint32_t id) { return id <= 1; };  // paths through 2..4 are not visible
    std::vector<DrawnNode> one = {{1}};
    EXPECT_EQ(checkCut(s, one, resident, only1, false), "");
}

// thesis-rh: within a sibling set, taken in ascending timeNeeded, each drawn node hands
// timeSlice - timeNeeded (when positive) to the next; the set's time is conserved.
TEST(Policies, ThesisRhPassesRemaindersInOrderAndConservesTime) {
    Skeleton s;
    uint32_t root = test::addNode(s, kNone, {{0, 0, 0}, {40, 10, 10}}, 4000);
    const uint32_t tris[] = {3000, 500, 1500, 1000};  // leaves of different cost
    for (int i = 0; i < 4; ++i) test::addNode(s, root, {{i * 10.f, 0, 0}, {i * 10.f + 10, 10, 10}}, tris[i]);
    test::linkSkeleton(s);
    SelectionState state(s);
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    SelectionParams p;
    p.hlod0Share = 10;
    p.vTime = 0.001;  // timeNeeded: 3, 0.5, 1.5, 1 ms
    p.initialHyst = p.hystLimit;  // refine the root at once
    p.passRemainders = true;
    Evaluate equal = [](uint32_t) { return NodeEval{1, 1}; };  // eq. 4.1: 2.5 ms each
    PolicyFront f = traverseThesis(s, p, equal, state, resident);
    ASSERT_EQ(f.drawn.size(), 4u);
    const uint32_t order[] = {2, 4, 3, 1};  // ascending timeNeeded
    double expectedIn = 0, used = 0;
    for (int i = 0; i < 4; ++i) {
        uint32_t id = order[i];
        EXPECT_EQ(f.drawn[i].node, id);
        const NodeState& n = state.nodes[id];
        EXPECT_NEAR(n.received, expectedIn, 1e-12) << "node " << id;
        EXPECT_NEAR(n.timeSlice, 2.5 + expectedIn, 1e-12);
        double need = p.vTime * s.nodes[id].cost;
        used += std::min(need, n.timeSlice);
        expectedIn = std::max(n.timeSlice - need, 0.0);
    }
    EXPECT_NEAR(used + expectedIn, 10.0, 1e-12);  // drawn time + the last remainder = the parent's slice
    EXPECT_NEAR(expectedIn, 10.0 - 6.0, 1e-12);   // 10 ms given, 6 ms needed in all
    // Without passing: the thesis's order (by id) and no node receives anything.
    SelectionState plain(s);
    p.passRemainders = false;
    PolicyFront g = traverseThesis(s, p, equal, plain, resident);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(g.drawn[i].node, uint32_t(i + 1));
    for (uint32_t id = 1; id < 5; ++id) EXPECT_EQ(plain.nodes[id].received, 0);
}

namespace {

// A camera 120 m above the centre of a 3 x 3 grid of 50 m blocks looking down: all in view.
Camera overhead(double height = 120) {
    Camera cam;
    cam.position[0] = 75;
    cam.position[1] = 75;
    cam.position[2] = height;
    return cam;
}

struct OneFrame {
    PolicyFront front;
    SelectionState state;
    std::vector<uint8_t> refined;  // ancestors of drawn nodes
    uint64_t triangles = 0;
};

// One frame of `policy` with everything resident; `observe` frames first report `actualMs`.
OneFrame runOnce(const Skeleton& s, SelectionPolicy& policy, const Camera& cam, int observe = 0, double actualMs = 30) {
    Harness h(s);
    h.resident.assign(s.nodes.size(), 1);
    OneFrame r{{}, SelectionState(s), std::vector<uint8_t>(s.nodes.size(), 0), 0};
    for (int i = 0; i < observe; ++i) policy.observe(FrameOutcome{actualMs, actualMs, 30, 0, h.vTime});
    h.withFrame(cam, 0, [&](const PolicyFrame& pf, const Evaluate&, auto& visible) {
        r.front = policy.select(pf, r.state);
        EXPECT_EQ(checkCut(s, r.front.drawn, h.resident, visible, false), "");
    });
    for (const DrawnNode& d : r.front.drawn) {
        r.triangles += s.nodes[d.node].triangles();
        for (uint32_t p = s.nodes[d.node].parent; p != kNone; p = s.nodes[p].parent) r.refined[p] = 1;
    }
    return r;
}

}  // namespace

TEST(Policies, NoneDrawsEveryVisibleLeaf) {
    Skeleton s = test::errorGridSkeleton(3, 3, 4);
    auto policy = makePolicy("none");
    OneFrame r = runOnce(s, *policy, overhead());
    ASSERT_FALSE(r.front.drawn.empty());
    for (const DrawnNode& d : r.front.drawn) EXPECT_EQ(s.nodes[d.node].firstChild, kNone) << "node " << d.node;
    EXPECT_EQ(r.front.drawn.size(), 9u * 64u);  // the whole grid is in view from above
}

// static: a node is refined exactly when its visible children's average triangle covers at least
// N projected pixels; N = 0 is full detail and a huge N keeps hlod0.
TEST(Policies, StaticRefinesWhileChildrenTrianglesCoverNPixels) {
    Skeleton s = test::errorGridSkeleton(3, 3, 4);
    Camera cam = overhead(60);
    Projection p = makeProjection(cam, 720);
    double velocity[3] = {0, 0, 0};
    View view = makeView(cam, velocity, 0.5);
    for (double pixels : {0.0, 20.0, 80.0, 320.0, 1e9}) {
        PolicyOptions o;
        o.values["static.pixels"] = pixels;
        auto policy = makePolicy("static", o);
        OneFrame r = runOnce(s, *policy, cam);
        auto childrenPx = [&](uint32_t id) {
            double area = 0, tris = 0;
            for (uint32_t c : s.children(id))
                if (frustumVis(view, s.nodes[c].bounds) >= 1) area += projectedAreaPx(s.nodes[c], p), tris += s.nodes[c].triangles();
            return area / tris;
        };
        uint32_t maxLevel = 0;
        for (const DrawnNode& d : r.front.drawn) {
            maxLevel = std::max(maxLevel, s.nodes[d.node].level);
            if (s.nodes[d.node].firstChild != kNone) {
                EXPECT_LT(childrenPx(d.node), pixels) << "node " << d.node;
            }
        }
        for (uint32_t id = 0; id < s.nodes.size(); ++id)
            if (r.refined[id]) {
                EXPECT_GE(childrenPx(id), pixels) << "node " << id;
            }
        if (pixels == 0) {
            EXPECT_EQ(maxLevel, 3u);
        }
        if (pixels == 1e9) {
            EXPECT_EQ(r.front.drawn.size(), 9u);  // hlod0 only
        }
    }
}

// sse: a node is refined exactly when its projected geometric error exceeds the tolerance.
TEST(Policies, SseRefinesExactlyTheNodesOverTolerance) {
    Skeleton s = test::errorGridSkeleton(3, 3, 5);
    Camera cam = overhead(40);
    Projection p = makeProjection(cam, 720);
    for (double tolerance : {4.0, 8.0, 16.0}) {
        PolicyOptions o;
        o.values["sse.tolerance"] = tolerance;
        auto policy = makePolicy("sse", o);
        OneFrame r = runOnce(s, *policy, cam);
        uint32_t over = 0;
        for (uint32_t id = 0; id < s.nodes.size(); ++id)
            if (r.refined[id]) {
                EXPECT_GT(projectedErrorPx(s.nodes[id], p), tolerance) << "node " << id;
            }
        for (const DrawnNode& d : r.front.drawn) {
            EXPECT_LE(projectedErrorPx(s.nodes[d.node], p), tolerance) << "node " << d.node;
            over += d.reason == DrawReason::Hysteresis;
        }
        EXPECT_GT(over, 0u);  // the tolerance, not the leaves, ended some refinement
    }
}

// feedback and sse-budget: slow frames raise the threshold (fewer triangles), fast ones lower it.
TEST(Policies, FeedbackPoliciesFollowTheMeasuredFrameTime) {
    Skeleton s = test::errorGridSkeleton(3, 3, 5);
    Camera cam = overhead(40);
    for (const char* name : {"feedback", "sse-budget"}) {
        PolicyOptions o;
        o.values["feedback.pixels"] = 40;
        o.values["sse-budget.tolerance"] = 8;
        auto base = makePolicy(name, o), slow = makePolicy(name, o), fast = makePolicy(name, o);
        uint64_t t0 = runOnce(s, *base, cam).triangles;
        uint64_t tSlow = runOnce(s, *slow, cam, 3, 60).triangles;  // frames twice the 30 ms target
        uint64_t tFast = runOnce(s, *fast, cam, 3, 15).triangles;  // half the target
        EXPECT_LT(tSlow, t0) << name;
        EXPECT_GT(tFast, t0) << name;
        auto steady = makePolicy(name, o);
        EXPECT_EQ(runOnce(s, *steady, cam, 5, 30).triangles, t0) << name;  // on target: unchanged
    }
}

// hold (player/policy_hold.cpp): on a still view with everything resident it fills the budget
// from hlod0 one level a frame, up to target x (1 - headroom), then keeps its front (no
// toggles); a lower target coarsens it until the estimate is within target x (1 + overrun), and
// the old target refills it.
TEST(Policies, HoldSettlesUnderTheTargetAndKeepsItsFront) {
    Skeleton s = test::errorGridSkeleton(3, 3, 4);
    Harness h(s);
    h.resident.assign(s.nodes.size(), 1);
    h.vTime = 0.01;  // full detail: 9 x 85 x 512 x 0.01 = 3,900 ms, hlod0 46 ms
    h.overhead = 2;
    SelectionState state(s);
    auto policy = makePolicy("hold");
    Camera cam;
    cam.position[0] = 75, cam.position[1] = 75, cam.position[2] = 150;  // above the grid's centre, looking down
    auto frameCost = [&](double target, uint64_t frame) {
        h.c.targetTimeMs = target;
        return h.withFrame(cam, frame, [&](const PolicyFrame& pf, const Evaluate&, auto&) {
            PolicyFront f = policy->select(pf, state);
            FrontAccount a = accountFront(s, state, f.drawn);
            return std::pair{h.overhead + h.vTime * a.drawnCost, a.upToggles + a.downToggles};
        });
    };
    uint64_t frame = 0;
    double est = 0;
    for (; frame < 30; ++frame) est = frameCost(200, frame).first;
    EXPECT_LE(est, 2 + 198 * 0.97);  // the default headroom
    EXPECT_GT(est, 200 * 0.8);  // filled (one refinement is at most 3 x 5.12 ms of 200)
    for (int k = 0; k < 10; ++k, ++frame) {
        auto [e, toggles] = frameCost(200, frame);
        EXPECT_EQ(e, est);
        EXPECT_EQ(toggles, 0u);
    }
    for (int k = 0; k < 10; ++k, ++frame) est = frameCost(120, frame).first;
    EXPECT_LE(est, 2 + 118 * 1.03);  // the default overrun
    for (int k = 0; k < 30; ++k, ++frame) est = frameCost(200, frame).first;
    EXPECT_GT(est, 200 * 0.8);
    EXPECT_LE(est, 200);
}
