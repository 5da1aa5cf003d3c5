// What `hlod inspect` shows, computed without the CLI (reused by `hlod stats`): a per-level
// summary of a database, one node in full, and the tree, as plain structs and as JSON.
#pragma once

#include "formats/db.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hlod {

struct LevelSummary {
    uint32_t level = 0;
    uint64_t nodes = 0;
    uint64_t texturedTriangles = 0, untexturedTriangles = 0;
    uint64_t vertices = 0;
    uint64_t texels = 0;
    uint64_t geometryBytes = 0, textureBytes = 0;
    uint64_t blobs = 0;
    double cost = 0;
    float minGeometricError = 0, maxGeometricError = 0;
};

struct DatabaseSummary {
    std::string path;
    uint16_t major = 0, minor = 0;
    uint64_t fileSize = 0;
    uint64_t nodes = 0, blobs = 0, blocks = 0;
    uint32_t depth = 0;                 // nodes on the longest root-to-leaf path
    std::vector<LevelSummary> levels;   // index = level
    std::vector<std::pair<std::string, std::string>> constants;   // meta keys "c_..."
    std::vector<std::pair<std::string, std::string>> provenance;  // the other meta keys
};

DatabaseSummary summarize(const Database& db);

nlohmann::json toJson(const DatabaseSummary& s);
// One node in full, with its blob records; throws std::invalid_argument for a bad id.
nlohmann::json nodeJson(const Skeleton& s, uint32_t id);
// The tree from the hlod0 list down to `maxDepth` levels (0 = unlimited): nested
// {"id", "level", "block", "triangles", "texels", "bytes", "error", "children"}; a node below the cut
// with children has "children_not_shown": N instead of "children".
nlohmann::json treeJson(const Skeleton& s, uint32_t maxDepth);

}  // namespace hlod
