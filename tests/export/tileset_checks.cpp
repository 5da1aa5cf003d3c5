// The structural rules of the 3D Tiles validator (CesiumGS/3d-tiles-validator is not on the npm
// registry here) as checks of our own, and the GLB reader with Draco decoding they use
// (tileset_checks.h). Boxes are oriented boxes (center + three half-axes); containment is tested
// on corners and vertices in the parent box's half-axis coordinates with a relative 1e-6.
#include "tileset_checks.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

namespace hlod::test {

namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot read");
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}

struct Box {
    Eigen::Vector3d center;
    Eigen::Matrix3d axes;  // columns: half-axes
    // Coordinates of p in half-axis units (|c| <= 1 inside); degenerate axes are handled by
    // the least-squares solve: a point off a flat box's plane gets a large residual instead.
    bool contains(const Eigen::Vector3d& p, double slack) const {
        const Eigen::Vector3d d = p - center;
        const Eigen::Vector3d c = axes.completeOrthogonalDecomposition().solve(d);
        return (axes * c - d).norm() <= slack && c.cwiseAbs().maxCoeff() <= 1 + 1e-6;
    }
    std::vector<Eigen::Vector3d> corners() const {
        std::vector<Eigen::Vector3d> out;
        for (int i = 0; i < 8; ++i)
            out.push_back(center + axes.col(0) * (i & 1 ? 1 : -1) + axes.col(1) * (i & 2 ? 1 : -1) +
                          axes.col(2) * (i & 4 ? 1 : -1));
        return out;
    }
    double size() const { return axes.norm(); }
};

const std::set<std::string> kTilesetKeys = {"asset", "properties", "schema", "schemaUri", "statistics", "groups",
                                            "metadata", "geometricError", "root", "extensionsUsed",
                                            "extensionsRequired", "extensions", "extras"};
const std::set<std::string> kTileKeys = {"boundingVolume", "viewerRequestVolume", "geometricError", "refine",
                                         "transform", "content", "contents", "metadata", "implicitTiling",
                                         "children", "extensions", "extras"};

struct Checker {
    std::string folder;
    std::vector<std::string> problems;

    void fail(const std::string& where, const std::string& what) { problems.push_back(where + ": " + what); }

    bool box(const nlohmann::json& volume, const std::string& where, Box& out) {
        if (!volume.is_object() || !volume.contains("box") || !volume["box"].is_array() || volume["box"].size() != 12) {
            fail(where, "boundingVolume needs a box of 12 numbers (the only volume hlod writes)");
            return false;
        }
        double v[12];
        for (int i = 0; i < 12; ++i) {
            if (!volume["box"][i].is_number() || !std::isfinite(v[i] = volume["box"][i].get<double>())) {
                fail(where, "box holds a value that is not a finite number");
                return false;
            }
        }
        out.center = {v[0], v[1], v[2]};
        for (int a = 0; a < 3; ++a) out.axes.col(a) = Eigen::Vector3d(v[3 + 3 * a], v[4 + 3 * a], v[5 + 3 * a]);
        return true;
    }

    void content(const nlohmann::json& c, const Box& b, const std::string& where) {
        if (!c.is_object() || !c.contains("uri") || !c["uri"].is_string()) return fail(where, "content needs a uri string");
        const std::string uri = c["uri"];
        const fs::path file = (fs::path(folder) / uri).lexically_normal();
        const std::string rel = fs::relative(file, folder).generic_string();
        if (uri.find("://") != std::string::npos || rel.rfind("..", 0) == 0 || !fs::is_regular_file(file))
            return fail(where, "content uri " + uri + " does not resolve to a file inside the tileset folder");
        if (file.extension() != ".glb") return;
        const double slack = 1e-6 * b.size() + 1e-9;
        for (const DecodedPrimitive& p : decodePrimitives(readGlb(file.string()))) {
            if (!p.attributesMatch) fail(uri, "a Draco attribute id names an attribute of another type");
            if (!p.countsMatchAccessors) fail(uri, "accessor counts differ from the decoded Draco mesh");
            if (!p.minMaxMatch) fail(uri, "POSITION min/max differ from the decoded positions");
            for (const auto& v : p.positions)
                if (!b.contains({v[0], v[1], v[2]}, slack))
                    return fail(where, "content " + uri + " has a vertex outside the tile's bounding volume");
        }
    }

