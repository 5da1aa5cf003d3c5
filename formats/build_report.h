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

struct BuildReport {
    std::vector<BuildStage> stages;
    uint64_t peakRssBytes = 0, memoryLimitBytes = 0, inputTriangles = 0, outputBytes = 0;
    double wallSeconds = 0, cpuSeconds = 0;
    std::vector<uint64_t> nodesPerLevel;
    // One line per unusable texture (README "Inputs: textures"), its material left untextured;
    // absent from reports written before the key existed (read as none).
    std::vector<std::string> textureProblems;
};

// "<DB>.build.json".
std::string buildReportPath(const std::string& database);

// Writes the report (JSON, snake_case keys); throws std::runtime_error "PATH: problem".
void writeBuildReport(const std::string& path, const BuildReport& report);

// Reads a report; std::nullopt when there is none. Throws InputError "PATH: problem" when it
// exists but is not a valid report.
std::optional<BuildReport> readBuildReport(const std::string& path);

}  // namespace hlod
