// Thesis §4.3: the doubly linked list + hash + cached pointer against a binary heap, replaying
// real frame-to-frame update streams: the priorities computed by the selection along a walk
// and a drive, plus the loader's queries (4 loads per frame) and evictions (budget of 400).
#include "player/camera_path.h"
#include "player/priority_queue.h"
#include "player/selection.h"
#include "tests/support/heap_queue.h"
#include "tests/support/trees.h"

#include <benchmark/benchmark.h>

#include <memory>

using namespace hlod;

namespace {

struct FrameUpdates {
    std::vector<std::pair<uint32_t, double>> updates;
    std::vector<uint32_t> forget;
};

std::vector<FrameUpdates> recordStream(const Skeleton& s, PathKind kind, int frames) {
    std::vector<uint8_t> resident(s.nodes.size(), 1);
    Constants c;
    SelectionState st(s);
    SelectionParams p = selectionParams(c, 300, 1e-3, false);
    PathOptions o;
    o.kind = kind;
    CameraPath path = generatePath(s, o);
    std::vector<FrameUpdates> out;
    std::vector<uint64_t> stamp(s.nodes.size(), 0);
    std::vector<uint32_t> last;
    double velocity[3] = {0, 0, 0};
    for (int f = 0; f < frames; ++f) {
        View view = makeView(sampleCameraPath(path, f * 0.03), velocity, 0.5);
        Evaluate e = [&](uint32_t id) {
            double fv = frustumVis(view, s.nodes[id].bounds);
            return NodeEval{nodePriority(s.nodes[id], view, c, fv), fv};
        };
        Selection sel = selectFront(s, p, e, st, resident);
        FrameUpdates fu;
        for (uint32_t id : sel.visited) {
            stamp[id] = f + 1;
            fu.updates.push_back({id, st.nodes[id].priority});
        }
        for (uint32_t id : last)
            if (stamp[id] != uint64_t(f + 1)) fu.forget.push_back(id);
        last = sel.visited;
        out.push_back(std::move(fu));
    }
    return out;
}

const std::vector<FrameUpdates>& stream(int kind) {
    static std::unique_ptr<std::vector<FrameUpdates>> cache[2];
    static Skeleton s = test::gridSkeleton(9, 3, 5, 900, 50);  // 9,207 nodes
    if (!cache[kind]) cache[kind] = std::make_unique<std::vector<FrameUpdates>>(
                          recordStream(s, kind == 0 ? PathKind::Walk : PathKind::Drive, 2000));
    return *cache[kind];
}

template <class Queue>
void replay(benchmark::State& state) {
    const auto& frames = stream(int(state.range(0)));
    uint64_t ops = 0;
    for (auto _ : state) {
        Queue q(9 * 3 * 341);
        uint32_t loaded = 0;
        for (const FrameUpdates& f : frames) {
            for (uint32_t id : f.forget) {
                if (q.loaded(id))
                    q.update(id, 0);
                else
                    q.remove(id);
            }
            for (auto [id, p] : f.updates) q.update(id, p);
            for (int k = 0; k < 4; ++k) {  // the loader takes the most urgent unloaded nodes
                uint32_t id = q.highestUnloaded();
                if (id == kNoNode) break;
                q.setLoaded(id, true);
                ++loaded;
            }
            while (loaded > 400) {  // eviction of the lowest-priority loaded node
                uint32_t id = q.lowestLoaded();
                q.setLoaded(id, false);
                --loaded;
            }
            ops += f.updates.size() + f.forget.size();
        }
        benchmark::DoNotOptimize(loaded);
    }
    state.counters["frames"] = double(frames.size());
    state.counters["ops/frame"] = double(ops) / state.iterations() / frames.size();
    state.counters["ns/frame"] =
        benchmark::Counter(double(frames.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

}  // namespace

// Argument: 0 = walk stream, 1 = drive stream.
BENCHMARK_TEMPLATE(replay, LinkedPriorityQueue)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(replay, HeapPriorityQueue)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
