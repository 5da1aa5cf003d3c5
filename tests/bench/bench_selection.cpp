// Selection time per frame (thesis §5.2 "Running Time Complexity": O(c_targetTime +
// numObjects), not O(nodes)) for hierarchies from 2,295 nodes (the thesis's model had 2,296)
// to about 1 M, with a walking camera and every node resident.
#include "player/camera_path.h"
#include "player/selection.h"
#include "tests/support/trees.h"

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

}  // namespace

// {blocks along x (3 rows), levels}: 27 x 85 = 2,295; 12 x 3 x 1,365 = 49,140; 61 x 3 x 5,461 = 999,363.
BENCHMARK(selection)->Args({9, 4})->Args({12, 6})->Args({61, 7})->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
