// Test fixture: hand-built in-memory HLOD skeletons for the player tests and benchmarks.
#pragma once

#include "formats/db.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace hlod::test {

// Appends a node (links are made by linkSkeleton).
inline uint32_t addNode(Skeleton& s, uint32_t parent, Box3f bounds, uint32_t triangles, float cost = -1) {
    Node n;
    n.id = uint32_t(s.nodes.size());
    n.parent = parent;
    n.level = parent == kNone ? 0 : s.nodes[parent].level + 1;
    n.bounds = bounds;
    n.texturedTriangles = triangles;
    n.cost = cost >= 0 ? cost : float(triangles);
    float area = (bounds.max.x - bounds.min.x) * (bounds.max.y - bounds.min.y);
    n.staticBenefit = std::sqrt(float(triangles) * area);
    n.avgNormal = {0, 0, 1};
    s.nodes.push_back(n);
    return n.id;
}

// First child / next sibling lists (thesis §3.3) from the parent links, in id order; the
// hlod0 nodes are siblings of each other.
inline void linkSkeleton(Skeleton& s) {
    std::vector<uint32_t> lastChild(s.nodes.size(), kNone);
    uint32_t lastRoot = kNone;
    for (Node& n : s.nodes) {
        n.firstChild = n.nextSibling = kNone;
        uint32_t& last = n.parent == kNone ? lastRoot : lastChild[n.parent];
        if (last != kNone)
            s.nodes[last].nextSibling = n.id;
        else if (n.parent != kNone)
            s.nodes[n.parent].firstChild = n.id;
        last = n.id;
    }
}

// Blocks of `blockSize` metres on the z = 0 plane, each a full quadtree of `levels` levels whose
// nodes all have `triangles` triangles (cost = triangles).
inline Skeleton gridSkeleton(uint32_t blocksX, uint32_t blocksY, uint32_t levels, uint32_t triangles = 512,
                             float blockSize = 100) {
    Skeleton s;
    s.blockCount = blocksX * blocksY;
    struct Item {
        uint32_t parent;
        Box3f box;
        uint32_t level;
    };
    std::vector<Item> queue;
    for (uint32_t by = 0; by < blocksY; ++by)
        for (uint32_t bx = 0; bx < blocksX; ++bx)
            queue.push_back({kNone, {{bx * blockSize, by * blockSize, 0}, {(bx + 1) * blockSize, (by + 1) * blockSize, 10}}, 0});
    for (size_t i = 0; i < queue.size(); ++i) {
        Item it = queue[i];
        uint32_t id = addNode(s, it.parent, it.box, triangles);
        s.nodes[id].block = it.parent == kNone ? id : s.nodes[it.parent].block;
        if (it.level + 1 >= levels) continue;
        float mx = 0.5f * (it.box.min.x + it.box.max.x), my = 0.5f * (it.box.min.y + it.box.max.y);
        for (int q = 0; q < 4; ++q) {
            Box3f c = it.box;
            (q & 1 ? c.min.x : c.max.x) = mx;
            (q & 2 ? c.min.y : c.max.y) = my;
            queue.push_back({id, c, it.level + 1});
        }
    }
    linkSkeleton(s);
    return s;
}

// gridSkeleton whose geometric error halves per level from `rootError` at the blocks' roots
// (leaves exact), as a build gives.
inline Skeleton errorGridSkeleton(uint32_t blocksX, uint32_t blocksY, uint32_t levels, float blockSize = 50,
                                  float rootError = 2) {
    Skeleton s = gridSkeleton(blocksX, blocksY, levels, 512, blockSize);
    for (Node& n : s.nodes) n.geometricError = n.firstChild == kNone ? 0.f : std::ldexp(rootError, -int(n.level));
    return s;
}

}  // namespace hlod::test