    void tile(const nlohmann::json& t, const std::string& where, const Box* parentBox, double parentError) {
        if (!t.is_object()) return fail(where, "a tile must be an object");
        for (const auto& [key, value] : t.items())
            if (!kTileKeys.count(key)) fail(where, "unknown tile property " + key);
        Box b;
        if (!t.contains("boundingVolume") || !box(t["boundingVolume"], where, b)) return;
        if (!t.contains("geometricError") || !t["geometricError"].is_number() || t["geometricError"].get<double>() < 0)
            return fail(where, "geometricError must be a number >= 0");
        const double error = t["geometricError"];
        if (error > parentError) fail(where, "geometricError " + std::to_string(error) + " exceeds its parent's " +
                                                 std::to_string(parentError));
        if (t.contains("refine") && t["refine"] != "ADD" && t["refine"] != "REPLACE")
            fail(where, "refine must be ADD or REPLACE");
        const bool hasTransform = t.contains("transform");
        if (hasTransform && (!t["transform"].is_array() || t["transform"].size() != 16))
            fail(where, "transform must be 16 numbers");
        // A tile's volume is in its own frame: compared with the parent's only when it adds no transform.
        if (parentBox && !hasTransform) {
            for (const Eigen::Vector3d& c : b.corners())
                if (!parentBox->contains(c, 1e-6 * parentBox->size() + 1e-9)) {
                    fail(where, "bounding volume not inside its parent's");
                    break;
                }
        }
        if (t.contains("content")) content(t["content"], b, where);
        if (t.contains("children")) {
            if (!t["children"].is_array() || t["children"].empty()) return fail(where, "children must be a non-empty array");
            for (size_t i = 0; i < t["children"].size(); ++i)
                tile(t["children"][i], where + "/" + std::to_string(i), &b, error);
        }
    }
};

}  // namespace

GlbFile readGlb(const std::string& path) {
    const std::vector<uint8_t> b = readBytes(path);
    if (b.size() < 20 || u32(b, 0) != 0x46546C67 || u32(b, 4) != 2 || u32(b, 8) != b.size())
        throw std::runtime_error(path + ": not a glTF 2.0 binary");
    GlbFile glb;
    size_t at = 12;
    while (at + 8 <= b.size()) {
        const uint32_t length = u32(b, at), type = u32(b, at + 4);
        if (at + 8 + length > b.size()) throw std::runtime_error(path + ": chunk past the end");
        if (type == 0x4E4F534A) glb.json = nlohmann::json::parse(b.begin() + long(at + 8), b.begin() + long(at + 8 + length));
        if (type == 0x004E4942) glb.bin.assign(b.begin() + long(at + 8), b.begin() + long(at + 8 + length));
        at += 8 + length;
    }
    return glb;
}

