// `fs-node`: Funkhouser & Séquin 1993's greedy by Value (§6) with front nodes as its objects
// (player/fs_node.h; player/SOLVERS.md "fs-node"), the node-granular variant of `fs-greedy`.
// Each frame the front starts at the visible hlod0 nodes (with allow_skip: at nothing, each
// visible root a step that draws it) and the front node whose refinement into its visible
// children has the highest Value = Δbenefit / ΔCost is refined while the budget holds. Cost is
// FS §4's max(per-primitive, per-pixel) per block exactly as the block solvers'
// (player/choice_map.cpp), benefit the common measure (player/benefit.h), the budget
// c_targetTime minus the overhead, and a refinement is a candidate only when its visible children
// are resident (all children with requireLoadedChildren). The children of every front node are
// evaluated (thesis §4.2 priority and frustumVis), so the loader fetches them by priority as in the
// thesis; nothing deeper is evaluated. Settings: allow_skip, pixel_ms (as the block solvers'),
// best_single (default 1).
#include "player/fs_node.h"
#include "player/node_front.h"

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
        NodeProblem p;
        p.budget = f.targetMs - f.overheadMs;
        auto addStep = [&](uint32_t id, uint32_t parent, uint32_t block) {  // the step refining front node `id`
            NodeRefinement x = evaluateRefinement(f, state, id, out.visited);
            if (x.possible) p.steps.push_back({id, parent, block, x.primMs, x.benefit, false});
        };
        std::vector<uint32_t> base;
        for (uint32_t r : state.roots) {
            // a non-resident hlod0 node cannot be drawn
            if (!evaluateNode(f, state, r, out.visited) || !f.resident[r]) continue;
            BlockCost b = rootBlockCost(f, r, pixelMs_);
            if (allowSkip_) {  // FS §3: "levels of detail representing no polygons at all"
                b.drawn = false;
                double benefit = nodeBenefit(s, s.nodes[r], f.projection);
                p.steps.push_back({r, kNoStep, uint32_t(p.blocks.size()), b.primMs, benefit, true});
                b.primMs = 0;
            } else {
                base.push_back(r);
                addStep(r, kNoStep, uint32_t(p.blocks.size()));
            }
            p.blocks.push_back(b);
        }
        p.expand = [&](uint32_t taken, NodeProblem& q) {
            const RefineStep x = q.steps[taken];
            if (x.inserts) return addStep(x.node, taken, x.block);
            for (uint32_t c = s.nodes[x.node].firstChild; c != kNone && s.nodes[c].parent == x.node; c = s.nodes[c].nextSibling)
                if (state.nodes[c].frustumVis >= 1) addStep(c, taken, x.block);
        };
        NodeChoice choice = fsNodeGreedy(p, bestSingle_);
        out.iterations = choice.iterations;
        refined_.resize(s.nodes.size(), 0);
        for (uint32_t k : choice.order) {
            const RefineStep& x = p.steps[k];
            if (x.inserts) base.push_back(x.node);
            else refined_[x.node] = 1;
        }
        for (uint32_t id : emitNodeFront(f, state, base, refined_, out)) refined_[id] = 0;
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
