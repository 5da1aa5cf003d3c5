// `fs-node`: Funkhouser & Séquin 1993's greedy by Value (§6) with front nodes as its objects
// (player/fs_node.h; player/SOLVERS.md "fs-node"), the node-granular variant of `fs-greedy`.
// Each frame the front starts at the visible hlod0 nodes (with allow_skip: at nothing, each
// visible root a step that draws it) and the front node whose refinement into its visible
// children has the highest Value = Δbenefit / ΔCost is refined while the budget holds. Cost is
// FS §4's max(per-primitive, per-pixel) per block exactly as the block solvers'
// (player/choice_map.cpp), benefit the common measure (player/benefit.h), the budget
// c_targetTime minus the overhead, and a refinement is a candidate only when its visible children
// are resident (all children with requireLoadedChildren). The children of every front node are
// evaluated (§4.2 priority and frustumVis), so the loader fetches them by priority as in the
// thesis; nothing deeper is evaluated. Settings: allow_skip, pixel_ms (as the block solvers'),
// best_single (default 1).
#include "player/fs_node.h"
#include "player/policy.h"

#include <algorithm>

namespace hlod {
namespace {

class FsNodePolicy final : public SelectionPolicy {
public:
    explicit FsNodePolicy(const PolicyOptions& o)
        : allowSkip_(o.get("fs-node.allow_skip", 0) != 0), pixelMs_(o.get("fs-node.pixel_ms", 0)),
          bestSingle_(o.get("fs-node.best_single", 1) != 0) {}
    const char* name() const override { return "fs-node"; }

    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        const Skeleton& s = f.skeleton;
        PolicyFront out;
        auto visit = [&](uint32_t id) {
            NodeEval e = f.evaluate(id);
            state.nodes[id].priority = e.priority;
            state.nodes[id].frustumVis = e.frustumVis;
            out.visited.push_back(id);
            return e.frustumVis >= 1;
        };
        auto visible = [&](uint32_t id) { return state.nodes[id].frustumVis >= 1; };
        NodeProblem p;
        p.budget = f.targetMs - f.overheadMs;
        // The refinement step of front node `id` (evaluating its children), if it has visible
        // children and they are resident.
        auto addStep = [&](uint32_t id, uint32_t parent, uint32_t block) {
            const Node& n = s.nodes[id];
            RefineStep x{id, parent, block, -f.vTime * n.cost, -nodeBenefit(s, n, f.projection), false};
            bool any = false, ready = true;
            for (uint32_t c = n.firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling) {
                bool v = visit(c);
                ready = ready && (f.resident[c] || (!v && !f.requireLoadedChildren));
                if (!v) continue;
                any = true;
                x.primMs += f.vTime * s.nodes[c].cost;
                x.benefit += nodeBenefit(s, s.nodes[c], f.projection);
            }
            if (any && ready) p.steps.push_back(x);
        };
        for (uint32_t r : state.roots) {
            if (!visit(r) || !f.resident[r]) continue;  // a non-resident hlod0 node cannot be drawn
            BlockCost b{f.vTime * s.nodes[r].cost, pixelMs_ * std::max(projectedAreaPx(s.nodes[r], f.projection), 1.0)};
            if (allowSkip_) {  // FS §3: "levels of detail representing no polygons at all"
                b.drawn = false;
                p.steps.push_back({r, kNoStep, uint32_t(p.blocks.size()), b.primMs, nodeBenefit(s, s.nodes[r], f.projection), true});
                b.primMs = 0;
            } else {
                addStep(r, kNoStep, uint32_t(p.blocks.size()));
            }
            p.blocks.push_back(b);
        }
        p.expand = [&](uint32_t taken, NodeProblem& q) {
            const RefineStep x = q.steps[taken];
            if (x.inserts) return addStep(x.node, taken, x.block);
            for (uint32_t c = s.nodes[x.node].firstChild; c != kNone && s.nodes[c].parent == x.node; c = s.nodes[c].nextSibling)
                if (visible(c)) addStep(c, taken, x.block);
        };
        NodeChoice choice = fsNodeGreedy(p, bestSingle_);
        out.iterations = choice.iterations;
        // The front: the base (or inserted) roots, each refined node replaced by its visible children.
        refined_.resize(s.nodes.size(), 0);
        std::vector<uint32_t> pending;
        for (uint32_t r : state.roots)
            if (visible(r) && f.resident[r] && !allowSkip_) pending.push_back(r);
        for (uint32_t k : choice.order) {
            const RefineStep& x = p.steps[k];
            if (x.inserts) pending.push_back(x.node);
            else refined_[x.node] = 1;
        }
        for (size_t i = 0; i < pending.size(); ++i) {  // breadth-first, as the thesis draws
            uint32_t id = pending[i];
            if (!refined_[id]) {
                DrawReason why = deriveReason(s, id, visible, f.resident);
                for (uint32_t c = s.nodes[id].firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling)
                    out.misses += visible(c) && !f.resident[c];
                out.drawn.push_back({id, why});
                continue;
            }
            refined_[id] = 0;
            for (uint32_t c = s.nodes[id].firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling)
                if (visible(c)) pending.push_back(c);
        }
        size_t roots = 0, drawnRoots = 0;  // a visible root neither drawn nor refined: its block is skipped
        for (uint32_t r : state.roots) roots += visible(r);
        for (uint32_t id : pending) drawnRoots += s.nodes[id].parent == kNone;
        out.skipsBlocks = drawnRoots < roots;
        return out;
    }

private:
    bool allowSkip_;
    double pixelMs_;
    bool bestSingle_;
    std::vector<uint8_t> refined_;  // scratch, all 0 between frames
};

}  // namespace

std::unique_ptr<SelectionPolicy> makeFsNodePolicy(const PolicyOptions& o) { return std::make_unique<FsNodePolicy>(o); }

}  // namespace hlod
