// Reader and writer of the build report (formats/build_report.h), one schema for both.
#include "formats/build_report.h"

#include "formats/errors.h"
#include "formats/json_text.h"
#include "formats/temp_files.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace hlod {

namespace {

template <class T>
constexpr bool kCount = std::is_integral_v<T> && !std::is_same_v<T, bool>;

// A count is a whole number from 0 to its type's largest: nlohmann converts -1 and 2.5 to an
// unsigned count without a word (`hlod stats` printed -1 as 2^64 - 1 until stop 46).
template <class T>
void checkCount(const nlohmann::json& v, const char* key, const std::string& path) {
    if (!v.is_number_unsigned() || v.get<uint64_t>() > std::numeric_limits<T>::max())
        throw InputError(path + ": \"" + key + "\" must be a whole number from 0 to " +
                         std::to_string(std::numeric_limits<T>::max()));
}

template <class T>
T field(const nlohmann::json& j, const char* key, const std::string& path) {
    if (!j.is_object() || !j.contains(key)) throw InputError(path + ": missing \"" + key + "\"");
    const nlohmann::json& v = j.at(key);
    if constexpr (kCount<T>) checkCount<T>(v, key, path);
    if constexpr (std::is_same_v<T, std::vector<uint64_t>>)
        if (v.is_array())
            for (const nlohmann::json& e : v) checkCount<uint64_t>(e, key, path);
    try {
        return v.get<T>();
    } catch (const nlohmann::json::exception&) {
        throw InputError(path + ": \"" + key + "\" has the wrong type");
    }
}

// A time is a number of seconds, 0 or more (a wall time of -1 was printed as given until stop 50).
double seconds(const nlohmann::json& j, const char* key, const std::string& path) {
    const double s = field<double>(j, key, path);
    if (!(s >= 0)) throw InputError(path + ": \"" + key + "\" must be a number of seconds, 0 or more");
    return s;
}

}  // namespace

std::string buildReportPath(const std::string& database) { return database + ".build.json"; }

void writeBuildReport(const std::string& path, const BuildReport& r) {
    nlohmann::json j;
    j["stages"] = nlohmann::json::array();
    for (const BuildStage& s : r.stages) j["stages"].push_back({{"name", s.name}, {"seconds", s.seconds}, {"items", s.items}});
    j["peak_rss_bytes"] = r.peakRssBytes;
    j["memory_limit_bytes"] = r.memoryLimitBytes;
    j["input_triangles"] = r.inputTriangles;
    j["wall_seconds"] = r.wallSeconds;
    j["cpu_seconds"] = r.cpuSeconds;
    j["huge_pages"] = r.hugePages;
    j["output_bytes"] = r.outputBytes;
    j["nodes_per_level"] = r.nodesPerLevel;
    j["texture_problems"] = r.textureProblems;
    j["nodes"] = nlohmann::json::array();
    for (const NodeQuality& n : r.nodes) {
        nlohmann::json node = {{"block", n.block}, {"node", n.node}, {"level", n.level}, {"triangles", n.triangles},
                               {"texels", n.texels}, {"error_one_sided", n.errorOneSided}, {"error_mean", n.errorMean},
                               {"error_max", n.errorMax}, {"baked", n.baked}, {"bake_psnr_db", n.bakePsnrDb}};
        if (n.fidelitySamples)
            node["texture_fidelity"] = {{"texels", n.fidelityTexels}, {"samples", n.fidelitySamples},
                                        {"squared_error", n.fidelitySquaredError}};
        j["nodes"].push_back(node);
    }
    writeTextFile(path, "build report", jsonText(j, 2) + "\n");  // beside it, then renamed: never half-written
}

std::optional<BuildReport> readBuildReport(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return std::nullopt;
    refuseSpecialFile(path);  // a FIFO blocked the open for good (until stop 44)
    if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": a folder, not a build report");
    std::ifstream in(path);
    if (!in) throw InputError(path + ": cannot read");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception&) {
        throw InputError(path + ": not valid JSON");
    }
    if (!j.is_object()) throw InputError(path + ": not a build report (expected a JSON object)");
    BuildReport r;
    const auto stages = field<nlohmann::json>(j, "stages", path);
    if (!stages.is_array()) throw InputError(path + ": \"stages\" is not an array");
    for (const auto& s : stages)
        r.stages.push_back({field<std::string>(s, "name", path), seconds(s, "seconds", path),
                            field<uint64_t>(s, "items", path)});
    r.peakRssBytes = field<uint64_t>(j, "peak_rss_bytes", path);
    r.inputTriangles = field<uint64_t>(j, "input_triangles", path);
    r.outputBytes = field<uint64_t>(j, "output_bytes", path);
    r.wallSeconds = seconds(j, "wall_seconds", path);
    r.cpuSeconds = seconds(j, "cpu_seconds", path);
    if (j.contains("huge_pages")) r.hugePages = field<bool>(j, "huge_pages", path);
    if (j.contains("memory_limit_bytes")) r.memoryLimitBytes = field<uint64_t>(j, "memory_limit_bytes", path);
    if (j.contains("nodes_per_level")) r.nodesPerLevel = field<std::vector<uint64_t>>(j, "nodes_per_level", path);
    if (j.contains("texture_problems")) r.textureProblems = field<std::vector<std::string>>(j, "texture_problems", path);
    if (j.contains("nodes")) {
        const auto nodes = field<nlohmann::json>(j, "nodes", path);
        if (!nodes.is_array()) throw InputError(path + ": \"nodes\" is not an array");
        for (const auto& n : nodes) {
            r.nodes.push_back({field<uint32_t>(n, "block", path), field<uint32_t>(n, "node", path), field<uint32_t>(n, "level", path),
                               field<uint64_t>(n, "triangles", path), field<uint64_t>(n, "texels", path),
                               field<double>(n, "error_one_sided", path), field<double>(n, "error_mean", path),
                               field<double>(n, "error_max", path), field<bool>(n, "baked", path),
                               field<double>(n, "bake_psnr_db", path)});
            if (!n.contains("texture_fidelity")) continue;
            const auto f = field<nlohmann::json>(n, "texture_fidelity", path);
            r.nodes.back().fidelityTexels = field<uint64_t>(f, "texels", path);
            r.nodes.back().fidelitySamples = field<uint64_t>(f, "samples", path);
            r.nodes.back().fidelitySquaredError = field<double>(f, "squared_error", path);
        }
        // A node of level L has L ancestors in the report: a larger level (-1 read as 2^32 - 1)
        // sized the per-level table by it (a crash or std::bad_alloc until stop 44).
        for (const NodeQuality& n : r.nodes)
            if (n.level >= r.nodes.size())
                throw InputError(path + ": node " + std::to_string(n.node) + " has level " + std::to_string(n.level) +
                                 ", impossible among " + std::to_string(r.nodes.size()) + " nodes (corrupt build report)");
    }
    return r;
}

}  // namespace hlod
