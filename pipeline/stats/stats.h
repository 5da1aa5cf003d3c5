// `hlod stats DB`: the preprocessing statistics of thesis §3.2 and §6 (blocks = hlod0 nodes,
// total nodes, maximum depth, per-level nodes / triangles / texels / bytes, the always-resident
// hlod0 set, mean triangles per node against c_desiredTris), the build's time per stage from the
// "<DB>.build.json" sidecar, and - when the input is the thesis-scale synthetic city - the
// thesis's own figures beside ours (114 hlod0 nodes, 2,296 nodes, depth 5, 8.95 M triangles,
// 937 M texels). Per-level figures come from formats/inspect.h (the same numbers as inspect).
#pragma once

#include "formats/build_report.h"
#include "formats/constants.h"
#include "formats/inspect.h"
#include "pipeline/tree_rules.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace hlod::stats {

// Thesis §1.1 and §3.2 figures of the Berkeley model.
struct ThesisFigures {
    uint64_t hlod0Nodes = 114;
    uint64_t nodes = 2296;
    uint32_t depth = 5;
    uint64_t triangles = 8'950'000;
    uint64_t texels = 937'000'000;
    uint64_t uncompressedTextureMiB = 2680;
};

// The synthetic city manifest (city.json of `hlod synth city`) an input path points at.
struct CityManifest {
    std::string path;
    double scale = 0;
    uint64_t seed = 0, blocks = 0, triangles = 0, texels = 0;
};

// Looks for city.json at the database's "input" (the file itself, inside it, or beside it),
// relative to the working directory, the database's directory and the directories above it.
std::optional<CityManifest> findCityManifest(const std::string& dbPath, const Skeleton& skeleton);

// Thesis figures are shown when the input is the synthetic city at scale 1 (its manifest says
// so), or when forced.
bool isThesisScale(const std::optional<CityManifest>& manifest);

// One level against its targets. A simplified node's target is numTriangles / factor (§3.2) with
// numTriangles its subtree's leaf triangles (the originals plus the cuts' extra triangles, the
// closest the database comes to the piece's input): c_desiredTris x c_levelFactor^level x
// subtree leaves / block leaves. Leaves keep the originals and have no target.
struct LevelCheck {
    uint64_t maxTriangles = 0;     // largest node of the level
    uint64_t simplifiedNodes = 0;  // nodes with children
    uint64_t missing = 0;          // simplified nodes above kTargetSlack x their target
    double worstRatio = 0;         // largest triangles / target of a simplified node
    double simplifiedTriangles = 0, targetTriangles = 0;  // sums over the simplified nodes
    double meanError = 0, maxError = 0;  // stored geometric error (bounds the subtree's), all nodes
};

// The §3.2 tree arithmetic under both leaf rules for the thesis's mean block (8.95 M / 114
// triangles) with constants `c` (Table 6.1's are Constants{}); pipeline/TREE.md.
struct TreeArithmetic {
    double desiredTris = 0, levelFactor = 0;
    double meanBlockTriangles = 0, hlod0Factor = 0;
    TreeShape belowOne, stopBefore;  // per block
};
TreeArithmetic thesisArithmetic(const Constants& c);

// What the build measured per level (the build report's "nodes", issue #16): the two-sided error
// against the original surface (mean of the nodes' means, largest max), the one-sided error it
// replaced (largest), the nodes whose texture was baked and their PSNR against the source, and
// (leaves built with --leaf-psnr) the stored textures against the source over the texels
// triangles use, pooled over the level (pipeline/TEXTURE_SIZE.md).
struct LevelQuality {
    uint64_t nodes = 0, baked = 0, texels = 0;
    double errorMean = 0, errorMax = 0, oneSidedMax = 0;
    double psnrMin = 0, psnrMean = 0;  // over the baked nodes (0 when none)
    uint64_t fidelityTexels = 0, fidelityStoredTexels = 0, fidelitySamples = 0;  // used, stored (of the measured nodes)
    double fidelitySquaredError = 0;
    double fidelityPsnr() const;  // psnrDb (formats/metrics.h); 0 when not measured
};
std::vector<LevelQuality> levelQuality(const std::vector<NodeQuality>& nodes);

struct Stats {
    DatabaseSummary summary;
    std::vector<LevelCheck> checks;  // per level
    double levelFactor = 0;          // c_levelFactor of the build
    std::string leafRule, planes;    // tree.leafRule / tree.planes metadata ("" before they existed)
    std::string errorCap;            // tree.errorCap metadata: "on" or "off" (every build since stop 41)
    std::string treeError;           // tree.error metadata: "bound", "exact" or "simplifier" (bottom-up builds only)
    uint64_t leafNodes = 0, leafTriangles = 0, leafTexels = 0;  // finest detail = the input
    uint64_t totalTriangles = 0;                                // over all nodes
    double desiredTris = 0;                                     // c_desiredTris of the build
    std::optional<BuildReport> build;
    std::string staleReport;  // why DB.build.json was left out (the report of another build), or ""
    std::optional<CityManifest> city;
    bool thesis = false;
};

Stats computeStats(const Database& db, bool forceThesis);
// hlod0 against its target alone (Stats::checks[0]), from the skeleton: `hlod build` and `hlod
// merge` warn when it is missed (the level drawn whatever the budget).
LevelCheck hlod0Check(const Database& db);

// Triangles of the input: the build sidecar's count, else the leaves'.
uint64_t inputTriangles(const Stats& s);

nlohmann::json toJson(const Stats& s);
void printStats(std::ostream& os, const Stats& s);

}  // namespace hlod::stats
