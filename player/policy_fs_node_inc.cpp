// `fs-node-inc`: Funkhouser & Séquin 1993's incremental optimisation (§6) with front
// nodes as its objects (player/SOLVERS.md "fs-node"): "each object is assigned the LOD chosen in
// the previous frame, or the lowest LOD if the object is newly visible. In each iteration, the
// algorithm first increments the accuracy attribute of the object that has the highest
// subsequent Value. It then decrements the accuracy attributes of the object tuples with the
// lowest current Value until the cumulative cost of all object tuples in S is less than the
// target frame time. The algorithm terminates when the same accuracy attribute of the same
// object tuple is both incremented and decremented in the same iteration." Here the front starts
// as last frame's (a refined node stays refined while its visible children are resident; a block
// newly visible starts at hlod0), an increment refines the front node of highest Value (as
// `fs-node`), a decrement merges the sibling set of lowest Value back into its parent (the
// refined node whose visible children are all front nodes; with allow_skip also a front root,
// which skips its block), each kept in a priority queue. Cost, benefit, budget and availability
// are `fs-node`'s (player/node_front.h). Settings: allow_skip, pixel_ms.
#include "player/fs_node.h"
#include "player/node_front.h"

#include <algorithm>
#include <limits>
#include <queue>

namespace hlod {
namespace {

// Per node, this frame: Out = evaluated, no longer in the front (merged away).
enum Status : uint8_t { Untouched, Front, Refined, Skipped, Out };

struct Entry {
    double value;
    uint32_t node;
    bool operator<(const Entry& o) const { return value != o.value ? value < o.value : node > o.node; }
    bool operator>(const Entry& o) const { return value != o.value ? value > o.value : node > o.node; }
};

double valueOf(double benefit, double cost) {  // FS §6: Value = Benefit / Cost
    return cost > 0 ? benefit / cost : std::numeric_limits<double>::infinity();
}

class FsNodeIncrementalPolicy final : public SelectionPolicy {
public:
    explicit FsNodeIncrementalPolicy(const PolicyOptions& o)
        : allowSkip_(o.get("fs-node-inc.allow_skip", 0) != 0), pixelMs_(o.get("fs-node-inc.pixel_ms", 0)) {}
    const char* name() const override { return "fs-node-inc"; }

    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        const Skeleton& s = f.skeleton;
        if (refined_.size() != s.nodes.size()) {
            for (auto* v : {&refined_, &status_, &evaluated_, &wasDrawn_, &skipped_}) v->assign(s.nodes.size(), 0);
            info_.assign(s.nodes.size(), {});
            block_.assign(s.nodes.size(), 0);
        }
        PolicyFront out;
        f_ = &f, state_ = &state, out_ = &out;
        blocks_.clear();
        touched_.clear();
        up_ = {}, down_ = {};
        // Last frame's front: a refined node stays refined while its refinement is possible.
        std::vector<uint32_t> roots;
        for (uint32_t r : state.roots) {
            bool newlyVisible = !wasDrawn_[r];
            wasDrawn_[r] = evaluateNode(f, state, r, out.visited) && f.resident[r];
            if (!wasDrawn_[r]) continue;
            if (newlyVisible) skipped_[r] = 0, refined_[r] = 0;  // FS §6: "the lowest LOD if the object is newly visible"
            BlockCost b = rootBlockCost(f, r, pixelMs_);  // FS §4 Cost per block, as in fs-node
            blocks_.push_back({0, b.pixelMs, !skipped_[r]});
            block_[r] = uint32_t(roots.size());
            roots.push_back(r);
        }
        double cost = 0;
        for (uint32_t r : roots) {
            if (skipped_[r]) {
                status_[r] = Skipped, touched_.push_back(r);
                up_.push({upValue(r), r});
                continue;
            }
            std::vector<uint32_t> pending{r};
            for (size_t i = 0; i < pending.size(); ++i) {
                uint32_t id = pending[i];
                enter(id, block_[r]);
                if (refined_[id] && info_[id].possible) {
                    status_[id] = Refined;
                    visibleChildren(id, [&](uint32_t c) { pending.push_back(c); });
                    blocks_[block_[r]].primMs -= f.vTime * s.nodes[id].cost;  // enter() counted it as a front node
                }
            }
            cost += blockCostMs(blocks_[block_[r]]);
        }
        for (uint32_t id : touched_)
            if (lowerable(id)) down_.push({downValue(id), id});
        const double budget = f.targetMs - f.overheadMs;
        // A cap on the iterations: 4 x the nodes evaluated so far (a cold start needs one per refinement).
        for (out.iterations = 0; out.iterations < 4 * touched_.size() + 4;) {
            ++out.iterations;
            // FS §6 increment: the object with the highest subsequent Value (stale entries re-queued).
            uint32_t raised = kNone;
            while (!up_.empty() && raised == kNone) {
                Entry e = up_.top();
                up_.pop();
                if (!raisable(e.node)) continue;
                if (double v = upValue(e.node); v != e.value) up_.push({v, e.node});
                else raised = e.node;
            }
            if (raised != kNone) cost += raise(raised);
            // FS §6 decrement: the lowest current Values until the cost is within the target.
            bool undone = false;
            while (cost > budget && !down_.empty()) {
                Entry e = down_.top();
                down_.pop();
                if (!lowerable(e.node)) continue;
                if (double v = downValue(e.node); v != e.value) {
                    down_.push({v, e.node});
                    continue;
                }
                cost -= lower(e.node);
                undone = undone || e.node == raised;
            }
            if (raised == kNone || undone) break;  // FS §6's stop rule, or nothing left to refine
        }
        std::vector<uint32_t> drawnRoots;
        for (uint32_t r : roots) {
            skipped_[r] = status_[r] == Skipped;
            if (!skipped_[r]) drawnRoots.push_back(r);
        }
        for (uint32_t id : kept_) refined_[id] = 0;  // the refined set kept for the next frame
        for (uint32_t id : touched_) refined_[id] = status_[id] == Refined;
        kept_ = emitNodeFront(f, state, drawnRoots, refined_, out);
        for (uint32_t id : touched_) status_[id] = evaluated_[id] = 0;
        return out;
    }

private:
    template <class F>
    void visibleChildren(uint32_t id, F&& fn) const {
        const Skeleton& s = f_->skeleton;
        for (uint32_t c = s.nodes[id].firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling)
            if (state_->nodes[c].frustumVis >= 1) fn(c);
    }
    bool isRoot(uint32_t id) const { return f_->skeleton.nodes[id].parent == kNone; }
    double rootCost(uint32_t id) const { return blockCostMs(rootBlockCost(*f_, id, pixelMs_)); }  // a skipped root drawn
    double rootBenefit(uint32_t id) const { return nodeBenefit(f_->skeleton, f_->skeleton.nodes[id], f_->projection); }

