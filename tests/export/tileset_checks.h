// Test support for `hlod export tiles`: reading an exported tileset back (GLB chunks, the
// KHR_draco_mesh_compression primitives decoded with Draco) and the structural rules of the 3D
// Tiles validator written as our own checks (3D Tiles 1.1 §Tileset JSON, §Bounding volumes,
// §Geometric error, §Refinement, §Content).
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hlod::test {

// A GLB split into its JSON and binary chunks (glTF 2.0 §4.4); throws std::runtime_error.
struct GlbFile {
    nlohmann::json json;
    std::vector<uint8_t> bin;
};
GlbFile readGlb(const std::string& path);

// One primitive decoded from its Draco buffer view, positions in the tileset's z-up frame (the
// glTF node matrix and the y-up to z-up rotation of 3D Tiles applied). `attributesMatch` is false
// when a semantic of the extension's `attributes` map names a Draco attribute of another type.
struct DecodedPrimitive {
    uint32_t triangles = 0, vertices = 0;
    std::vector<std::array<double, 3>> positions;
    bool attributesMatch = true;
    bool countsMatchAccessors = true;
    bool minMaxMatch = true;  // POSITION accessor min/max equal the decoded extremes
};
std::vector<DecodedPrimitive> decodePrimitives(const GlbFile& glb);

// Every violated structural rule of the tileset in `folder`, one message each: schema fields
// (required, types, allowed keys), asset.version 1.1, refine values, geometricError
// non-increasing from parent to child, every child's box inside its parent's, every content
// inside its tile's box (all decoded vertices), every URI resolvable inside the folder.
std::vector<std::string> checkTileset(const std::string& folder);

}  // namespace hlod::test
