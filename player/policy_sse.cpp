// The screen-space-error rule of today's streaming systems (OGC 3D Tiles 1.1 §"Geometric
// error": a tile is refined while its geometric error projected to the screen exceeds the
// maximum screen-space error, CesiumJS default 16 pixels; Nexus (Ponchio, ISTI-CNR) likewise
// refines to a target error in pixels): `sse` refines a node while geometricError x focal / distance > tolerance
// (sse.tolerance, pixels, default 16). `sse-budget` adjusts the tolerance each frame to the
// budget: drawn triangles grow about as 1 / tolerance^2 (error ~ edge length, triangles ~
// 1 / edge^2), so tolerance <- tolerance x sqrt(actual / target), in [0.01, 1e4] pixels.
// Open choices: player/POLICIES.md.
#include "player/policy.h"
#include "player/rule_traversal.h"

#include <algorithm>
#include <cmath>

namespace hlod {
namespace {

class SsePolicy final : public SelectionPolicy {
public:
    SsePolicy(const char* name, double tolerance, bool budget) : name_(name), tolerance_(tolerance), budget_(budget) {}
    const char* name() const override { return name_; }
    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        return traverseByRule(f, state,
                              [&](uint32_t id) { return projectedErrorPx(f.skeleton.nodes[id], f.projection) > tolerance_; });
    }
    void observe(const FrameOutcome& o) override {
        if (budget_ && o.targetMs > 0 && o.actualMs > 0)
            tolerance_ = std::clamp(tolerance_ * std::sqrt(o.actualMs / o.targetMs), kMinTolerance, kMaxTolerance);
    }

private:
    static constexpr double kMinTolerance = 0.01, kMaxTolerance = 1e4;
    const char* name_;
    double tolerance_;
    bool budget_;
};

}  // namespace

std::unique_ptr<SelectionPolicy> makeSsePolicy(const PolicyOptions& o) {
    return std::make_unique<SsePolicy>("sse", o.get("sse.tolerance", 16), false);
}
std::unique_ptr<SelectionPolicy> makeSseBudgetPolicy(const PolicyOptions& o) {
    return std::make_unique<SsePolicy>("sse-budget", o.get("sse-budget.tolerance", 16), true);
}

}  // namespace hlod