    // A node enters the front: its refinement is evaluated once a frame (its children's priorities set).
    void enter(uint32_t id, uint32_t block) {
        if (!evaluated_[id]) {
            info_[id] = evaluateRefinement(*f_, *state_, id, out_->visited);
            evaluated_[id] = 1;
            if (status_[id] == Untouched) touched_.push_back(id);
        }
        status_[id] = Front;
        block_[id] = block;
        blocks_[block].primMs += f_->vTime * f_->skeleton.nodes[id].cost;
        if (raisable(id)) up_.push({upValue(id), id});
    }
    bool raisable(uint32_t id) const {
        return status_[id] == Skipped || (status_[id] == Front && info_[id].possible && info_[id].benefit > 0);
    }
    bool lowerable(uint32_t id) const {  // a sibling set to merge, or (allow_skip) a block to skip
        if (status_[id] == Front) return allowSkip_ && isRoot(id);
        if (status_[id] != Refined) return false;
        bool all = true;
        visibleChildren(id, [&](uint32_t c) { all = all && status_[c] == Front; });
        return all;
    }
    double upValue(uint32_t id) const {  // the Value of the increment
        if (status_[id] == Skipped) return valueOf(rootBenefit(id), rootCost(id));
        BlockCost b = blocks_[block_[id]];
        b.primMs += info_[id].primMs;
        return valueOf(info_[id].benefit, blockCostMs(b) - blockCostMs(blocks_[block_[id]]));
    }
    double downValue(uint32_t id) const {  // the current Value of the tuple the decrement takes back
        const BlockCost& now = blocks_[block_[id]];
        if (status_[id] == Front) return valueOf(rootBenefit(id), blockCostMs(now));
        BlockCost b = now;
        b.primMs -= info_[id].primMs;
        return valueOf(info_[id].benefit, blockCostMs(now) - blockCostMs(b));
    }

    // Refines front node `id` (or draws skipped root `id`); returns the cost change.
    double raise(uint32_t id) {
        BlockCost& b = blocks_[block_[id]];
        double before = blockCostMs(b);
        if (status_[id] == Skipped) {
            b.drawn = true;
            enter(id, block_[id]);
        } else {
            status_[id] = Refined;
            b.primMs -= f_->vTime * f_->skeleton.nodes[id].cost;
            visibleChildren(id, [&](uint32_t c) { enter(c, block_[id]); });
        }
        down_.push({downValue(id), id});
        return blockCostMs(b) - before;
    }

    // Merges refined node `id`'s visible children back into it (or skips front root `id`); returns the cost saved.
    double lower(uint32_t id) {
        BlockCost& b = blocks_[block_[id]];
        double before = blockCostMs(b);
        uint32_t parent = f_->skeleton.nodes[id].parent;
        if (status_[id] == Front) {  // allow_skip: FS §3's "levels of detail representing no polygons at all"
            b.drawn = false;
            b.primMs = 0;
            status_[id] = Skipped;
        } else {
            visibleChildren(id, [&](uint32_t c) {
                status_[c] = Out;
                b.primMs -= f_->vTime * f_->skeleton.nodes[c].cost;
            });
            status_[id] = Front;
            b.primMs += f_->vTime * f_->skeleton.nodes[id].cost;
            if (parent != kNone && lowerable(parent)) down_.push({downValue(parent), parent});
            if (lowerable(id)) down_.push({downValue(id), id});
        }
        if (raisable(id)) up_.push({upValue(id), id});
        return before - blockCostMs(b);
    }

    bool allowSkip_;
    double pixelMs_;
    std::vector<uint8_t> refined_;    // per node: refined in last frame's front
    std::vector<uint32_t> kept_;      // the nodes refined_ is set for
    std::vector<uint8_t> wasDrawn_;   // per root: visible and resident last frame
    std::vector<uint8_t> skipped_;    // per root: skipped last frame (allow_skip)
    // This frame's state (status_ and evaluated_ are 0 between frames).
    const PolicyFrame* f_ = nullptr;
    SelectionState* state_ = nullptr;
    PolicyFront* out_ = nullptr;
    std::vector<uint8_t> status_, evaluated_;
    std::vector<NodeRefinement> info_;
    std::vector<uint32_t> block_;     // per node: index into blocks_
    std::vector<BlockCost> blocks_;
    std::vector<uint32_t> touched_;
    std::priority_queue<Entry> up_;                                       // highest Value first
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> down_;  // lowest Value first
};

}  // namespace

std::unique_ptr<SelectionPolicy> makeFsNodeIncrementalPolicy(const PolicyOptions& o) {
    return std::make_unique<FsNodeIncrementalPolicy>(o);
}

}  // namespace hlod
