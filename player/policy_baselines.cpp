// The three baselines of T. A. Funkhouser and C. H. Séquin, "Adaptive Display Algorithm for
// Interactive Frame Rates During Visualization of Complex Virtual Environments", SIGGRAPH 1993,
// §7 "Test Methods" (a)-(c), on the node hierarchy (player/rule_traversal.h):
//  - none: "No Detail Elision: each object is rendered at the highest LOD" (every visible leaf);
//  - static: "rendered at the highest LOD for which an average polygon covers at least 1024
//    pixels on the screen": a node is refined while its visible children's average triangle
//    still covers >= N pixels (static.pixels, default 1024);
//  - feedback: the same threshold "updated in each frame by a feedback loop, based on the
//    difference between the time required to render the previous frame and the target frame
//    time" (also §2: "if the previous frame took longer than the target frame time, the size
//    threshold for LOD selection is increased"): N <- N x actual / target, in [0.01, 1e7].
// Open choices (average triangle area, the feedback law): player/POLICIES.md.
#include "player/policy.h"
#include "player/rule_traversal.h"

#include <algorithm>

namespace hlod {
namespace {

class NonePolicy final : public SelectionPolicy {
public:
    const char* name() const override { return "none"; }
    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        return traverseByRule(f, state, [](uint32_t) { return true; });
    }
};

// Projected pixels per triangle of a node's visible children (FS §7 "average polygon").
double childrenPixelsPerTriangle(const PolicyFrame& f, const SelectionState& state, uint32_t id) {
    double area = 0, tris = 0;
    const Skeleton& s = f.skeleton;
    for (uint32_t c = s.nodes[id].firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling)
        if (state.nodes[c].frustumVis >= 1) {
            area += projectedAreaPx(s.nodes[c], f.projection);
            tris += s.nodes[c].triangles();
        }
    return tris > 0 ? area / tris : 0;
}

class StaticPolicy final : public SelectionPolicy {
public:
    StaticPolicy(const char* name, double pixels, bool feedback) : name_(name), pixels_(pixels), feedback_(feedback) {}
    const char* name() const override { return name_; }
    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        return traverseByRule(f, state, [&](uint32_t id) { return childrenPixelsPerTriangle(f, state, id) >= pixels_; });
    }
    void observe(const FrameOutcome& o) override {
        if (feedback_ && o.targetMs > 0 && o.actualMs > 0)
            pixels_ = std::clamp(pixels_ * o.actualMs / o.targetMs, kMinPixels, kMaxPixels);  // FS §2, §7 (c)
    }

private:
    static constexpr double kMinPixels = 0.01, kMaxPixels = 1e7;
    const char* name_;
    double pixels_;
    bool feedback_;
};

}  // namespace

std::unique_ptr<SelectionPolicy> makeNonePolicy(const PolicyOptions&) { return std::make_unique<NonePolicy>(); }
std::unique_ptr<SelectionPolicy> makeStaticPolicy(const PolicyOptions& o) {
    return std::make_unique<StaticPolicy>("static", o.get("static.pixels", 1024), false);
}
std::unique_ptr<SelectionPolicy> makeFeedbackPolicy(const PolicyOptions& o) {
    return std::make_unique<StaticPolicy>("feedback", o.get("feedback.pixels", 1024), true);
}

}  // namespace hlod
