// Test fixture: a small procedural HLOD database written through the Writer API: a grid of
// blocks over a wavy textured terrain, each block a full c_levelFactor-ary tree whose level L
// has levelFactor^L pieces (cut along the longest axis, as thesis §3.2). Used by the tests, the
// benchmarks and the fuzz seed corpus; not a substitute for the pipeline.
#pragma once

#include "formats/codec.h"

#include <cstdint>
#include <string>

namespace hlod {

struct SyntheticOptions {
    uint32_t blocksX = 2, blocksY = 2;
    uint32_t levels = 3;              // levels per block (hlod0 .. hlod{levels-1})
    uint32_t levelFactor = 4;         // children per node
    uint32_t trianglesPerNode = 512;  // roughly c_desiredTris
    uint32_t textureSize = 64;        // texels per side of each node's texture; 0 = untextured
    float blockSize = 100;            // metres
    uint32_t seed = 1;
};

// Writes the database atomically; throws std::runtime_error.
void writeSyntheticDatabase(const std::string& path, const SyntheticOptions& options);

// A smooth RGB texture of size x size texels: low-frequency waves, different per `seed` (the
// baking tests and benchmark).
Image smoothTexture(uint32_t size, int seed);

}  // namespace hlod
