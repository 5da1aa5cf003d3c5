// The tileset.json of `hlod export tiles` (3D Tiles 1.1 §Tileset JSON): a root tile without
// content whose children are the hlod0 nodes, then one tile per node following the database's
// tree. Every tile refines by REPLACE (a node's children replace it, thesis §3.2). Bounding
// volumes are axis-aligned boxes in the database's frame (z up): a tile's box is the union of its
// node's bounds, its content's exact decoded bounds (positions may lie half a lattice step outside
// the node's bounds, FORMAT.md §Geometry blobs) and its children's boxes, so it contains both.
// geometricError is the database's measured error in metres, raised to the largest of its
// children's where a database breaks the non-increasing rule; the root's is the diagonal of the
// whole model (the error of drawing nothing) and at least every hlod0 node's. --origin places the
// local frame as east-north-up at a WGS84 point through the root's transform. A y-up database
// (META "up", a glTF input) keeps its boxes and GLBs in its own frame and gets a root transform
// that turns its y up into the tileset's z up, (x, y, z) -> (x, -z, y), before any placement.
// A database built with --offset (META "offset") records it in the tileset's extras, beside the
// frame: --origin places the database's frame, whose zero is the input's offset point.
#include "formats/offset.h"
#include "formats/tiles_detail.h"
#include "formats/up_axis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>

namespace hlod {

Geodetic parseGeodetic(const std::string& text) {
    std::istringstream in(text);
    Geodetic g;
    char comma1 = 0, comma2 = 0;
    if (!(in >> g.latitude >> comma1 >> g.longitude >> comma2 >> g.height) || comma1 != ',' || comma2 != ',' ||
        !(in >> std::ws).eof() || !(g.height >= -6e6 && g.height <= 1e7) || std::abs(g.latitude) > 90 || std::abs(g.longitude) > 180)
        // -6e6 m keeps the origin on its side of the earth's centre (polar radius 6,356,752 m): -7e6
        // turned the model's east-north-up frame inside out (accepted until stop 44).
        throw std::invalid_argument("--origin " + text +
                                    ": expected LAT,LON,HEIGHT (degrees in [-90, 90], [-180, 180], metres in [-6e6, 1e7])");
    return g;
}

std::array<double, 16> eastNorthUpToEcef(const Geodetic& g) {
    constexpr double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);  // WGS84
    const double lat = g.latitude * std::numbers::pi / 180, lon = g.longitude * std::numbers::pi / 180;
    const double sinLat = std::sin(lat), cosLat = std::cos(lat), sinLon = std::sin(lon), cosLon = std::cos(lon);
    const double n = a / std::sqrt(1 - e2 * sinLat * sinLat);
    return {-sinLon,          cosLon,           0,      0,   // east
            -sinLat * cosLon, -sinLat * sinLon, cosLat, 0,   // north
            cosLat * cosLon,  cosLat * sinLon,  sinLat, 0,   // up
            (n + g.height) * cosLat * cosLon, (n + g.height) * cosLat * sinLon, (n * (1 - e2) + g.height) * sinLat, 1};
}

namespace tiles {

namespace {

using Matrix = std::array<double, 16>;  // column-major, as 3D Tiles' transform

// The database's y-up frame to the tileset's z-up frame: x stays, y (up) becomes z, z becomes -y.
constexpr Matrix kYUpToZUp = {1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1};

Matrix multiply(const Matrix& a, const Matrix& b) {
    Matrix c{};
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row)
            for (int k = 0; k < 4; ++k) c[col * 4 + row] += a[k * 4 + row] * b[col * 4 + k];
    return c;
}

Box3f unite(const Box3f& a, const Box3f& b) {
    return {{std::min(a.min.x, b.min.x), std::min(a.min.y, b.min.y), std::min(a.min.z, b.min.z)},
            {std::max(a.max.x, b.max.x), std::max(a.max.y, b.max.y), std::max(a.max.z, b.max.z)}};
}

nlohmann::json boxJson(const Box3f& b) {
    const double c[3] = {0.5 * (double(b.min.x) + b.max.x), 0.5 * (double(b.min.y) + b.max.y), 0.5 * (double(b.min.z) + b.max.z)};
    const double h[3] = {0.5 * (double(b.max.x) - b.min.x), 0.5 * (double(b.max.y) - b.min.y), 0.5 * (double(b.max.z) - b.min.z)};
    return {{"box", nlohmann::json::array({c[0], c[1], c[2], h[0], 0, 0, 0, h[1], 0, 0, 0, h[2]})}};
}

bool finite(const Box3f& b) {
    return std::isfinite(b.min.x) && std::isfinite(b.min.y) && std::isfinite(b.min.z) && std::isfinite(b.max.x) &&
           std::isfinite(b.max.y) && std::isfinite(b.max.z);
}

struct Tree {
    const Skeleton& s;
    const std::vector<std::optional<Box3f>>& content;
    std::vector<Box3f> box;
    std::vector<double> error;

