// `hlod split`'s work folder (layout and rules: split_work.h, README "Beyond one machine"). The
// split is the same findBlocks a build runs, so a build from the work folder sees the blocks,
// materials and lattice a build from the input would, and writes the same bytes.
#include "pipeline/split_work.h"

#include "formats/json_text.h"
#include "formats/offset.h"
#include "formats/temp_files.h"

#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <xxhash.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <set>

#ifndef HLOD_VERSION
#define HLOD_VERSION "0.0.0"
#endif

namespace hlod {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Ordered = nlohmann::ordered_json;  // the manifest as written: format first
using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

constexpr const char* kManifest = "manifest.json";

// XXH3-64 of a file, read 1 MiB at a time; as 16 hex digits.
std::string fileChecksum(const std::string& path, const std::string& shown) {
    refuseSpecialFile(path);
    File f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) throw InputError(shown + ": cannot read (" + std::strerror(errno) + ")");
    std::unique_ptr<XXH3_state_t, XXH_errorcode (*)(XXH3_state_t*)> state(XXH3_createState(), &XXH3_freeState);
    XXH3_64bits_reset(state.get());
    std::vector<char> buffer(1 << 20);
    size_t n;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), f.get())) > 0) XXH3_64bits_update(state.get(), buffer.data(), n);
    if (std::ferror(f.get())) throw InputError(shown + ": read failed");
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(XXH3_64bits_digest(state.get())));
    return hex;
}

void writeImage(const std::string& path, const Image& image) {
    File f(std::fopen(path.c_str(), "wb"), &std::fclose);
    const uint32_t header[3] = {image.width, image.height, image.channels};
    if (!f || std::fwrite(header, sizeof header, 1, f.get()) != 1 ||
        (!image.pixels.empty() && std::fwrite(image.pixels.data(), 1, image.pixels.size(), f.get()) != image.pixels.size()) ||
        std::fclose(f.release()) != 0)
        throw std::runtime_error(path + ": write failed (" + std::strerror(errno) + ")");
}

Image readImage(const std::string& path, const std::string& shown) {
    refuseSpecialFile(path);
    File f(std::fopen(path.c_str(), "rb"), &std::fclose);
    uint32_t header[3];
    if (!f || std::fread(header, sizeof header, 1, f.get()) != 1) throw InputError(shown + ": missing or truncated image");
    Image image{header[0], header[1], header[2], {}};
    const uint64_t bytes = uint64_t(image.width) * image.height * image.channels;
    if (image.channels < 1 || image.channels > 4 || bytes > kMaxTextureTexels * 4 || fs::file_size(path) != sizeof header + bytes)
        throw InputError(shown + ": corrupt image");
    image.pixels.resize(bytes);
    if (bytes && std::fread(image.pixels.data(), 1, bytes, f.get()) != bytes) throw InputError(shown + ": truncated image");
    return image;
}

Ordered gridJson(const GridSpec& g) {
    return {{"axis_u", g.axisU}, {"axis_v", g.axisV}, {"cells_u", g.cellsU}, {"cells_v", g.cellsV},
            {"min_u", g.minU},   {"min_v", g.minV},   {"size_u", g.sizeU},   {"size_v", g.sizeV}};
}

GridSpec gridFrom(const json& j) {
    GridSpec g;
    g.axisU = j.at("axis_u"), g.axisV = j.at("axis_v"), g.cellsU = j.at("cells_u"), g.cellsV = j.at("cells_v");
    g.minU = j.at("min_u"), g.minV = j.at("min_v"), g.sizeU = j.at("size_u"), g.sizeV = j.at("size_v");
    if (g.axisU < 0 || g.axisU > 2 || g.axisV < 0 || g.axisV > 2 || g.cellsU < 1 || g.cellsV < 1 ||
        uint64_t(g.cellsU) * g.cellsV > kMaxGridBlocks)
        throw std::runtime_error("grid out of range");
    // Corners within the coordinate limit, cells of positive size within its span.
    if (!(std::abs(g.minU) <= kMaxCoordinate && std::abs(g.minV) <= kMaxCoordinate && g.sizeU > 0 && g.sizeV > 0 &&
          g.sizeU <= 2 * kMaxCoordinate && g.sizeV <= 2 * kMaxCoordinate))
        throw std::runtime_error("grid out of range");
    return g;
}

