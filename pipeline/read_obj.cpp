// OBJ + MTL input: many materials and texture atlases (map_Kd), as photogrammetry produces.
// The OBJ is parsed here line by line in one streaming pass into a RawMesh (v with optional
// r g b, vt, vn, f with v/vt/vn, v//vn and negative indices, polygons cut by their shape
// (polygon.h), usemtl, mtllib; a `\` at a line's end continues it), because a scan can be
// larger than memory and every number must be checked: tinyobjloader reads whole files and turns
// an unparsable number into 0. The MTL files are parsed by tinyobjloader (LoadMtl).
#include "pipeline/pipeline.h"
#include "pipeline/mtl_map.h"
#include "pipeline/polygon.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

namespace hlod {
namespace {

namespace fs = std::filesystem;

struct Line {
    const char* p;
    const char* end;
    size_t number;
};

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view token(Line& l) {
    while (l.p < l.end && blank(*l.p)) ++l.p;
    const char* start = l.p;
    while (l.p < l.end && !blank(*l.p)) ++l.p;
    return {start, static_cast<size_t>(l.p - start)};
}

std::string_view trimmed(std::string_view text) {
    while (!text.empty() && blank(text.front())) text.remove_prefix(1);
    while (!text.empty() && blank(text.back())) text.remove_suffix(1);
    return text;
}

// The rest of the line after the tokens read so far, without its surrounding blanks.
std::string_view rest(const Line& l) { return trimmed({l.p, static_cast<size_t>(l.end - l.p)}); }

// Where a line that goes on on the next one ends: the OBJ specification's `\` at its end (after
// blanks). Not a line holding `#`: a comment, whole or after the data, may end in a Windows
// folder, and joining would swallow the next line. npos for any other line.
size_t continuation(std::string_view text) {
    const std::string_view t = trimmed(text);
    if (t.empty() || t.back() != '\\' || t.find('#') != std::string_view::npos) return std::string_view::npos;
    return static_cast<size_t>(t.data() + t.size() - 1 - text.data());
}

// A UTF-8 byte order mark, which Windows tools may write before an OBJ's or MTL's first keyword
// (it would hide that line: an OBJ's first `mtllib`, an MTL's first `newmtl`).
constexpr char kByteOrderMark[3] = {'\xEF', '\xBB', '\xBF'};
// The largest |scale| or |offset| of `map_Kd -s`/`-o` taken: a float texcoord near 1,000 still
// tells a 4K texture's quarter-texels apart (its step 6e-5); beyond, the material is untextured.
constexpr double kMaxUvMove = 1000;

void skipByteOrderMark(std::istream& in) {
    char head[3] = {};
    if (!in.read(head, 3) || std::memcmp(head, kByteOrderMark, 3) != 0) {
        in.clear();
        in.seekg(0);
    }
}

class ObjParser {
public:
    ObjParser(const std::string& path, RawMesh& raw, const ReadOptions& options)
        : path_(path), folder_(folderOf(path)), raw_(raw), options_(options) {}

