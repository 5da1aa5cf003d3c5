// The whole city, streamed to disk (thesis §1.1 model at `scale`): blocks are planned up front
// (a few kB each), then meshed, textured and written one at a time per worker thread and freed,
// so memory stays at a few blocks whatever the scale. city.json (seed, scale, per-block counts)
// is written last, so its presence marks a complete city that stats and tests can check.
#include "pipeline/synth/synth.h"

#include "formats/json_text.h"
#include "formats/temp_files.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <stdexcept>

namespace hlod::synth {

namespace {

namespace fs = std::filesystem;

// The files a city run writes (an earlier, larger run's blocks would be read as this city's).
bool isCityFile(const fs::path& file) {
    static const std::regex ours(R"(block_\d+\.(obj|mtl|jpg)|city\.json)");
    return std::regex_match(file.filename().string(), ours);
}

void checkDirectory(const fs::path& dir) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw std::runtime_error(dir.string() + ": exists and is not a directory");
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

// The complete city in `staging` becomes DIR: the folder itself when DIR does not exist, else its
// files replace the city's in DIR (an earlier, larger run's blocks would be read as this city's),
// city.json last.
void moveCity(StagingFolder& staging, const std::string& dir) {
    std::error_code ec;
    if (!fs::exists(dir, ec)) {
        fs::rename(staging.path, dir);
        staging.kept = true;
        return;
    }
    for (const auto& entry : fs::directory_iterator(dir))
        if (isCityFile(entry.path())) fs::remove(entry.path());
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(staging.path)) files.push_back(entry.path());
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
        return (a.filename() == "city.json") < (b.filename() == "city.json");
    });
    for (const fs::path& file : files) fs::rename(file, fs::path(dir) / file.filename());
}

CityResult writeCity(const CityOptions& options, const CityPlan& plan, const std::string& dir) {
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
    writeTextFile((fs::path(dir) / "city.json").string(), "the city manifest", jsonText(manifest(plan, result), 1) + "\n");
    return result;
}

}  // namespace

// The city is written in a staging folder beside DIR and moved in when complete: a run that fails
// (a full disk, a folder it cannot write) or is interrupted leaves no partial city (an interrupted
// one was a folder `hlod build` read as a city until stop 44); a failure is one line naming the
// file and the reason, as every output of hlod.
CityResult generateCity(const CityOptions& options, const std::string& dir) {
    CityPlan plan = planCity(options);
    checkDirectory(dir);
    fs::path target = fs::absolute(dir).lexically_normal();
    if (target.filename().empty()) target = target.parent_path();  // "out/": the staging folder beside out, not in it
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    StagingFolder staging(target.string());
    CityResult result;
    try {
        result = writeCity(options, plan, staging.path);
    } catch (const std::exception& e) {  // name the file the user asked for, not the staging one
        std::string what = e.what();
        for (size_t at = what.find(staging.path); at != std::string::npos; at = what.find(staging.path, at + dir.size()))
            what.replace(at, staging.path.size(), dir);
        throw std::runtime_error(what);
    }
    moveCity(staging, target.string());
    return result;
}

}  // namespace hlod::synth
