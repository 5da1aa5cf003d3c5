// Priority heuristics of thesis §4.2: priority_n = staticBenefit_n * vis_n * foreshorten_n /
// (cost_n * distance_n^2), vis_n = 1 + c_vis * frustumVis_n, foreshorten_n = 1 + c_fore *
// (view . avgNormal_n). Choices the thesis leaves open are documented at each function.
#include "player/selection.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace hlod {
namespace {

using Eigen::Vector3d;

Vector3d vec(const double v[3]) { return {v[0], v[1], v[2]}; }

void setPlane(double plane[4], const Vector3d& normal, const Vector3d& point) {
    Vector3d n = normal.normalized();
    plane[0] = n.x();
    plane[1] = n.y();
    plane[2] = n.z();
    plane[3] = -n.dot(point);
}

// Distance from a point to a box (0 inside).
double boxDistance(const Box3f& b, const Vector3d& p) {
    double dx = std::max({double(b.min.x) - p.x(), 0.0, p.x() - double(b.max.x)});
    double dy = std::max({double(b.min.y) - p.y(), 0.0, p.y() - double(b.max.y)});
    double dz = std::max({double(b.min.z) - p.z(), 0.0, p.z() - double(b.max.z)});
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

// The camera looks down -Z with +Y up (renderer.h). The distance adjustment by velocity
// (left open by the thesis): a node's distance is the smaller of its distances from the eye
// and from the eye moved ahead by velocity * lookahead, so nodes the user approaches gain
// priority (and are prefetched) before they are reached, without losing the ones at hand.
View makeView(const Camera& camera, const double velocity[3], double lookaheadSeconds) {
    View v;
    Eigen::Quaterniond q(camera.orientation[3], camera.orientation[0], camera.orientation[1], camera.orientation[2]);
    q.normalize();
    Vector3d eye = vec(camera.position);
    Vector3d forward = q * Vector3d(0, 0, -1), up = q * Vector3d(0, 1, 0), right = q * Vector3d(1, 0, 0);
    Vector3d ahead = eye + vec(velocity) * lookaheadSeconds;
    for (int i = 0; i < 3; ++i) {
        v.eye[i] = eye[i];
        v.ahead[i] = ahead[i];
        v.forward[i] = forward[i];
    }
    double hv = camera.vfovDegrees * M_PI / 360.0;
    double hh = std::atan(std::tan(hv) * camera.aspect);
    setPlane(v.planes[0], right * std::cos(hh) + forward * std::sin(hh), eye);   // left
    setPlane(v.planes[1], -right * std::cos(hh) + forward * std::sin(hh), eye);  // right
    setPlane(v.planes[2], up * std::cos(hv) + forward * std::sin(hv), eye);      // bottom
    setPlane(v.planes[3], -up * std::cos(hv) + forward * std::sin(hv), eye);     // top
    setPlane(v.planes[4], forward, eye + forward * camera.nearPlane);            // near
    setPlane(v.planes[5], -forward, eye + forward * camera.farPlane);            // far
    // frustumVis falls to 0 half a vertical field of view outside the frustum (thesis: "linearly
    // decreases to 0 based on how far outside"; the width of the ramp is our choice).
    v.falloff = hv;
    return v;
}

// Plane/box test with the box corner furthest along each inward normal; the amount by which
// that corner lies behind the worst plane, over the box's distance from the eye, approximates
// the angle by which the box is outside.
double frustumVis(const View& view, const Box3f& box) {
    double outside = 0;
    for (const auto& p : view.planes) {
        double x = p[0] >= 0 ? box.max.x : box.min.x;
        double y = p[1] >= 0 ? box.max.y : box.min.y;
        double z = p[2] >= 0 ? box.max.z : box.min.z;
        outside = std::max(outside, -(p[0] * x + p[1] * y + p[2] * z + p[3]));
    }
    if (outside <= 0) return 1;
    double distance = std::max(boxDistance(box, vec(view.eye)), 1.0);
    return std::max(0.0, 1.0 - (outside / distance) / view.falloff);
}

// view . avgNormal with the sign that favours surfaces facing the camera: `view` is the
// image-plane normal pointing back at the viewer (-forward), so a facade seen head-on gets
// 1 + c_fore and one seen from behind 1 - c_fore. staticBenefit / distance^2 stands for the
// node's screen area, which stops growing once the node fills the view: the distance (to the
// box) is floored at the node's bounding radius, and at 1 unit, the distance at which
// staticBenefit is defined (§3.3). Costs are floored at 1 so that a degenerate node cannot
// take all of its siblings' time.
double nodePriority(const Node& node, const View& view, const Constants& c, double frustumVisibility) {
    Vector3d normal(node.avgNormal.x, node.avgNormal.y, node.avgNormal.z);
    double facing = -vec(view.forward).dot(normal);
    double foreshorten = 1 + c.fore * facing;
    double vis = 1 + c.vis * frustumVisibility;
    double distance = std::min(boxDistance(node.bounds, vec(view.eye)), boxDistance(node.bounds, vec(view.ahead)));
    Vector3d extent(node.bounds.max.x - node.bounds.min.x, node.bounds.max.y - node.bounds.min.y,
                    node.bounds.max.z - node.bounds.min.z);
    distance = std::max({distance, 0.5 * extent.norm(), 1.0});
    double cost = std::max(double(node.cost), 1.0);
    return double(node.staticBenefit) * vis * foreshorten / (cost * distance * distance);
}

}  // namespace hlod