    void parse() {
        refuseSpecialFile(path_);
        std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path_.c_str(), "rb"), &std::fclose);
        if (!f) throw InputError(path_ + ": cannot open (" + std::strerror(errno) + ")");
        std::vector<char> buffer(readBufferBytes(f.get()));
        std::string carry;
        size_t number = 0, n = 0, joined = std::string::npos;  // joined: carry's size after a `\` joined a line
        bool first = true;
        while ((n = std::fread(buffer.data(), 1, buffer.size(), f.get())) > 0) {
            if (raw_.progress) raw_.progress->advance(n);
            const char* p = buffer.data();
            const char* end = p + n;
            if (std::exchange(first, false) && n >= 3 && std::memcmp(p, kByteOrderMark, 3) == 0) p += 3;
            while (const char* nl = static_cast<const char*>(std::memchr(p, '\n', end - p))) {
                if (!carry.empty()) carry.append(p, nl);
                const std::string_view text = carry.empty() ? std::string_view(p, nl - p) : std::string_view(carry);
                ++number;
                if (const size_t cut = continuation(text); cut != std::string_view::npos) {
                    if (carry.empty()) carry.assign(p, cut);
                    else carry.resize(cut);  // text is carry
                    carry.push_back(' ');
                    joined = carry.size();
                } else {
                    line({text.data(), text.data() + text.size(), number});
                    carry.clear();
                }
                p = nl + 1;
            }
            carry.append(p, end);
        }
        if (std::ferror(f.get())) throw InputError(path_ + ": read error (" + std::strerror(errno) + ")");
        lastLine_ = true;
        if (const size_t cut = continuation(carry); cut != std::string_view::npos) carry.resize(cut);
        // The last line: after the last newline, or (nothing after it) the one a final `\` continued.
        if (!carry.empty()) line({carry.data(), carry.data() + carry.size(), carry.size() == joined ? number : ++number});
        checkAhead();
        warnUnknown();
        raw_.hasTexcoords = anyFaceHasTexcoords_ && raw_.texcoords.size() > 0;
        if (raw_.hasTexcoords) unmappedTextures();
        raw_.hasNormals = everyFaceHasNormals_ && raw_.normals.size() > 0;
        raw_.materials.push_back({"default", "", nullptr});
    }

private:
    [[noreturn]] void corrupt(const Line& l, const std::string& what) const {
        throw InputError(path_ + ":" + std::to_string(l.number) + ": " + (lastLine_ ? "truncated or corrupt" : "corrupt") +
                         " OBJ (" + what + ")");
    }

    template <class T = float>
    T number(Line& l, bool required, T fallback = 0) {
        const std::string_view t = token(l);
        if (t.empty()) {
            if (required) corrupt(l, "missing number");
            return fallback;
        }
        const char* begin = t.data() + (t.front() == '+' ? 1 : 0);
        T v = 0;
        auto [end, ec] = std::from_chars(begin, t.data() + t.size(), v);
        if constexpr (std::is_floating_point_v<T>) {
            // 7.5e-53 is a number below float's range: 0, as strtof reads it ("bad number" until stop 45)
            if (ec == std::errc::result_out_of_range && std::abs(std::strtold(std::string(begin, end).c_str(), nullptr)) < 1)
                v = 0, ec = std::errc();
        }
        if (ec != std::errc() || end != t.data() + t.size()) corrupt(l, "bad number '" + shownBytes(t) + "'");
        return v;
    }

