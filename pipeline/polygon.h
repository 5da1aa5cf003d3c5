// A polygon face (an OBJ `f` line, a PLY face list) cut into triangles (polygon.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace hlod {

// Ear clipping costs O(n^3) here; a polygon with more corners is fanned (scans write triangles).
inline constexpr size_t kMaxEarClippedCorners = 64;

// The triangles of the polygon with `corners` in order, as triples of corner indices in its winding:
// the fan (0, k - 1, k) when it is convex, flat to a line, or has more than kMaxEarClippedCorners
// corners (the fan every polygon was cut into until stop 46); otherwise ear clipping in the plane of
// its Newell normal, so a concave polygon's triangles do not fold over its notch.
void triangulatePolygon(std::span<const std::array<double, 3>> corners, std::vector<std::array<uint32_t, 3>>& triangles);

}  // namespace hlod
