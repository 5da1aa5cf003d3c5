// `hlod validate`: checks every invariant of FORMAT.md §Invariants and reports each violation:
// one tree per block (thesis §3.3 first-child/next-sibling links), level = parent level + 1,
// children's bounds inside the parent's, cost = eq. 3.1, counts = the blobs' counts, blobs
// tiling the data area, geometric error non-increasing, and (unless quick) every blob
// checksum-correct and decodable with the counts its record claims.
#include "formats/validate.h"

#include "formats/codec.h"
#include "formats/constants.h"
#include "formats/layout.h"
#include "formats/offset.h"
#include "formats/up_axis.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>
#include <sstream>

namespace hlod {

namespace {

struct Report {
    std::vector<Violation>& out;
    void add(uint32_t node, const std::string& message) {
        out.push_back({node, (node == kNone ? "" : "node " + std::to_string(node) + ": ") + message});
    }
};

bool finite(const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double diagonal(const Box3f& b) {
    double dx = b.max.x - b.min.x, dy = b.max.y - b.min.y, dz = b.max.z - b.min.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

bool inside(const Box3f& c, const Box3f& p, double relTol) {
    double mag = std::max({std::abs(p.min.x), std::abs(p.min.y), std::abs(p.min.z), std::abs(p.max.x),
                           std::abs(p.max.y), std::abs(p.max.z)});
    double tol = relTol * diagonal(p) + 4 * FLT_EPSILON * mag;
    return c.min.x >= p.min.x - tol && c.min.y >= p.min.y - tol && c.min.z >= p.min.z - tol &&
           c.max.x <= p.max.x + tol && c.max.y <= p.max.y + tol && c.max.z <= p.max.z + tol;
}

void checkNode(const Skeleton& s, const Node& nd, const ValidateOptions& o, double cTextured, Report& r) {
    const uint32_t id = nd.id;
    if (!finite(nd.bounds.min) || !finite(nd.bounds.max) || nd.bounds.min.x > nd.bounds.max.x ||
        nd.bounds.min.y > nd.bounds.max.y || nd.bounds.min.z > nd.bounds.max.z)
        r.add(id, "bounding box is not finite or has min > max");
    if (!std::isfinite(nd.staticBenefit) || nd.staticBenefit < 0) r.add(id, "static benefit is not a finite number >= 0");
    double len = std::sqrt(double(nd.avgNormal.x) * nd.avgNormal.x + double(nd.avgNormal.y) * nd.avgNormal.y +
                           double(nd.avgNormal.z) * nd.avgNormal.z);
    if (!finite(nd.avgNormal) || (len != 0 && std::abs(len - 1) > 1e-3)) r.add(id, "average normal is neither unit nor zero");
    if (!std::isfinite(nd.geometricError) || nd.geometricError < 0) r.add(id, "geometric error is not a finite number >= 0");
    double expected = nodeCost(nd.texturedTriangles, nd.untexturedTriangles, cTextured);
    if (!(std::abs(nd.cost - expected) <= 1e-4 * std::max(1.0, expected))) {
        std::ostringstream m;
        m << "cost " << nd.cost << " differs from eq. 3.1 (" << expected << " with c_textured=" << cTextured << ")";
        r.add(id, m.str());
    }
    if (nd.parent == kNone) return;  // links, levels and blocks: checkTree
    const Node& p = s.nodes[nd.parent];
    if (!inside(nd.bounds, p.bounds, o.boundsTolerance)) r.add(id, "bounding box is not inside its parent's");
    if (nd.geometricError > p.geometricError)
        r.add(id, "geometric error " + std::to_string(nd.geometricError) + " exceeds its parent's " +
                      std::to_string(p.geometricError));
}

// The node's counts must be the sums over its blobs, its blobs must tile its data range, and
// a geometry blob may only sample a texture of the same node.
void checkCounts(const Skeleton& s, const Node& nd, Report& r) {
    uint64_t textured = 0, untextured = 0, vertices = 0, texels = 0, pos = nd.dataOffset;
    for (uint32_t i = nd.firstBlob; i < nd.firstBlob + nd.blobCount; ++i) {
        const BlobRef& b = s.blobs[i];
        if (b.offset != pos) r.add(nd.id, "blob " + std::to_string(i) + " does not follow the previous blob");
        pos = b.offset + b.size;
        if (b.kind == BlobKind::Texture) texels += uint64_t(b.width) * b.height;
        else (b.texture == kNone ? untextured : textured) += b.triangles;
        if (b.kind == BlobKind::Geometry) vertices += b.vertices;
        if (b.kind == BlobKind::Geometry && b.positionBits > kMaxDecodablePositionBits)  // FORMAT.md "Position lattice"
            r.add(nd.id, "blob " + std::to_string(i) + " claims " + std::to_string(b.positionBits) +
                             "-bit positions (at most " + std::to_string(kMaxDecodablePositionBits) + ")");
        if (b.texture != kNone && s.blobs[b.texture].node != nd.id)
            r.add(nd.id, "blob " + std::to_string(i) + " samples a texture of another node");
    }
    if (pos != nd.dataOffset + nd.dataSize) r.add(nd.id, "data size does not equal the sum of its blob sizes");
    if (textured != nd.texturedTriangles || untextured != nd.untexturedTriangles || vertices != nd.vertexCount ||
        texels != nd.texelCount)
        r.add(nd.id, "triangle/vertex/texel counts differ from the sums over its blobs");
}

// Every byte between the header and the skeleton belongs to exactly one blob.
void checkCoverage(const Database& db, Report& r) {
    std::vector<uint8_t> head(std::min<uint64_t>(db.fileSize(), layout::kMaxHeaderSize));
    db.readRange(0, head);
    layout::HeaderInfo h = layout::parseHeader(head, db.fileSize(), db.path());
    std::vector<std::pair<uint64_t, uint64_t>> ranges;
    for (const BlobRef& b : db.skeleton().blobs) ranges.emplace_back(b.offset, b.size);
    std::sort(ranges.begin(), ranges.end());
    uint64_t pos = h.headerSize;
    for (const auto& [offset, size] : ranges) {
        if (offset != pos)
            r.add(kNone, (offset > pos ? "bytes " + std::to_string(pos) + ".." + std::to_string(offset) +
                                             " belong to no blob"
                                       : "blobs overlap at byte " + std::to_string(offset)));
        pos = std::max(pos, offset + size);
    }
    if (pos < h.skeletonOffset)
        r.add(kNone, "bytes " + std::to_string(pos) + ".." + std::to_string(h.skeletonOffset) + " belong to no blob");
    if (pos > h.skeletonOffset) r.add(kNone, "blobs overlap the skeleton");
}

void checkBlobData(const Database& db, uint32_t i, Report& r) {
    const BlobRef& b = db.skeleton().blobs[i];
    const std::string name = "blob " + std::to_string(i);
    try {
        std::vector<uint8_t> bytes = db.readBlob(i);
        if (b.kind == BlobKind::Geometry) {
            MeshData m = decodeGeometry(bytes, name);
            if (m.triangleCount() != b.triangles || m.vertexCount() != b.vertices)
                r.add(b.node, name + " decodes to " + std::to_string(m.triangleCount()) + " triangles and " +
                                  std::to_string(m.vertexCount()) + " vertices, its record claims " +
                                  std::to_string(b.triangles) + " and " + std::to_string(b.vertices));
            if (b.texture != kNone && m.texcoords.empty()) r.add(b.node, name + " is textured but has no texture coordinates");
            const uint8_t mask = kAttrPosition | (m.texcoords.empty() ? 0 : kAttrTexcoord) |
                                 (m.normals.empty() ? 0 : kAttrNormal) | (m.colors.empty() ? 0 : kAttrColor);
            if (mask != b.attributes)
                r.add(b.node, name + " decodes to attribute mask " + std::to_string(mask) + ", its record claims " +
                                  std::to_string(b.attributes));
        } else {
            Image img = decodeTexture(bytes, b.codec, name);
            if (img.width != b.width || img.height != b.height || img.channels != b.channels)
                r.add(b.node, name + " decodes to " + std::to_string(img.width) + "x" + std::to_string(img.height) + "x" +
                                  std::to_string(img.channels) + ", its record claims " + std::to_string(b.width) +
                                  "x" + std::to_string(b.height) + "x" + std::to_string(b.channels));
        }
    } catch (const FormatError& e) {
        std::string what = e.what();
        const std::string prefix = db.path() + ": ";
        r.add(b.node, what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
    }
}

}  // namespace

std::vector<Violation> validate(const Database& db, const ValidateOptions& o) {
    std::vector<Violation> out;
    Report r{out};
    const Skeleton& s = db.skeleton();
    double cTextured = o.cTextured;
    if (cTextured < 0) {
        const std::string* meta = s.findMeta("c_textured");
        cTextured = Constants{}.textured;
        if (meta) {
            try {
                cTextured = std::stod(*meta);
                if (!(cTextured > 0 && cTextured <= 1))  // what every player refuses ("valid" until stop 45)
                    r.add(kNone, "metadata c_textured='" + *meta + "' is not in (0, 1]");
            } catch (const std::exception&) {
                r.add(kNone, "metadata c_textured='" + *meta + "' is not a number");
            }
        }
    }
    for (const char* key : {"c_desiredTris", "c_levelFactor"})  // `hlod stats` reads them ("valid" until stop 49)
        if (const std::string* meta = s.findMeta(key)) try {
                Constants c;
                setConstant(c, key, *meta);
                validateConstants(c, kUsedByBuild);
            } catch (const std::invalid_argument& e) {
                r.add(kNone, std::string("metadata ") + e.what());
            }
    const auto readable = [&](const std::function<void()>& read) {  // a META value its readers refuse
        try {
            read();
        } catch (const FormatError& e) {
            const std::string what = e.what();  // "META: META KEY ..."
            r.add(kNone, what.substr(what.find(": ") + 2));
        }
    };
    readable([&] { upAxisOf(s, "META"); });
    readable([&] { offsetOf(s, "META"); });
    checkTree(s, [&](uint32_t node, const std::string& message) { r.add(node, message); });
    for (const Node& nd : s.nodes) {
        checkNode(s, nd, o, cTextured, r);
        checkCounts(s, nd, r);
    }
    checkCoverage(db, r);
    if (!o.quick)
        for (uint32_t i = 0; i < s.blobs.size(); ++i) checkBlobData(db, i, r);
    return out;
}

}  // namespace hlod
