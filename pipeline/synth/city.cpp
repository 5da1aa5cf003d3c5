// The whole city, streamed to disk (thesis §1.1 model at `scale`): blocks are planned up front
// (a few kB each), then meshed, textured and written one at a time per worker thread and freed,
// so memory stays at a few blocks whatever the scale. city.json (seed, scale, per-block counts)
// is written last, so its presence marks a complete city that stats and tests can check.
#include "pipeline/synth/synth.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <stdexcept>

namespace hlod::synth {

namespace {

namespace fs = std::filesystem;

void prepareDirectory(const fs::path& dir) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw std::runtime_error(dir.string() + ": exists and is not a directory");
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error(dir.string() + ": cannot create directory: " + ec.message());
    // Blocks of an earlier, larger run would be read as part of this city.
    static const std::regex stale(R"(block_\d+\.(obj|mtl|jpg)|city\.json)");
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (std::regex_match(entry.path().filename().string(), stale)) fs::remove(entry.path());
    }
}

nlohmann::json manifest(const CityPlan& plan, const CityResult& result) {
    nlohmann::json blocks = nlohmann::json::array();
    for (const BlockRecord& r : result.blocks) {
        blocks.push_back({{"obj", r.obj},
                          {"mtl", r.mtl},
                          {"texture", r.jpg},
                          {"triangles", r.triangles},
                          {"facade_triangles", r.facadeTriangles},
                          {"aerial_triangles", r.aerialTriangles},
                          {"vertices", r.vertices},
                          {"texture_width", r.width},
                          {"texture_height", r.height},
                          {"texels", r.texels},
                          {"target_triangles", r.targetTriangles},
                          {"target_texels", r.targetTexels},
                          {"length_m", r.length},
                          {"mean_scan_spacing_m", r.meanScanSpacing},
                          {"bounds_min", r.boundsMin},
                          {"bounds_max", r.boundsMax}});
    }
    return {{"generator", "hlod synth city"},
            {"manifest_version", 1},
            {"seed", plan.options.seed},
            {"scale", plan.options.scale},
            {"jpeg_quality", plan.options.jpegQuality},
            {"city_blocks", plan.cityBlocks},
            {"block_count", result.blocks.size()},
            {"triangles", result.triangles},
            {"texels", result.texels},
            {"units", "metres, z up"},
            {"thesis", {{"city_blocks", kThesisCityBlocks},
                        {"blocks", kThesisBlocks},
                        {"triangles", kThesisTriangles},
                        {"texels", kThesisTexels}}},
            {"blocks", blocks}};
}

}  // namespace

CityResult generateCity(const CityOptions& options, const std::string& dir) {
    CityPlan plan = planCity(options);
    prepareDirectory(dir);
    CityResult result;
    result.blocks.resize(plan.blocks.size());
    tbb::parallel_for(size_t(0), plan.blocks.size(), [&](size_t k) {
        result.blocks[k] = writeBlock(plan.blocks[k], dir, options.jpegQuality);
    });
    for (const BlockRecord& r : result.blocks) {
        result.triangles += r.triangles;
        result.texels += r.texels;
        for (const std::string& name : {r.obj, r.mtl, r.jpg}) result.bytes += fs::file_size(fs::path(dir) / name);
    }
    fs::path json = fs::path(dir) / "city.json", tmp = json;
    tmp += ".tmp-synth";
    {
        std::ofstream out(tmp);
        out << manifest(plan, result).dump(1) << '\n';
        if (!out) throw std::runtime_error(json.string() + ": cannot write");
    }
    fs::rename(tmp, json);
    return result;
}

}  // namespace hlod::synth
