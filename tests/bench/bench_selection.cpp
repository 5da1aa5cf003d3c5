// Selection time per frame (thesis §5.2 "Running Time Complexity": O(c_targetTime +
// numObjects), not O(nodes)) for hierarchies from 2,295 nodes (the thesis's model had 2,296)
// to about 1 M, with a walking camera and every node resident; and the policies of
// player/policy.h at 2,295 nodes (select() in all, and the optimisation proper alone).
#include "player/camera_path.h"
#include "player/policy.h"
#include "player/selection.h"
#include "tests/support/trees.h"

#include <cmath>

#include <benchmark/benchmark.h>

using namespace hlod;

namespace {

void selection(benchmark::State& state) {
    uint32_t blocks = uint32_t(state.range(0)), levels = uint32_t(state.range(1));
    Skeleton s = test::gridSkeleton(blocks, 3, levels, 900, 50);
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    Constants c;
    SelectionState st(s);
    SelectionParams p = selectionParams(c, 28, 1e-3, false);
    PathOptions o;
    o.kind = PathKind::Walk;
    CameraPath path = generatePath(s, o);
    double velocity[3] = {0, 0, 0}, t = 0;
    uint64_t drawn = 0, visited = 0, frames = 0;
    for (auto _ : state) {
        View view = makeView(sampleCameraPath(path, t), velocity, 0.5);
        Evaluate e = [&](uint32_t id) {
            double fv = frustumVis(view, s.nodes[id].bounds);
            return NodeEval{nodePriority(s.nodes[id], view, c, fv), fv};
        };
        Selection sel = selectFront(s, p, e, st, resident);
        drawn += sel.drawn.size();
        visited += sel.visited.size();
        ++frames;
        t = t + 0.03 > path.duration() ? 0 : t + 0.03;
    }
    state.counters["nodes"] = double(s.nodes.size());
    state.counters["drawn"] = double(drawn) / frames;
    state.counters["visited"] = double(visited) / frames;
}

// One policy (by its index in the registry) over 27 blocks x 85 nodes = 2,295 nodes, a 30 ms
// target with 2 ms overhead at 1e-4 ms per unit of cost (full detail ~4 x the budget).
void policy(benchmark::State& state) {
    const PolicyInfo& info = policyRegistry()[size_t(state.range(0))];
    Skeleton s = test::gridSkeleton(9, 3, 4, 900, 50);
    for (Node& n : s.nodes) n.geometricError = n.firstChild == kNone ? 0.f : std::ldexp(2.f, -int(n.level));
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    Constants c;
    SelectionState st(s);
    auto pol = makePolicy(info.name);
    PathOptions o;
    o.kind = PathKind::Walk;
    CameraPath path = generatePath(s, o);
    double velocity[3] = {0, 0, 0}, t = 0, optMs = 0, iterations = 0;
    uint64_t frames = 0, drawn = 0;
    for (auto _ : state) {
        Camera cam = sampleCameraPath(path, t);
        View view = makeView(cam, velocity, 0.5);
        Projection proj = makeProjection(cam, 720);
        Evaluate e = [&](uint32_t id) {
            double fv = frustumVis(view, s.nodes[id].bounds);
            return NodeEval{nodePriority(s.nodes[id], view, c, fv), fv};
        };
        PolicyFrame pf{s, c, cam, view, proj, e, resident, frames, 30, 2, 1e-4, 28, false, -c.hystSwitch};
        PolicyFront f = pol->select(pf, st);
        FrontAccount a = accountFront(s, st, f.drawn);
        pol->observe(FrameOutcome{2 + 1e-4 * a.drawnCost, 2 + 1e-4 * a.drawnCost, 30, a.drawnCost, 1e-4});
        optMs += f.optimisationMs;
        iterations += f.iterations;
        drawn += f.drawn.size();
        ++frames;
        t = t + 0.03 > path.duration() ? 0 : t + 0.03;
    }
    state.SetLabel(info.name);
    state.counters["nodes"] = double(s.nodes.size());
    state.counters["drawn"] = double(drawn) / frames;
    state.counters["opt_us"] = optMs >= 0 ? 1e3 * optMs / frames : -1;
    state.counters["iterations"] = iterations / frames;
}

}  // namespace

// {blocks along x (3 rows), levels}: 27 x 85 = 2,295; 12 x 3 x 1,365 = 49,140; 61 x 3 x 5,461 = 999,363.
BENCHMARK(selection)->Args({9, 4})->Args({12, 6})->Args({61, 7})->Unit(benchmark::kMicrosecond);
BENCHMARK(policy)->DenseRange(0, int(policyRegistry().size()) - 1)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
