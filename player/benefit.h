// The one benefit measure every selection policy is scored by (player/POLICIES.md "Benefit"),
// after the benefit of T. A. Funkhouser and C. H. Séquin, "Adaptive Display Algorithm for
// Interactive Frame Rates During Visualization of Complex Virtual Environments", SIGGRAPH 1993,
// §4.2: benefit = size x accuracy. Size is the node's surface area projected at the distance of
// its block (the hlod0 root's box), so that it adds up over a node's children; accuracy falls
// with the node's geometric error projected at the node's own box (the screen-space error of
// 3D Tiles and Nexus): accuracy = 1 / (1 + error_px), 1 when exact, 0.5 at one pixel (FS's
// accuracy 1 - 0.5 / samples^m is 0.5 at one sample). Refining a node never lowers the benefit
// when its children's surface areas add up to at least its own and their errors are at most its
// own (the build makes errors monotone and boxes nested; tests/player/test_compare.cpp checks
// it). projectedAreaPx and projectedErrorPx are also the projections the `static` and `sse`
// policies threshold.
#pragma once

#include "formats/db.h"
#include "player/renderer.h"

#include <functional>
#include <span>

namespace hlod {

struct Projection {
    double eye[3] = {0, 0, 0};
    double focalPx = 1;     // (viewport height / 2) / tan(vfov / 2): pixels per unit at distance 1
    double viewportPx = 1;  // viewport pixels (height x aspect x height): a node's size is capped at it
};

Projection makeProjection(const Camera& camera, double viewportHeightPx);

// Distance from the eye to the node's box, at least 1 unit (0 inside the box would be infinite).
double projectionDistance(const Node& node, const Projection& p);
// Surface area of the node (staticBenefit^2 / triangles, §3.3) projected at that distance, in
// pixels, at most the viewport (no foreshortening, no occlusion).
double projectedAreaPx(const Node& node, const Projection& p);
// geometricError x focalPx / distance: the node's error on screen, pixels.
double projectedErrorPx(const Node& node, const Projection& p);
// Distance from the eye to the box of the node's block (its hlod0 ancestor), at least 1 unit.
double blockDistance(const Skeleton& skeleton, const Node& node, const Projection& p);
// "Accurate pixels": surface area x (focalPx / blockDistance)^2 (no viewport cap)
// / (1 + projectedErrorPx).
double nodeBenefit(const Skeleton& skeleton, const Node& node, const Projection& p);
// Sum of nodeBenefit over the drawn nodes that are visible.
double frontBenefit(const Skeleton& skeleton, std::span<const DrawItem> drawn, const Projection& p,
                    const std::function<bool(uint32_t)>& visible);

}  // namespace hlod
