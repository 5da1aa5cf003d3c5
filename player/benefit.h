// The one benefit measure every selection policy is scored by (player/POLICIES.md "Benefit"),
// after the benefit of T. A. Funkhouser and C. H. Séquin, "Adaptive Display Algorithm for
// Interactive Frame Rates During Visualization of Complex Virtual Environments", SIGGRAPH 1993,
// §4.2: benefit = size x accuracy. Here size is the node's surface area projected to pixels and
// accuracy falls with the node's geometric error projected to pixels (the screen-space error
// of 3D Tiles and Nexus): accuracy = 1 / (1 + error_px), 1 when exact, 0.5 at one pixel (FS's
// accuracy 1 - 0.5 / samples^m is 0.5 at one sample). Also the projections the `static` and
// `sse` policies threshold.
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
// projectedAreaPx / (1 + projectedErrorPx): "accurate pixels".
double nodeBenefit(const Node& node, const Projection& p);
// Sum of nodeBenefit over the drawn nodes that are visible.
double frontBenefit(const Skeleton& skeleton, std::span<const DrawItem> drawn, const Projection& p,
                    const std::function<bool(uint32_t)>& visible);

}  // namespace hlod