Ordered boxJson(const Box3f& b) { return {{b.min.x, b.min.y, b.min.z}, {b.max.x, b.max.y, b.max.z}}; }
Box3f boxFrom(const json& j) {
    const Box3f b{{j.at(0).at(0), j.at(0).at(1), j.at(0).at(2)}, {j.at(1).at(0), j.at(1).at(1), j.at(1).at(2)}};
    const float lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z};
    for (int k = 0; k < 3; ++k)
        if (!(lo[k] <= hi[k] && std::abs(lo[k]) <= kMaxCoordinate && std::abs(hi[k]) <= kMaxCoordinate))
            throw std::runtime_error("bounds out of range");
    return b;
}

std::string absolute(const std::string& path) { return path.empty() ? path : fs::absolute(path).lexically_normal().string(); }

// A texture the split wrote into the work folder (a glTF's embedded image) is named relative to
// it, so the folder keeps working when renamed or moved; any other texture by its absolute path.
std::string inWork(const std::string& work, const std::string& texture) {
    const std::string a = absolute(texture), root = absolute(work) + "/";
    return a.rfind(root, 0) == 0 ? a.substr(root.size()) : a;
}


}  // namespace

bool isSplitWork(const std::string& path) {
    std::error_code ec;
    return fs::is_directory(path, ec) && fs::exists(fs::path(path) / kManifest, ec);
}

namespace {
// What a split writes: the manifest and the cells of a single mesh (cells/cell_N.piece).
bool splitWrites(const std::string& entry, bool isFolder) {
    static const std::regex cell(R"(cells/cell_[0-9]+\.piece)");
    return isFolder ? entry == "cells" : entry == kManifest || std::regex_match(entry, cell);
}
}  // namespace

SplitSummary writeSplitWork(const std::string& input, const BuildOptions& options, const std::string& work,
                            Progress& progress) {
    checkBuildOptions(options);
    const fs::path target = fs::absolute(work).lexically_normal();
    std::error_code ec;
    if (fs::exists(target, ec) && !isSplitWork(work) && !(fs::is_directory(target, ec) && fs::is_empty(target, ec)))
        throw std::invalid_argument(work + ": exists and is not an hlod split work folder (refusing to replace it)");
    if (const auto other = isSplitWork(work) ? foreignEntry(work, splitWrites) : std::nullopt)
        throw std::invalid_argument(work + ": holds " + *other + ", which hlod split does not write (refusing to replace it)");
    if (isSplitWork(input)) throw std::invalid_argument(input + ": is already a split work folder");
    const UpChoice up = chooseUpAxis(input, options.up);
    progress.message("up axis: " + up.axis + " (" + up.reason + ")");
    StagingFolder staging(target);
    const fs::path cells = fs::path(staging.path) / "cells";
    fs::create_directories(cells);
    SplitInputs in = findBlocks(input, options, cells.string(), progress);

    Ordered manifest = {{"format", kSplitFormat}, {"tool", std::string("hlod ") + HLOD_VERSION}, {"input", input}};
    manifest["up"] = {{"axis", up.axis}, {"reason", up.reason}};
    manifest["options"] = {{"block_triangles", options.blockTriangles}, {"block_size", options.blockSize},
                           {"up", options.up}, {"allow_outside_input", options.read.allowOutsideInput},
                           {"offset", options.read.offset}};
    manifest["grid"] = in.grid ? gridJson(*in.grid) : Ordered(nullptr);
    manifest["bounds"] = in.grid ? boxJson(in.bounds) : Ordered(nullptr);
    manifest["lattice"] = {{"position_bits", options.draco.positionBits}, {"position_step", in.positionStep}};
    manifest["block_count"] = in.blocks.size();
    manifest["input_triangles"] = in.inputTriangles;
    SplitSummary summary{static_cast<uint32_t>(in.blocks.size()), 0};
    progress.beginStage("checksum", in.blocks.size(), "blocks");
    Ordered blocks = Ordered::array();
    for (const BlockSource& b : in.blocks) {
        const std::string file = b.isPiece ? "cells/" + fs::path(b.file).filename().string() : absolute(b.file);
        blocks.push_back({{"file", file}, {"piece", b.isPiece}, {"triangles", b.triangles},
                          {"bytes", fs::file_size(b.file)}, {"xxh3", fileChecksum(b.file, b.file)}});
        summary.triangles += b.triangles;
        progress.advance(1);
    }
    progress.endStage();
    if (fs::is_empty(cells)) fs::remove(cells);  // a folder input: its blocks are its mesh files
    manifest["blocks"] = std::move(blocks);
    Ordered materials = Ordered::array();
    std::map<std::string, Ordered> textureFiles;  // by path: a file several materials share is read once
    for (size_t m = 0; m < in.materials.size(); ++m) {
        const Material& material = in.materials[m];
        std::string image;
        if (material.image) {
            fs::create_directories(fs::path(staging.path) / "materials");
            image = "materials/" + std::to_string(m) + ".image";
            writeImage((fs::path(staging.path) / image).string(), *material.image);
        }
        Ordered entry = {{"name", material.name},
                         {"texture", inWork(staging.path, material.texturePath)},
                         {"image", image},
                         {"uv_period", {material.uvPeriod[0], material.uvPeriod[1]}}};
        // A texture file the shards read where the split found it: checked by them (none until stop 47,
        // so shards built after it changed merged into a database of both versions).
        if (!material.texturePath.empty()) {
            auto [known, fresh] = textureFiles.try_emplace(material.texturePath);
            if (fresh) {
                std::error_code ec;
                const uint64_t bytes = fs::file_size(material.texturePath, ec);
                if (ec) throw InputError(material.texturePath + ": cannot read (" + ec.message() + ")");
                known->second = {{"bytes", bytes}, {"xxh3", fileChecksum(material.texturePath, material.texturePath)}};
            }
            entry["texture_file"] = known->second;
        }
        materials.push_back(std::move(entry));
    }
    manifest["materials"] = std::move(materials);
    Ordered problems = Ordered::array();
    for (const TextureProblem& p : in.textureProblems) problems.push_back({{"what", p.what}, {"material", p.material}});
    manifest["texture_problems"] = std::move(problems);
    {
        std::ofstream out(fs::path(staging.path) / kManifest);
        out << jsonText(manifest, 1) << "\n";
        if (!out.flush()) {
            const int error = errno;
            throw std::runtime_error(work + "/" + kManifest + ": write failed (" + std::strerror(error) + ")");
        }
    }
    staging.publish([&] {
        if (isSplitWork(work)) fs::remove_all(target);  // an earlier split of this folder
        fs::rename(staging.path, target);
    });
    return summary;
}

