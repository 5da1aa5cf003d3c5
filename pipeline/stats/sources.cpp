// Side input of `hlod stats` (besides the build report, formats/build_report.h): the synthetic
// city's city.json, found through the database's "input" metadata. The thesis's
// figures (§1.1, §3.2) are put beside ours only when that manifest says the input is the city at
// scale 1: the rule rests on what the generator recorded, not on guessing from counts.
#include "pipeline/stats/stats.h"

#include "formats/errors.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <type_traits>

namespace hlod::stats {

namespace {

namespace fs = std::filesystem;

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path.string() + ": cannot read");
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception&) {
        throw InputError(path.string() + ": not valid JSON");  // as a bad build report: exit 2
    }
}

// A count is a JSON integer >= 0, a scale a positive finite number: -1 was printed as 2^64 - 1 and
// 1e300 converted to a count was undefined behaviour (until stop 45).
template <class T>
T field(const nlohmann::json& j, const char* key, const fs::path& path) {
    if (!j.contains(key)) throw InputError(path.string() + ": missing \"" + key + "\"");
    const nlohmann::json& v = j.at(key);
    const bool fits = std::is_integral_v<T> ? v.is_number_unsigned() : v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() > 0;
    if (!fits)
        throw InputError(path.string() + ": \"" + key + "\" = " + v.dump() + " is not " +
                         (std::is_integral_v<T> ? "a count" : "a positive number"));
    return v.get<T>();
}

std::optional<CityManifest> readManifest(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return std::nullopt;
    nlohmann::json j = readJson(path);
    if (!j.is_object() || j.value("generator", "") != "hlod synth city") return std::nullopt;
    CityManifest m;
    m.path = path.string();
    m.scale = field<double>(j, "scale", path);
    m.seed = field<uint64_t>(j, "seed", path);
    m.blocks = field<uint64_t>(j, "block_count", path);
    m.triangles = field<uint64_t>(j, "triangles", path);
    m.texels = field<uint64_t>(j, "texels", path);
    return m;
}

}  // namespace

std::optional<CityManifest> findCityManifest(const std::string& dbPath, const Skeleton& skeleton) {
    const std::string* input = skeleton.findMeta("input");
    if (!input || input->empty()) return std::nullopt;
    fs::path in(*input);
    // A relative input was relative to where the build ran: try the working directory, then the
    // database's folder and each folder above it.
    std::vector<fs::path> bases = {in};
    if (in.is_relative()) {
        std::error_code ec;
        fs::path dir = fs::absolute(fs::path(dbPath), ec).parent_path();
        for (int up = 0; up < 64 && !dir.empty(); ++up, dir = dir.parent_path()) {
            bases.push_back(dir / in);
            if (dir == dir.root_path()) break;
        }
    }
    for (const fs::path& base : bases) {
        std::error_code ec;
        if (!fs::exists(base, ec)) continue;  // the input was not here: a city.json beside it is another input's
        for (const fs::path& candidate : {base, base / "city.json", base.parent_path() / "city.json"}) {
            if (candidate.filename() != "city.json") continue;
            // a manifest of other blocks (the city's, beside one of its blocks built alone) is not this input's
            if (auto m = readManifest(candidate); m && m->blocks == skeleton.roots().size()) return m;
        }
    }
    return std::nullopt;
}

bool isThesisScale(const std::optional<CityManifest>& manifest) {
    return manifest && manifest->scale == 1.0;
}

}  // namespace hlod::stats
