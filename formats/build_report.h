// The build report "<DB>.build.json" that `hlod build` writes beside a database: what varies
// from run to run (time per stage, peak memory), which the database itself never holds, so the
// same input and options give the same database bytes. `hlod stats` reads it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hlod {

struct BuildStage {
    std::string name;
    double seconds = 0;
    uint64_t items = 0;
};

// What the build measured of one node (issue #16): its error against the original surface it
// stands for (pipeline/error.cpp) and, for a node whose texture was baked (pipeline/bake.cpp),
// the baked texture's PSNR against the source over the texels its triangles cover; for a leaf
// built with --leaf-psnr, its stored (decoded) textures against the source texels they copy
// (pipeline/TEXTURE_SIZE.md).
struct NodeQuality {
    uint32_t block = 0, node = 0, level = 0;  // node: index within its block, breadth-first (hlod0 = 0)
    uint64_t triangles = 0, texels = 0;
    double errorOneSided = 0;                 // simplified -> original only (the measure before #16)
    double errorMean = 0, errorMax = 0;       // two-sided; errorMax is the node's stored geometric error before the subtree max
    bool baked = false;
    double bakePsnrDb = 0;                    // 0 when not baked
    uint64_t fidelityTexels = 0, fidelitySamples = 0;  // texels compared (x channels), 0 when not measured
    double fidelitySquaredError = 0;                   // summed over the samples
};

struct BuildReport {
    std::vector<BuildStage> stages;
    uint64_t peakRssBytes = 0, memoryLimitBytes = 0, inputTriangles = 0, outputBytes = 0;
    double wallSeconds = 0, cpuSeconds = 0;
    // The heap's large blocks on 2 MiB transparent huge pages (formats/cli/huge_pages.h; speed
    // figures depend on it); absent from reports written before the key existed (read as false).
    bool hugePages = false;
    std::vector<uint64_t> nodesPerLevel;
    // One line per unusable texture (README "Textures: one rule"), its material left untextured;
    // absent from reports written before the key existed (read as none).
    std::vector<std::string> textureProblems;
    std::vector<NodeQuality> nodes;  // in block order, then breadth-first; absent from older reports
};

// "<DB>.build.json".
std::string buildReportPath(const std::string& database);

// Writes the report (JSON, snake_case keys); throws std::runtime_error "PATH: problem".
void writeBuildReport(const std::string& path, const BuildReport& report);

// Reads a report; std::nullopt when there is none. Throws InputError "PATH: problem" when it
// exists but is not a valid report.
std::optional<BuildReport> readBuildReport(const std::string& path);

}  // namespace hlod