SplitWork openSplitWork(const std::string& work, BuildOptions& options, uint32_t first, uint32_t last) {
    const std::string file = (fs::path(work) / kManifest).string();
    json j;
    refuseSpecialFile(file);
    try {
        std::ifstream in(file);
        j = json::parse(in);
    } catch (const std::exception& e) {
        throw InputError(file + ": corrupt manifest (" + jsonProblem(e.what()) + ")");
    }
    if (!j.is_object() || !j.contains("format") || j["format"] != kSplitFormat)
        throw InputError(file + ": not a " + kSplitFormat + " manifest (split the input again with this hlod)");
    SplitWork w;
    int splitBits = 0;
    std::vector<std::pair<uint64_t, std::string>> expected;  // per block: bytes, XXH3-64
    struct TextureFile {
        std::string path;
        uint64_t bytes;
        std::string xxh3, material;
    };
    std::vector<TextureFile> textures;
    try {
        w.input = j.at("input").get<std::string>();
        w.up = {j.at("up").at("axis").get<std::string>(), j.at("up").at("reason").get<std::string>()};
        const json& o = j.at("options");
        auto adopt = [&](auto& value, const auto& split, const char* flag) {
            using T = std::remove_reference_t<decltype(value)>;
            if (value != T{} && value != split)
                throw std::invalid_argument(std::string(flag) + " differs from the split of " + work + " (give it to hlod split)");
            value = split;
        };
        adopt(options.blockTriangles, o.at("block_triangles").get<uint64_t>(), "--block-triangles");
        adopt(options.blockSize, o.at("block_size").get<double>(), "--block-size");
        adopt(options.up, o.at("up").get<std::string>(), "--up");
        adopt(options.read.offset, o.value("offset", Offset{}), "--offset");  // absent: a split before the option
        options.read.allowOutsideInput = options.read.allowOutsideInput || o.at("allow_outside_input").get<bool>();
        if (w.up.axis != "y" && w.up.axis != "z") throw std::runtime_error("up axis '" + w.up.axis + "' is neither y nor z");
        if (!options.up.empty() && options.up != "y" && options.up != "z")  // "": chosen by the input's kind
            throw std::runtime_error("--up '" + options.up + "' is neither y nor z");
        for (double v : options.read.offset)
            if (!(std::abs(v) <= kMaxCoordinate)) throw std::runtime_error("offset beyond +-1e15");
        if (!j.at("grid").is_null()) w.inputs.grid = gridFrom(j["grid"]), w.inputs.bounds = boxFrom(j.at("bounds"));
        splitBits = j.at("lattice").at("position_bits");
        if (splitBits < 1 || splitBits > kMaxPositionBits) throw std::runtime_error("position_bits out of range");
        // The lattice follows from the grid (one step for every block; none for a folder's blocks): a
        // step of 1e300 collapsed every position, 1e-300 failed in the codec (until stop 44).
        w.inputs.positionStep = j.at("lattice").at("position_step");
        if (w.inputs.positionStep != (w.inputs.grid ? gridPositionStep(w.inputs.bounds, *w.inputs.grid, splitBits) : 0.0))
            throw std::runtime_error("lattice position_step is not its grid's");
        // Files the split wrote lie in the work folder ("../" led out of it until stop 44). A texture by
        // its absolute path is where the split found it (the input may have been named relative to
        // another working directory, so its folder is not known here).
        const auto inWork = [&](const std::string& name) {
            const std::string file = (fs::path(work) / name).string();
            if (!isInsideFolder(file, work)) throw std::runtime_error("'" + name + "' is outside the work folder");
            return file;
        };
        for (const json& m : j.at("materials")) {
            const std::string texture = m.at("texture").get<std::string>();
            Material material{m.at("name").get<std::string>(),
                              texture.empty() || fs::path(texture).is_absolute() ? texture : inWork(texture), nullptr};
            const std::string image = m.at("image").get<std::string>();
            if (!image.empty()) {
                const std::string path = inWork(image);
                material.image = std::make_shared<const Image>(readImage(path, path));
            }
            for (int a = 0; a < 2; ++a) material.uvPeriod[a] = m.at("uv_period").at(a).get<float>();
            if (m.contains("texture_file") && !material.texturePath.empty())  // absent: a split before stop 47
                textures.push_back({material.texturePath, m["texture_file"].at("bytes").get<uint64_t>(),
                                    m["texture_file"].at("xxh3").get<std::string>(), material.name});
            w.inputs.materials.push_back(std::move(material));
        }
        for (const json& p : j.at("texture_problems")) w.inputs.textureProblems.push_back({p.at("what").get<std::string>(), p.at("material").get<std::string>()});
        const size_t count = j.at("block_count");
        if (count != j.at("blocks").size()) throw std::runtime_error("block_count differs from the blocks listed");
        if (j.contains("input_triangles")) {  // absent: a split before stop 46
            if (!j["input_triangles"].is_number_unsigned()) throw std::runtime_error("input_triangles is not a whole number");
            w.inputs.inputTriangles = j["input_triangles"].get<uint64_t>();
        }
        for (const json& b : j.at("blocks")) {
            const std::string name = b.at("file").get<std::string>();
            const bool piece = b.at("piece").get<bool>();
            if (piece && (name.find("..") != std::string::npos || fs::path(name).is_absolute()))
                throw std::runtime_error("cell '" + name + "' outside the work folder");
            w.inputs.blocks.push_back({piece ? (fs::path(work) / name).string() : name, piece, b.at("triangles").get<uint64_t>()});
            expected.emplace_back(b.at("bytes").get<uint64_t>(), b.at("xxh3").get<std::string>());
        }
    } catch (const std::invalid_argument&) {
        throw;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(file + ": corrupt manifest (" + jsonProblem(e.what()) + ")");
    }
    if (options.strict && !w.inputs.textureProblems.empty())
        throw InputError(w.inputs.textureProblems.front().what + " (--strict)");
    if (options.draco.positionBits != splitBits && w.inputs.grid)
        w.inputs.positionStep = gridPositionStep(w.inputs.bounds, *w.inputs.grid, options.draco.positionBits);
    // Every block file is present with its size; those this build reads also match their checksum.
    for (size_t b = 0; b < w.inputs.blocks.size(); ++b) {
        const std::string& path = w.inputs.blocks[b].file;
        std::error_code ec;
        const uint64_t bytes = fs::file_size(path, ec);
        if (ec) throw InputError(path + ": block " + std::to_string(b) + " of " + work + " is missing (split again)");
        if (bytes != expected[b].first || (b >= first && b < last && fileChecksum(path, path) != expected[b].second))
            throw InputError(path + ": block " + std::to_string(b) + " of " + work +
                             " differs from its manifest (corrupt or changed since the split; split again)");
    }
    std::set<std::string> checked;  // a file several materials share is read once
    for (const TextureFile& t : textures) {
        if (!checked.insert(t.path).second) continue;
        std::error_code ec;
        const uint64_t bytes = fs::file_size(t.path, ec);
        if (ec || bytes != t.bytes || fileChecksum(t.path, t.path) != t.xxh3)
            throw InputError(t.path + ": texture of material '" + t.material + "' of " + work +
                             (ec ? " is missing (moved or deleted since the split; split again)"
                                 : " differs from the split's (changed or corrupt since; split again)"));
    }
    return w;
}

}  // namespace hlod
