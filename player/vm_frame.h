// What the vm loader classifies with (Varadhan & Manocha 2002 §4.2), built by the render thread
// once a frame from the selector's state: the errors eps_O of the evaluated nodes against the
// selector's tolerance, and the render and prefetch frusta's half-angles (player/LOADERS.md).
#pragma once

#include "player/loader_vm.h"
#include "player/policy.h"

#include <memory>
#include <span>
#include <string>

namespace hlod {

struct VmFrameInput {
    const Skeleton& skeleton;
    const SelectionState& state;
    std::span<const uint32_t> visited;  // nodes evaluated this frame
    const std::string& policy;          // selector's registry name
    const PolicyOptions& policyOptions;
    const VmOptions& options;
    const Camera& camera;
    const Projection& projection;
    double vTime = 0;          // ms per unit of cost
    double angularSpeed = 0;   // rad/s of the viewing direction
    double lookaheadSeconds = 0;
    bool moved = true;
};

// "Close to a switch", by selector:
//   thesis, thesis-rh: eps_O = epsilon x timeSlice_O / (v_time x sum of cost over O's visible
//     children): O switches to its children when its slice covers their time (eq. 4.1), i.e. when
//     eps_O reaches epsilon, as a node refines when its projected error exceeds epsilon (§3.2);
//     a leaf has 0; an invisible node is left to inherit.
//   sse, sse-budget: eps_O = projectedErrorPx, epsilon = the policy's tolerance (native).
//   any other: projectedErrorPx against VmOptions::tolerance.
// The evaluated nodes outside the render frustum are listed (VmFrame::outside) for the visibility
// events of §4.2.2; for the thesis selectors their slice is the one eq. 4.1 would give them were
// they visible among their visible siblings.
std::shared_ptr<const VmFrame> makeVmFrame(const VmFrameInput& in);

// Half-angle of the cone around the render frustum F_R (its half diagonal field of view).
double renderFrustumHalfAngle(const Camera& camera);

}  // namespace hlod