std::vector<DecodedPrimitive> decodePrimitives(const GlbFile& glb) {
    const nlohmann::json& g = glb.json;
    // glTF node matrix (column-major), then 3D Tiles' y-up to z-up: (x, y, z) -> (x, -z, y).
    Eigen::Matrix4d node = Eigen::Matrix4d::Identity();
    if (g["nodes"][0].contains("matrix"))
        for (int i = 0; i < 16; ++i) node(i % 4, i / 4) = g["nodes"][0]["matrix"][i].get<double>();
    Eigen::Matrix4d yUpToZUp = Eigen::Matrix4d::Zero();
    yUpToZUp(0, 0) = 1, yUpToZUp(1, 2) = -1, yUpToZUp(2, 1) = 1, yUpToZUp(3, 3) = 1;
    const Eigen::Matrix4d toTile = yUpToZUp * node;

    std::vector<DecodedPrimitive> out;
    for (const auto& prim : g["meshes"][0]["primitives"]) {
        const auto& ext = prim["extensions"]["KHR_draco_mesh_compression"];
        const auto& view = g["bufferViews"][ext["bufferView"].get<size_t>()];
        const size_t offset = view.value("byteOffset", size_t(0)), length = view["byteLength"];
        draco::DecoderBuffer buffer;
        buffer.Init(reinterpret_cast<const char*>(glb.bin.data() + offset), length);
        draco::Decoder decoder;
        auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
        if (!decoded.ok()) throw std::runtime_error("Draco: " + decoded.status().error_msg_string());
        const draco::Mesh& mesh = *decoded.value();
        DecodedPrimitive p;
        p.triangles = mesh.num_faces();
        p.vertices = mesh.num_points();
        using GA = draco::GeometryAttribute;
        const std::pair<const char*, GA::Type> semantics[] = {
            {"POSITION", GA::POSITION}, {"TEXCOORD_0", GA::TEX_COORD}, {"NORMAL", GA::NORMAL}, {"COLOR_0", GA::COLOR}};
        for (const auto& [name, type] : semantics) {
            if (!ext["attributes"].contains(name)) continue;
            const draco::PointAttribute* a = mesh.GetAttributeByUniqueId(ext["attributes"][name].get<uint32_t>());
            if (!a || a->attribute_type() != type) p.attributesMatch = false;
            if (g["accessors"][prim["attributes"][name].get<size_t>()]["count"] != p.vertices) p.countsMatchAccessors = false;
        }
        if (g["accessors"][prim["indices"].get<size_t>()]["count"] != uint64_t(p.triangles) * 3) p.countsMatchAccessors = false;
        const draco::PointAttribute* pos = mesh.GetAttributeByUniqueId(ext["attributes"]["POSITION"].get<uint32_t>());
        const auto& accessor = g["accessors"][prim["attributes"]["POSITION"].get<size_t>()];
        Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
        for (uint32_t i = 0; pos && i < mesh.num_points(); ++i) {
            Eigen::Vector3f v;
            pos->ConvertValue(pos->mapped_index(draco::PointIndex(i)), 3, v.data());
            lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
            const Eigen::Vector4d t = toTile * Eigen::Vector4d(v.x(), v.y(), v.z(), 1);
            p.positions.push_back({t.x(), t.y(), t.z()});
        }
        for (int c = 0; c < 3; ++c)
            if (accessor["min"][c].get<float>() != lo[c] || accessor["max"][c].get<float>() != hi[c]) p.minMaxMatch = false;
        out.push_back(std::move(p));
    }
    return out;
}

std::vector<std::string> checkTileset(const std::string& folder) {
    Checker c{folder, {}};
    nlohmann::json t;
    try {
        t = nlohmann::json::parse(readBytes(folder + "/tileset.json"));
    } catch (const std::exception& e) {
        return {std::string("tileset.json: ") + e.what()};
    }
    for (const auto& [key, value] : t.items())
        if (!kTilesetKeys.count(key)) c.fail("tileset", "unknown property " + key);
    if (!t.contains("asset") || !t["asset"].is_object() || t["asset"].value("version", "") != "1.1")
        c.fail("asset", "asset.version must be \"1.1\"");
    if (!t.contains("geometricError") || !t["geometricError"].is_number() || t["geometricError"].get<double>() < 0)
        return c.fail("tileset", "geometricError must be a number >= 0"), c.problems;
    if (!t.contains("root")) return c.fail("tileset", "no root"), c.problems;
    if (!t["root"].contains("refine")) c.fail("root", "the root tile must have refine");
    c.tile(t["root"], "root", nullptr, t["geometricError"]);
    return c.problems;
}

}  // namespace hlod::test
