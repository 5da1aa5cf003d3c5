// Per-level summary, node detail and tree views of a database (`hlod inspect`, `hlod stats`).
// Node attributes are those of thesis §3.3 plus the FORMAT.md extensions.
#include "formats/inspect.h"

#include <algorithm>

namespace hlod {

namespace {

nlohmann::json vec(const Vec3f& v) { return {v.x, v.y, v.z}; }

const char* codecName(Codec c) { return c == Codec::Draco ? "draco" : c == Codec::Jpeg ? "jpeg" : c == Codec::Png ? "png" : "?"; }

constexpr uint32_t kMaxTreeDepth = 256;

// `shown` marks printed nodes: each node appears once even when corrupt links share or cycle.
nlohmann::json treeNode(const Skeleton& s, uint32_t id, uint32_t depth, uint32_t maxDepth, std::vector<uint8_t>& shown) {
    shown[id] = 1;
    const Node& n = s.nodes[id];
    nlohmann::json j = {{"id", id},          {"level", n.level},        {"block", n.block},
                        {"triangles", n.triangles()}, {"texels", n.texelCount}, {"bytes", n.dataSize},
                        {"error", n.geometricError}};
    const std::vector<uint32_t> children = s.children(id);
    if (depth >= kMaxTreeDepth) j["truncated"] = true;  // only corrupt links nest this deep
    if (depth >= kMaxTreeDepth || (maxDepth != 0 && depth + 1 >= maxDepth)) {
        // Below the cut: no "children" key (an empty list would read as a leaf), only their count.
        if (!children.empty()) j["children_not_shown"] = children.size();
        else j["children"] = nlohmann::json::array();
        return j;
    }
    nlohmann::json kids = nlohmann::json::array();
    for (uint32_t c : children)
        if (!shown[c]) kids.push_back(treeNode(s, c, depth + 1, maxDepth, shown));
    j["children"] = kids;
    return j;
}

}  // namespace

DatabaseSummary summarize(const Database& db) {
    const Skeleton& s = db.skeleton();
    DatabaseSummary out;
    out.path = db.path();
    out.major = s.major;
    out.minor = s.minor;
    out.fileSize = db.fileSize();
    out.nodes = s.nodes.size();
    out.blobs = s.blobs.size();
    out.blocks = s.blockCount;
    for (const Node& n : s.nodes) {
        if (n.level >= out.levels.size()) {
            if (n.level > s.nodes.size()) continue;  // absurd level: reported by validate
            out.levels.resize(n.level + 1);
            for (uint32_t l = 0; l <= n.level; ++l) out.levels[l].level = l;
        }
        LevelSummary& L = out.levels[n.level];
        L.minGeometricError = L.nodes ? std::min(L.minGeometricError, n.geometricError) : n.geometricError;
        L.maxGeometricError = L.nodes ? std::max(L.maxGeometricError, n.geometricError) : n.geometricError;
        ++L.nodes;
        L.texturedTriangles += n.texturedTriangles;
        L.untexturedTriangles += n.untexturedTriangles;
        L.vertices += n.vertexCount;
        L.texels += n.texelCount;
        L.cost += n.cost;
        L.blobs += n.blobCount;
        for (uint32_t b = n.firstBlob; b < n.firstBlob + n.blobCount; ++b)
            (s.blobs[b].kind == BlobKind::Texture ? L.textureBytes : L.geometryBytes) += s.blobs[b].size;
    }
    // Longest root-to-leaf path, walking parents (bounded by the node count).
    for (const Node& n : s.nodes) {
        if (n.firstChild != kNone) continue;
        uint32_t d = 1;
        for (uint32_t p = n.parent; p != kNone && d <= s.nodes.size(); p = s.nodes[p].parent) ++d;
        out.depth = std::max(out.depth, d);
    }
    for (const auto& kv : s.meta) (kv.first.rfind("c_", 0) == 0 ? out.constants : out.provenance).push_back(kv);
    return out;
}

nlohmann::json toJson(const DatabaseSummary& s) {
    nlohmann::json levels = nlohmann::json::array();
    for (const LevelSummary& L : s.levels)
        levels.push_back({{"level", L.level},
                          {"nodes", L.nodes},
                          {"textured_triangles", L.texturedTriangles},
                          {"untextured_triangles", L.untexturedTriangles},
                          {"vertices", L.vertices},
                          {"texels", L.texels},
                          {"geometry_bytes", L.geometryBytes},
                          {"texture_bytes", L.textureBytes},
                          {"blobs", L.blobs},
                          {"cost", L.cost},
                          {"geometric_error", {L.minGeometricError, L.maxGeometricError}}});
    nlohmann::json constants = nlohmann::json::object(), provenance = nlohmann::json::object();
    for (const auto& [k, v] : s.constants) constants[k] = v;
    for (const auto& [k, v] : s.provenance) provenance[k] = v;
    return {{"path", s.path},
            {"version", std::to_string(s.major) + "." + std::to_string(s.minor)},
            {"file_size", s.fileSize},
            {"nodes", s.nodes},
            {"blobs", s.blobs},
            {"blocks", s.blocks},
            {"levels", s.levels.size()},
            {"depth", s.depth},
            {"per_level", levels},
            {"constants", constants},
            {"provenance", provenance}};
}

nlohmann::json nodeJson(const Skeleton& s, uint32_t id) {
    if (id >= s.nodes.size()) throw std::invalid_argument("node " + std::to_string(id) + " does not exist (the database has " +
                                                      std::to_string(s.nodes.size()) + " nodes)");
    const Node& n = s.nodes[id];
    auto link = [](uint32_t v) { return v == kNone ? nlohmann::json(nullptr) : nlohmann::json(v); };
    nlohmann::json blobs = nlohmann::json::array();
    for (uint32_t i = n.firstBlob; i < n.firstBlob + n.blobCount; ++i) {
        const BlobRef& b = s.blobs[i];
        nlohmann::json j = {{"index", i}, {"kind", b.kind == BlobKind::Texture ? "texture" : "geometry"},
                            {"codec", codecName(b.codec)}, {"offset", b.offset}, {"size", b.size},
                            {"checksum", b.checksum}};
        if (b.kind == BlobKind::Geometry) {
            j.update({{"triangles", b.triangles}, {"vertices", b.vertices}, {"texture", link(b.texture)},
                      {"attributes", {{"position", bool(b.attributes & kAttrPosition)},
                                      {"texcoord", bool(b.attributes & kAttrTexcoord)},
                                      {"normal", bool(b.attributes & kAttrNormal)},
                                      {"color", bool(b.attributes & kAttrColor)}}},
                      {"quantization_bits", {{"position", b.positionBits}, {"texcoord", b.texcoordBits},
                                            {"normal", b.normalBits}, {"color", b.colorBits}}}});
        } else {
            j.update({{"width", b.width}, {"height", b.height}, {"channels", b.channels}});
        }
        blobs.push_back(j);
    }
    return {{"id", n.id},
            {"parent", link(n.parent)},
            {"first_child", link(n.firstChild)},
            {"next_sibling", link(n.nextSibling)},
            {"children", s.children(id)},
            {"level", n.level},
            {"block", n.block},
            {"bounds", {{"min", vec(n.bounds.min)}, {"max", vec(n.bounds.max)}}},
            {"cost", n.cost},
            {"static_benefit", n.staticBenefit},
            {"avg_normal", vec(n.avgNormal)},
            {"geometric_error", n.geometricError},
            {"textured_triangles", n.texturedTriangles},
            {"untextured_triangles", n.untexturedTriangles},
            {"vertex_count", n.vertexCount},
            {"texel_count", n.texelCount},
            {"data_offset", n.dataOffset},
            {"data_size", n.dataSize},
            {"blobs", blobs}};
}

nlohmann::json treeJson(const Skeleton& s, uint32_t maxDepth) {
    nlohmann::json roots = nlohmann::json::array();
    std::vector<uint8_t> shown(s.nodes.size(), 0);
    for (uint32_t r : s.roots())
        if (!shown[r]) roots.push_back(treeNode(s, r, 0, maxDepth, shown));
    return roots;
}

}  // namespace hlod