    // One index of a face corner: 1-based, or negative = relative to the elements so far. `kind`:
    // 0 vertex, 1 texture coordinate, 2 normal.
    uint32_t index(const Line& l, std::string_view t, size_t count, int kind) {
        long long v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || end != t.data() + t.size() || v == 0) corrupt(l, "bad face index '" + shownBytes(t) + "'");
        const long long resolved = v > 0 ? v - 1 : static_cast<long long>(count) + v;
        if (resolved < 0 || resolved >= 0xFFFFFFFFll) corrupt(l, "face index " + std::to_string(v) + " out of range");
        Ahead& a = ahead_[kind];
        if (static_cast<size_t>(resolved) >= count && (a.line == 0 || resolved > a.index)) a = {resolved, l.number};
        return static_cast<uint32_t>(resolved);
    }

    // A face may name an element defined further down; the largest such index must exist at the end
    // (until stop 46 a later check named the fanned triangle and a 0-based vertex, without the line).
    void checkAhead() const {
        const size_t counts[3] = {raw_.positionCount(), raw_.texcoords.size() / 2, raw_.normals.size() / 3};
        static constexpr const char* kNames[3] = {"vertices", "texture coordinates", "normals"};
        for (int k = 0; k < 3; ++k)
            if (ahead_[k].line && static_cast<size_t>(ahead_[k].index) >= counts[k])
                throw InputError(path_ + ":" + std::to_string(ahead_[k].line) + ": face index " + std::to_string(ahead_[k].index + 1) +
                                 " names one of " + std::to_string(counts[k]) + " " + kNames[k]);
    }

    void face(Line& l) {
        corners_.clear();
        for (std::string_view c = token(l); !c.empty(); c = token(l)) {
            const size_t s1 = c.find('/'), s2 = s1 == c.npos ? c.npos : c.find('/', s1 + 1);
            Corner corner;
            corner.p = index(l, c.substr(0, s1), raw_.positionCount(), 0);
            const std::string_view vt = s1 == c.npos ? std::string_view() : c.substr(s1 + 1, s2 == c.npos ? c.npos : s2 - s1 - 1);
            const std::string_view vn = s2 == c.npos ? std::string_view() : c.substr(s2 + 1);
            if (vt.empty()) corner.t = kNone, withoutTexcoords_.insert(material_);
            else corner.t = index(l, vt, raw_.texcoords.size() / 2, 1), anyFaceHasTexcoords_ = true;
            if (vn.empty()) everyFaceHasNormals_ = false;
            else corner.n = index(l, vn, raw_.normals.size() / 3, 2);
            corners_.push_back(corner);
        }
        if (corners_.size() < 3) corrupt(l, "face with fewer than 3 vertices");
        // A polygon's positions, when read already (a face may name later vertices: fanned), cut it
        // by its shape (polygon.h); a triangle is itself.
        bool known = corners_.size() > 3;
        for (const Corner& c : corners_) known = known && c.p < raw_.positionCount();
        triangles_.clear();
        if (known) {
            points_.resize(corners_.size());
            for (size_t i = 0; i < corners_.size(); ++i) {
                float xyz[3];
                raw_.positions.read(3 * size_t(corners_[i].p), 3, xyz);
                points_[i] = {xyz[0], xyz[1], xyz[2]};
            }
            triangulatePolygon(points_, triangles_);
        } else {
            for (uint32_t k = 2; k < corners_.size(); ++k) triangles_.push_back({0, k - 1, k});
        }
        for (const auto& [a, b, c] : triangles_) {
            const Corner &x = corners_[a], &y = corners_[b], &z = corners_[c];
            raw_.addTriangle({{x.p, y.p, z.p}, {x.t, y.t, z.t}, {x.n, y.n, z.n}, material_});
        }
    }

    // `mtllib A B`: libraries A and B, or the one library `A B` when only that file exists (a
    // name with a space, as exporters write it unescaped).
    void materialLibrary(Line& l) {
        const std::string whole(rest(l));
        std::error_code error;
        if (whole.find_first_of(" \t") != std::string::npos && fs::is_regular_file(fs::path(folder_) / whole, error))
            return loadLibrary(whole);
        for (std::string_view name = token(l); !name.empty(); name = token(l)) loadLibrary(name);
    }

    void loadLibrary(std::string_view name) {
        const std::string file = resolveReference(path_, folder_, std::string(name), "material library", options_);
        std::error_code statusError;
        const std::filesystem::file_status status = std::filesystem::status(file, statusError);
        std::ifstream in;
        if (std::filesystem::is_regular_file(status)) in.open(file);
        if (!in.is_open()) {  // its materials are then defined nowhere: each `usemtl` of one says so (textures rule)
            raw_.stats.warnings.push_back(path_ + ": material library '" + std::string(name) + "' " +
                                          (!std::filesystem::exists(status) ? "not found"
                                           : std::filesystem::is_regular_file(status) ? "cannot be read"
                                                                                      : "is not a regular file"));
            return;
        }
        skipByteOrderMark(in);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::istringstream mtl(text);
        std::map<std::string, int> ids;
        std::vector<tinyobj::material_t> materials;
        std::string warning, error;
        tinyobj::LoadMtl(&ids, &materials, &mtl, &warning, &error);
        // map_Kd read by mtl_map.h: tinyobjloader took the file of `map_Kd -o 0 0.25 a.png` for a
        // third number (the material untextured without a word until stop 47).
        const std::map<std::string, DiffuseMap> maps = diffuseMaps(text);
        for (const tinyobj::material_t& m : materials) {
            const std::string name(trimmed(m.name));
            const auto it = maps.find(name);
            // A statement tinyobjloader read where mtl_map.h found none (lines it reads otherwise): its reading.
            DiffuseMap map = it == maps.end() ? DiffuseMap{m.diffuse_texname} : it->second;
            if (it == maps.end()) {
                map.clamp = m.diffuse_texopt.clamp;
                std::copy_n(m.diffuse_texopt.scale, 3, map.scale), std::copy_n(m.diffuse_texopt.origin_offset, 3, map.offset);
            }
            byName_[name] = static_cast<uint32_t>(raw_.materials.size());
            raw_.materials.push_back({m.name, map.file.empty() ? "" : resolveReference(path_, folder_, map.file, "texture", options_), nullptr});
            if (map.clamp) raw_.materials.back().uvPeriod[0] = raw_.materials.back().uvPeriod[1] = 0;  // map_Kd -clamp on
            if (it != maps.end() && map.file.empty())  // options alone: the textures rule, not an untextured material without a word
                raw_.stats.textureProblems.push_back({file + ": material '" + m.name + "': map_Kd names no texture file", m.name});
            if (!map.file.empty()) moveUvs(file, m.name, map);
        }
    }

    // `map_Kd -s su sv -o ou ov`: the texture looked up at (u su + ou, v sv + ov) (the MTL
    // specification's "scales the size of the texture pattern" and "offset the position of the map
    // origin", as three.js's MTLLoader reads them: its texture repeat and offset); warned of and
    // not applied until stop 51. In the v-down texcoords (v' = 1 - v): v' sv + (1 - sv - ov). A
    // number written that is not finite or beyond kMaxUvMove leaves the material untextured.
    void moveUvs(const std::string& file, const std::string& name, const DiffuseMap& map) {
        Material& material = raw_.materials.back();
        for (int a = 0; a < 2; ++a)  // the numbers as written, both axes before any is taken
            if (!(std::abs(map.scale[a]) <= kMaxUvMove) || !(std::abs(map.offset[a]) <= kMaxUvMove)) {
                raw_.stats.textureProblems.push_back({file + ": material '" + name + "': map_Kd -s/-o beyond ±" +
                                                          std::to_string(int(kMaxUvMove)) + " or not a number", name});
                material.texturePath.clear();
                return;
            }
        material.uvScale[0] = static_cast<float>(map.scale[0]), material.uvOffset[0] = static_cast<float>(map.offset[0]);
        material.uvScale[1] = static_cast<float>(map.scale[1]), material.uvOffset[1] = static_cast<float>(1 - map.scale[1] - map.offset[1]);
    }

    // "v x y z r g b": the vertex colours MeshLab and many scanners write (0..1, clamped), kept
    // while every vertex has them (the first vertex without leaves the colours short, and a mesh
    // whose colours do not match its vertices is read without them, as a PLY's).
    void vertexColor(Line& l) {
        Line after = l;
        const bool three = !token(after).empty() && !token(after).empty() && !token(after).empty() && token(after).empty();
        everyVertexHasColor_ = everyVertexHasColor_ && three;
        if (!everyVertexHasColor_) return;
        uint8_t rgba[4] = {0, 0, 0, 255};
        for (int c = 0; c < 3; ++c) {
            const float v = number(l, true);
            if (!std::isfinite(v)) corrupt(l, "a vertex colour is not a number");
            rgba[c] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        }
        raw_.colors.push(rgba, 4);
    }

    void line(Line l) {
        const std::string_view keyword = token(l);
        if (keyword == "v") {
            // Parsed as floats when nothing is subtracted (the bytes of every earlier build), else as doubles.
            const bool offset = raw_.offset != std::array<double, 3>{};
            double p[3];
            for (double& c : p) c = offset ? number<double>(l, true) : number(l, true);
            raw_.addPosition(p, path_);
            vertexColor(l);
        } else if (keyword == "vt") {
            const float u = number(l, true), v = number(l, false);
            raw_.addTexcoord(u, 1.0f - v, path_);
        } else if (keyword == "vn") {
            const float x = number(l, true), y = number(l, true), z = number(l, true);
            const float n[3] = {x, y, z};
            raw_.addNormal(n, path_);
        } else if (keyword == "f") {
            face(l);
        } else if (keyword == "usemtl") {
            // The rest of the line, as tinyobjloader reads `newmtl` (a name may hold spaces), else its first word.
            const std::string whole(rest(l)), name = byName_.count(whole) ? whole : std::string(token(l));
            const auto it = byName_.find(name);
            material_ = it == byName_.end() ? kNone : it->second;
            // A material no library defines is unusable like a missing texture (README "Textures: one
            // rule"): its faces are untextured, said once per name, fatal with --strict.
            if (it == byName_.end() && undefined_.insert(name).second)
                raw_.stats.textureProblems.push_back(
                    {path_ + ":" + std::to_string(l.number) + ": material '" + name + "' is defined in no material library", name});
        } else if (keyword == "mtllib") {
            materialLibrary(l);
        } else if (!keyword.empty() && keyword[0] != '#' && !kIgnored.count(keyword) && unknown_.count++ == 0) {
            unknown_.line = l.number, unknown_.keyword = shownBytes(keyword);
        }
    }

    // The statements of the OBJ specification hlod does not draw (groups, smoothing, free-form
    // geometry, points and lines, display attributes): skipped as the specification allows. Any
    // other first word is counted and said once (skipped without a word until stop 46: an `F` line
    // lost its face).
    static inline const std::set<std::string_view> kIgnored = {
        "o",     "g",    "s",     "vp",    "l",     "p",      "cstype",   "deg",      "bmat",       "step",      "curv",  "curv2",
        "surf",  "parm", "trim",  "hole",  "scrv",  "sp",     "end",      "con",      "mg",         "lod",       "usemap", "maplib",
        "bevel", "c_interp", "d_interp", "shadow_obj", "trace_obj", "ctech", "stech", "call", "csh"};
    struct Unknown {
        uint64_t count = 0;
        size_t line = 0;
        std::string keyword;
    } unknown_;

    // A face without `vt` reads texcoord (0, 0) (rawCorners): harmless in an untextured material; a
    // textured one cannot be mapped, the textures rule. Until stop 51 one such face anywhere (an
    // untextured part of a photogrammetry export) left every material of the file untextured.
    void unmappedTextures() {
        for (const uint32_t m : withoutTexcoords_) {
            if (m == kNone || raw_.materials[m].texturePath.empty()) continue;
            raw_.stats.textureProblems.push_back({path_ + ": texture '" + raw_.materials[m].texturePath +
                                                      "' cannot be mapped: not every face of material '" + raw_.materials[m].name +
                                                      "' has texture coordinates",
                                                  raw_.materials[m].name});
            raw_.materials[m].texturePath.clear();
        }
    }

    void warnUnknown() {
        if (unknown_.count)
            raw_.stats.warnings.push_back(path_ + ":" + std::to_string(unknown_.line) + ": " + std::to_string(unknown_.count) +
                                          " lines skipped whose first word is no OBJ statement (the first: '" + unknown_.keyword + "')");
    }

    const std::string& path_;
    const std::string folder_;
    RawMesh& raw_;
    const ReadOptions& options_;
    std::map<std::string, uint32_t> byName_;
    std::set<std::string> undefined_;  // names of `usemtl` lines no library defines, reported once
    struct Ahead {
        long long index = 0;  // 0-based
        size_t line = 0;      // 0: none
    };
    Ahead ahead_[3];  // vertex, texture coordinate, normal
    struct Corner {
        uint32_t p = 0, t = 0, n = 0;
    };
    std::vector<Corner> corners_;  // of the face being read, and its triangles (reused)
    std::vector<std::array<double, 3>> points_;
    std::vector<std::array<uint32_t, 3>> triangles_;
    uint32_t material_ = kNone;
    std::set<uint32_t> withoutTexcoords_;  // the materials of faces without `vt` (kNone: the default)
    bool anyFaceHasTexcoords_ = false, everyFaceHasNormals_ = true, everyVertexHasColor_ = true, lastLine_ = false;
};

}  // namespace

void parseObj(const std::string& path, RawMesh& raw, const ReadOptions& options) {
    raw.offset = options.offset;
    ObjParser(path, raw, options).parse();
    raw.seal();
}

SourceMesh readObj(const std::string& path, const ReadOptions& options) {
    RawMesh raw;
    parseObj(path, raw, options);
    return toSourceMesh(raw, path);
}

}  // namespace hlod
