// An independent measure of a baked texture (pipeline/bake.cpp) for hlod_bench_bake: the PSNR of
// the atlas, read bilinearly at each covered texel's 2 x 2 sub-samples, against the source colour
// at that sub-sample's own closest original point (one exact query per sub-sample). The baker's
// own PSNR compares the atlas with the colours the baker itself took, so a cheaper correspondence
// (fewer queries) can raise it while moving away from the original; this one cannot be fooled so
// (pipeline/TEXTURE_SPEED.md round 8).
#pragma once

#include "pipeline/pipeline.h"

#include <vector>

namespace hlod::bench {

double referencePsnr(const BakedTexture& baked, const std::vector<BakeSource>& sources);

}  // namespace hlod::bench
