// The common benefit measure of player/benefit.h (Funkhouser & Séquin 1993 §4.2, benefit =
// size x accuracy; accuracy from the projected geometric error). Choices: player/POLICIES.md.
#include "player/benefit.h"

#include <algorithm>
#include <cmath>

namespace hlod {

Projection makeProjection(const Camera& camera, double viewportHeightPx) {
    Projection p;
    std::copy(camera.position, camera.position + 3, p.eye);
    p.focalPx = 0.5 * viewportHeightPx / std::tan(camera.vfovDegrees * M_PI / 360.0);
    p.viewportPx = viewportHeightPx * viewportHeightPx * camera.aspect;
    return p;
}

double projectionDistance(const Node& node, const Projection& p) {
    const Box3f& b = node.bounds;
    double dx = std::max({double(b.min.x) - p.eye[0], 0.0, p.eye[0] - double(b.max.x)});
    double dy = std::max({double(b.min.y) - p.eye[1], 0.0, p.eye[1] - double(b.max.y)});
    double dz = std::max({double(b.min.z) - p.eye[2], 0.0, p.eye[2] - double(b.max.z)});
    return std::max(std::sqrt(dx * dx + dy * dy + dz * dz), 1.0);
}

double projectedAreaPx(const Node& node, const Projection& p) {
    uint32_t tris = node.triangles();
    if (tris == 0) return 0;
    double area = double(node.staticBenefit) * node.staticBenefit / tris;  // §3.3: staticBenefit = sqrt(tris x area)
    double d = projectionDistance(node, p);
    return std::min(area * p.focalPx * p.focalPx / (d * d), p.viewportPx);
}

double projectedErrorPx(const Node& node, const Projection& p) {
    return double(node.geometricError) * p.focalPx / projectionDistance(node, p);
}

double blockDistance(const Skeleton& skeleton, const Node& node, const Projection& p) {
    const Node* root = &node;
    while (root->parent != kNone) root = &skeleton.nodes[root->parent];
    return projectionDistance(*root, p);
}

double nodeBenefit(const Skeleton& skeleton, const Node& node, const Projection& p) {
    uint32_t tris = node.triangles();
    if (tris == 0) return 0;
    double area = double(node.staticBenefit) * node.staticBenefit / tris;  // §3.3: staticBenefit = sqrt(tris x area)
    double D = blockDistance(skeleton, node, p);  // shared by the whole block: size adds up over children
    double size = area * p.focalPx * p.focalPx / (D * D);
    return size / (1 + projectedErrorPx(node, p));  // FS §4.2 size x accuracy
}

double frontBenefit(const Skeleton& skeleton, std::span<const DrawItem> drawn, const Projection& p,
                    const std::function<bool(uint32_t)>& visible) {
    double sum = 0;
    for (const DrawItem& d : drawn)
        if (visible(d.node)) sum += nodeBenefit(skeleton, skeleton.nodes[d.node], p);
    return sum;
}

}  // namespace hlod
