// The whole city, streamed to disk (thesis §1.1 model at `scale`): blocks are planned up front
// (a few kB each), then meshed, textured and written one at a time per worker thread and freed,
// so memory stays at a few blocks whatever the scale. city.json (seed, scale, per-block counts)
// is written last, so its presence marks a complete city that stats and tests can check.
#include "pipeline/synth/synth.h"

#include "formats/errors.h"
#include "formats/json_text.h"
#include "formats/temp_files.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
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

// An existing DIR is written into only when it is empty (but for killed runs' staging folders)
// or holds an earlier city (its city.json; the files beside it, camera paths, are kept): until
// stop 47 a scan's folder got a city mixed into it, and a user's block_000.obj was replaced.
void checkEarlierCity(const fs::path& dir) {
    std::error_code ec;
    if (fs::exists(dir / "city.json", ec)) return;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (it->path().filename().string().rfind(".city.tmp-", 0) != 0)
            throw std::invalid_argument(dir.string() + ": holds " + it->path().filename().string() +
                                        " but no city.json (not an earlier city); not written into");
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

// The complete city in `staging` becomes DIR: the folder itself when DIR did not exist; else (the
// staging folder is inside DIR, on its filesystem) its blocks replace the earlier city's, whose
// other files go (a larger run's blocks would be read as this city's), and city.json comes last.
void moveCity(StagingFolder& staging, const fs::path& dir, bool existed) {
    staging.publish([&] {
        if (!existed) {
            std::error_code ec;
            fs::rename(staging.path, dir, ec);
            if (ec)  // another run made DIR since this one began (two syntheses into one new folder)
                throw std::runtime_error(dir.string() + ": cannot move the city in (" + ec.message() +
                                         "; another run wrote it meanwhile?)");
            return;
        }
        std::set<fs::path> names;
        for (const auto& entry : fs::directory_iterator(staging.path))
            if (entry.path().filename() != "city.json") names.insert(entry.path().filename());
        for (const fs::path& name : names) fs::rename(fs::path(staging.path) / name, dir / name);
        for (const auto& entry : fs::directory_iterator(dir))
            if (isCityFile(entry.path()) && !names.count(entry.path().filename())) fs::remove(entry.path());
        fs::rename(fs::path(staging.path) / "city.json", dir / "city.json");
        fs::remove(staging.path);  // empty now
    });
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

// The city is written in a staging folder and moved into DIR when complete: a run that fails (a
// full disk, a folder it cannot write) or is interrupted leaves no partial city (an interrupted one
// was a folder `hlod build` read as a city until stop 44); a failure is one line naming the file
// and the reason, as every output of hlod. The staging folder is DIR/.city.tmp-hlodSPACE-PID-XXXXXX when DIR
// exists (a mount point or a link to another filesystem: renames stay on it), else beside DIR.
CityResult generateCity(const CityOptions& options, const std::string& dir) {
    CityPlan plan = planCity(options);
    checkDirectory(dir);
    fs::path target = fs::absolute(dir).lexically_normal();
    if (target.filename().empty()) target = target.parent_path();  // "out/": out itself
    std::error_code ec;
    const bool existed = fs::exists(target, ec);
    if (existed) checkEarlierCity(target);
    if (!existed) fs::create_directories(target.parent_path(), ec);
    StagingFolder staging((existed ? target / ".city" : target).string());
    CityResult result;
    try {
        result = writeCity(options, plan, staging.path);
    } catch (const InputError&) {
        throw;
    } catch (const std::runtime_error& e) {  // name the file the user asked for, not the staging one
        std::string what = e.what();
        const std::string shown = existed ? (fs::path(dir) / "").string() : dir;  // DIR/.city.tmp-…/F -> DIR/F
        const std::string staged = existed ? staging.path + "/" : staging.path;
        for (size_t at = what.find(staged); at != std::string::npos; at = what.find(staged, at + shown.size()))
            what.replace(at, staged.size(), shown);
        throw std::runtime_error(what);
    }
    moveCity(staging, target, existed);
    return result;
}

}  // namespace hlod::synth