    nlohmann::json tile(uint32_t n) const {
        nlohmann::json t = {{"boundingVolume", boxJson(box[n])}, {"geometricError", error[n]}, {"refine", "REPLACE"}};
        if (content[n]) t["content"] = {{"uri", contentUri(n)}};
        nlohmann::json children = nlohmann::json::array();
        for (uint32_t c = s.nodes[n].firstChild; c != kNone; c = s.nodes[c].nextSibling) children.push_back(tile(c));
        if (!children.empty()) t["children"] = std::move(children);
        return t;
    }
};

}  // namespace

nlohmann::json tilesetJson(const Skeleton& s, const std::vector<std::optional<Box3f>>& content,
                           const TilesOptions& options, const std::string& name) {
    Tree tree{s, content, std::vector<Box3f>(s.nodes.size()), std::vector<double>(s.nodes.size(), 0)};
    std::vector<std::optional<Box3f>> below(s.nodes.size());  // union of the children's boxes
    // A child's id is larger than its parent's (the writer adds parents first, FORMAT.md), so a
    // pass from the last node to the first sees every child before its parent.
    for (uint32_t n = uint32_t(s.nodes.size()); n-- > 0;) {
        const Node& node = s.nodes[n];
        if (!finite(node.bounds) || !std::isfinite(node.geometricError) || node.geometricError < 0)
            throw FormatError(name + ": node " + std::to_string(n) + ": non-finite bounds or geometric error");
        Box3f b = content[n] ? unite(node.bounds, *content[n]) : node.bounds;
        if (below[n]) b = unite(b, *below[n]);
        tree.box[n] = b;
        tree.error[n] = std::max(tree.error[n], double(node.geometricError));
        if (node.parent == kNone) continue;
        if (node.parent >= n) throw FormatError(name + ": node " + std::to_string(n) + ": its parent does not precede it");
        below[node.parent] = below[node.parent] ? unite(*below[node.parent], b) : b;
        tree.error[node.parent] = std::max(tree.error[node.parent], tree.error[n]);
    }

    const std::vector<uint32_t> roots = s.roots();
    if (roots.empty()) throw FormatError(name + ": the database has no hlod0 node");
    Box3f all = tree.box[roots.front()];
    double rootError = 0;
    nlohmann::json children = nlohmann::json::array();
    for (uint32_t r : roots) {
        all = unite(all, tree.box[r]);
        rootError = std::max(rootError, tree.error[r]);
        children.push_back(tree.tile(r));
    }
    const double diagonal = std::hypot(double(all.max.x) - all.min.x, double(all.max.y) - all.min.y,
                                       double(all.max.z) - all.min.z);
    rootError = std::max(rootError, diagonal);
    nlohmann::json root = {{"boundingVolume", boxJson(all)}, {"geometricError", rootError}, {"refine", "REPLACE"},
                           {"children", std::move(children)}};
    nlohmann::json frame;
    const bool yUp = (options.up.empty() ? upAxisOf(s, name).axis : parseUpAxis(options.up, "--up")) == 1;
    const std::string axes = yUp ? "the database's x, -z, y (its y up)" : "the database's x, y, z";
    if (options.origin) {
        root["transform"] = yUp ? multiply(eastNorthUpToEcef(*options.origin), kYUpToZUp) : eastNorthUpToEcef(*options.origin);
        frame = {{"frame", "east-north-up at origin, metres (" + axes + ")"},
                 {"origin", {{"latitude", options.origin->latitude}, {"longitude", options.origin->longitude},
                             {"height", options.origin->height}}}};
    } else {
        if (yUp) root["transform"] = kYUpToZUp;
        frame = {{"frame", "local: " + axes + " in metres, z up; not placed on the globe "
                           "(hlod export tiles --origin LAT,LON,HEIGHT places it)"}};
    }
    frame["up"] = yUp ? "y" : "z";
    if (const std::optional<Offset> offset = offsetOf(s, name)) frame["offset"] = *offset;  // + the database's = the input's coordinates
    return {{"asset", {{"version", "1.1"}, {"generator", "hlod export tiles"}, {"extras", {{"hlod", frame}}}}},
            {"geometricError", rootError},
            {"root", std::move(root)}};
}

}  // namespace tiles
}  // namespace hlod
