// The two readings of the thesis §3.2 tree (pipeline/TREE.md), shared by `hlod build`
// (build_tree.cpp, cut.cpp) and `hlod stats` (the arithmetic printed beside the thesis's 2,296
// nodes): which node is a leaf (LeafRule), where the division planes go (Planes), and the node
// count of a full tree under a leaf rule.
#pragma once

#include <cstdint>
#include <string>

namespace hlod {

// "The division and simplification process is recursively repeated on each piece with a smaller
// simplification factor until the factor becomes less than 1" (§3.2). Leaves keep the original
// triangles under both rules.
enum class LeafRule {
    BelowOne,    // divide every node whose factor is > 1: leaves have factor <= 1 (default)
    StopBefore,  // divide only when the children's factor (factor / c_levelFactor) is >= 1
};
// Division planes perpendicular to the longest side of a piece (§3.2).
enum class Planes {
    Balanced,  // triangle-count quantiles that avoid slicing a surface along itself (default)
    Even,      // evenly spaced over the bounding box; empty pieces are dropped
};

// Where each node's simplification starts (pipeline/BUILD_SPEED.md has both measured).
enum class BuildMode {
    TopDown,   // thesis §3.2 (default): every node simplifies its piece's original triangles
    BottomUp,  // each node simplifies its children's simplified triangles, welded (~1.33 passes)
};
inline const char* buildModeName(BuildMode m) { return m == BuildMode::TopDown ? "top-down" : "bottom-up"; }
// A bottom-up node's geometric error (build_tree.cpp; pipeline/BUILD_SPEED.md has all three measured).
enum class BottomUpError {
    Bound,       // default: two-sided distance to its children's simplified surface + their largest error
    Exact,       // two-sided distance to its original piece, as top-down (a pass over the original per level)
    Simplifier,  // the children's largest error + the simplifier's own estimate (meshopt only): no
                 // distance measured, not a bound of the distance to the original
};
inline const char* bottomUpErrorName(BottomUpError e) {
    return e == BottomUpError::Bound ? "bound" : e == BottomUpError::Exact ? "exact" : "simplifier";
}
// The value of a --bottom-up-error name; false for an unknown name.
[[nodiscard]] inline bool parseBottomUpError(const std::string& name, BottomUpError& out) {
    for (const BottomUpError e : {BottomUpError::Bound, BottomUpError::Exact, BottomUpError::Simplifier})
        if (name == bottomUpErrorName(e)) return out = e, true;
    return false;
}
// The smallest hole the geometric error must see, as a fraction of the node's extent (issue #16;
// build_tree.cpp samples at half of it).
inline constexpr double kMeasuredHole = 10;
inline const char* leafRuleName(LeafRule r) { return r == LeafRule::BelowOne ? "below-one" : "stop-before"; }
inline const char* planesName(Planes p) { return p == Planes::Balanced ? "balanced" : "even"; }

// A simplified node may hold up to this many times its target (numTriangles / factor) before
// it counts as missing it (simplify.cpp's hole-filling fallback; `hlod stats` flags the misses).
inline constexpr double kTargetSlack = 1.25;

// Is a node of simplification factor `factor` a leaf under `rule`?
inline bool isLeaf(double factor, double levelFactor, LeafRule rule) {
    return rule == LeafRule::BelowOne ? factor <= 1 : factor < levelFactor;
}

// Levels and nodes of a block of `triangles` when every division gives c_levelFactor pieces:
// factor_0 = triangles / c_desiredTris, factor_(i+1) = factor_i / c_levelFactor (§3.2).
struct TreeShape {
    uint32_t levels = 0;
    uint64_t nodes = 0;
};
inline TreeShape fullTree(double triangles, double desiredTris, double levelFactor, LeafRule rule) {
    TreeShape shape;
    uint64_t width = 1;
    for (double factor = triangles / desiredTris;; factor /= levelFactor, width *= static_cast<uint64_t>(levelFactor)) {
        ++shape.levels, shape.nodes += width;
        if (isLeaf(factor, levelFactor, rule)) return shape;
    }
}

}  // namespace hlod
