// The vm loader's per-frame classification data (Varadhan & Manocha 2002 §4.2.2, §4.2.3).
// The prefetch frustum F_I (open in the paper: "the size of F_I can be adapted based on the rate
// at which the user pans"): theta1 = min(theta0 + margin + angular speed x lookahead, pi), the
// angle the viewing direction sweeps in the look-ahead time the selector already uses for
// velocity (player/SELECTION.md), plus a fixed margin.
#include "player/vm_frame.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace hlod {

double renderFrustumHalfAngle(const Camera& camera) {
    double tv = std::tan(camera.vfovDegrees * M_PI / 360.0);
    return std::atan(tv * std::hypot(1.0, camera.aspect));
}

std::shared_ptr<const VmFrame> makeVmFrame(const VmFrameInput& in) {
    auto f = std::make_shared<VmFrame>();
    const bool thesis = in.policy == "thesis" || in.policy == "thesis-rh";
    const bool sse = in.policy == "sse" || in.policy == "sse-budget";
    f->tolerance = sse ? in.policyOptions.get(in.policy + ".tolerance", 16) : in.options.tolerance;
    f->delta = f->tolerance * in.options.deltaRatio;
    f->binWidth = f->tolerance / in.options.binsPerTolerance;
    f->nativeErrors = !thesis;
    f->projection = in.projection;
    Eigen::Quaterniond q(in.camera.orientation[3], in.camera.orientation[0], in.camera.orientation[1],
                         in.camera.orientation[2]);
    Eigen::Vector3d forward = q.normalized() * Eigen::Vector3d(0, 0, -1);
    for (int i = 0; i < 3; ++i) {
        f->eye[i] = in.camera.position[i];
        f->forward[i] = forward[i];
    }
    f->theta0 = renderFrustumHalfAngle(in.camera);
    f->theta1 = std::min(f->theta0 + in.options.marginDegrees * M_PI / 180 + in.angularSpeed * in.lookaheadSeconds, M_PI);
    f->moved = in.moved;
    const Skeleton& s = in.skeleton;
    std::vector<uint8_t> seen(s.nodes.size(), 0);
    for (uint32_t id : in.visited) {
        seen[id] = 1;
        if (in.state.nodes[id].frustumVis < 1) f->outside.push_back(id);
    }
    if (thesis) {
        for (uint32_t id : in.visited) {
            const NodeState& n = in.state.nodes[id];
            const uint32_t parent = s.nodes[id].parent;
            double slice = n.timeSlice;
            if (n.frustumVis < 1) {
                // Outside F_R: the slice it would get by eq. 4.1 were it visible among its siblings.
                if (parent == kNone || !seen[parent] || in.state.nodes[parent].frustumVis < 1) continue;  // inherits
                double sum = n.priority;
                for (uint32_t c = s.nodes[parent].firstChild; c != kNone && s.nodes[c].parent == parent;
                     c = s.nodes[c].nextSibling)
                    if (seen[c] && in.state.nodes[c].frustumVis >= 1) sum += in.state.nodes[c].priority;
                slice = sum > 0 ? in.state.nodes[parent].timeSlice * n.priority / sum : 0;
            }
            double need = 0, needAll = 0;
            bool anySeen = false;
            for (uint32_t c = s.nodes[id].firstChild; c != kNone && s.nodes[c].parent == id; c = s.nodes[c].nextSibling) {
                double cost = std::max(double(s.nodes[c].cost), 1.0);
                needAll += cost;
                if (seen[c]) {
                    anySeen = true;
                    if (in.state.nodes[c].frustumVis >= 1) need += cost;
                }
            }
            need = (anySeen ? need : needAll) * in.vTime;
            f->errors[id] = need > 0 ? f->tolerance * slice / need : 0;
        }
    }
    return f;
}

}  // namespace hlod
