// Test fixture: a NodeSource (player/node_source.h) over an in-memory skeleton with synthesized
// meshes, for tests and benchmarks of the engine without a database file.
#pragma once

#include "player/node_source.h"

#include <cstdint>
#include <memory>

namespace hlod {

// Node n decodes to one mesh of n.texturedTriangles triangles with a 1x1 texture and one of
// n.untexturedTriangles triangles; its stored size is `bytesPerTriangle` per triangle.
std::shared_ptr<const NodeSource> memorySource(Skeleton skeleton, uint32_t bytesPerTriangle = 16);

}  // namespace hlod
