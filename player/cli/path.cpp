// `hlod path DB --kind walk|drive|fly|erratic -o FILE`: camera paths of thesis Chapter 6 (walk,
// 10x faster drive, fly-over) and the erratic viewpoint path of Funkhouser & Séquin 1993, in the format of
// player/CAMERA_PATH.md.
#include "player/cli/subcommands.h"

#include "formats/db.h"
#include "formats/temp_files.h"
#include "formats/up_axis.h"
#include "player/camera_path.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace hlod::cli {
namespace {

struct PathArgs {
    std::string db, output, kind = "walk", up, units = "m";  // up empty: the database's (FORMAT.md META "up")
    PathOptions options;
};

// The deepest level whose cut (its nodes and the leaves above it) holds at most
// kMaxGroundTriangles: the surfaces a walk keeps its eye above (player/CAMERA_PATH.md).
constexpr uint64_t kMaxGroundTriangles = 2'000'000;

bool inCut(const Node& n, uint32_t level) { return n.level == level || (n.level < level && n.firstChild == kNone); }

uint32_t groundLevel(const Skeleton& s) {
    uint32_t deepest = 0;
    for (const Node& n : s.nodes) deepest = std::max(deepest, n.level);
    for (uint32_t level = deepest; level > 0; --level) {
        uint64_t triangles = 0;
        for (const Node& n : s.nodes)
            if (inCut(n, level)) triangles += n.triangles();
        if (triangles <= kMaxGroundTriangles) return level;
    }
    return 0;
}

// A blob that cannot be read or decoded is left out of the ground with one warning (as `hlod
// play` skips a node it cannot load): the path is still written.
void addSurfaces(const Database& db, uint32_t level, SurfaceHeights& surfaces) {
    const Skeleton& s = db.skeleton();
    uint64_t failed = 0;
    std::string first;
    for (const Node& n : s.nodes) {
        if (!inCut(n, level)) continue;
        for (uint32_t b = n.firstBlob; b < n.firstBlob + n.blobCount; ++b) {
            if (s.blobs[b].kind != BlobKind::Geometry) continue;
            try {
                surfaces.add(decodeGeometry(db.readBlob(b), db.path() + ": blob " + std::to_string(b)));
            } catch (const FormatError& e) {
                if (failed++ == 0) first = e.what();
            }
        }
    }
    if (failed)
        std::cerr << "hlod path: warning: " << failed << " geometry blobs left out of the ground (first: " << first << ")\n";
}

int runPath(PathArgs& a) {
    checkOutputFile(a.output, "camera path", {a.db});
    a.options.kind = parsePathKind(a.kind);
    if (!a.up.empty()) a.options.upAxis = parseUpAxis(a.up, "--up");
    a.options.metresPerUnit = parseUnits(a.units);
    Database db = Database::open(a.db);
    const UpAxis stored = upAxisOf(db.skeleton(), a.db);
    if (a.up.empty()) a.options.upAxis = stored.axis;
    for (uint32_t root : db.skeleton().roots()) {  // the path is planned from the hlod0 bounds
        const Box3f& b = db.skeleton().nodes[root].bounds;
        const float v[6] = {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
        if (!std::all_of(v, v + 6, [](float x) { return std::isfinite(x) && std::abs(x) <= 1e15f; }) || b.min.x > b.max.x ||
            b.min.y > b.max.y || b.min.z > b.max.z)
            throw FormatError(a.db + ": node " + std::to_string(root) +
                              ": bounding box is not finite or has min > max (`hlod validate` lists every violation)");
    }
    const PathPlan plan = planPath(db.skeleton(), a.options);
    const bool onGround = !plan.object && a.options.kind != PathKind::Fly;
    SurfaceHeights surfaces(a.options.upAxis);
    const uint32_t level = onGround ? groundLevel(db.skeleton()) : 0;
    if (onGround) addSurfaces(db, level, surfaces);
    CameraPath path = generatePath(db.skeleton(), a.options, onGround ? &surfaces : nullptr);
    for (const CameraKey& k : path.keys)  // a fly orbit lies 1.5 extents out: play refused what path wrote (until stop 45)
        for (double c : k.position)
            if (!(std::abs(c) <= kMaxCameraCoordinate))
                throw InputError(a.db + ": the " + a.kind + " path reaches a coordinate of " + std::to_string(c) +
                                 ", beyond the 1e15 a camera path holds (the model is too large or too far from the origin)");
    writeCameraPathFile(a.output, path);
    std::cout << a.output << ": " << a.kind << " path, " << path.keys.size() << " keys, duration " << path.duration()
              << " s\n";
    std::cout << "scale: " << (plan.object ? "object" : "city-like") << " (horizontal extent " << plan.horizontalExtent
              << ", height " << plan.verticalExtent << " units; 1 unit = " << a.options.metresPerUnit << " m)";
    if (a.options.kind != PathKind::Fly)
        std::cout << "; speed " << plan.speed << " units/s, eye " << plan.eyeHeight << " units above the "
                  << (plan.object ? "model's bottom" : "ground");
    std::cout << '\n';
    if (onGround)
        std::cout << "ground: the lowest of " << surfaces.triangles() << " triangles (level " << level
                  << " and the leaves above it) under the eye, climbing at most " << kMaxClimbMps
                  << " m/s; the route does not avoid walls: it passes through the geometry between "
                  << countCrossings(path, surfaces) << " of " << path.keys.size() - 1 << " key pairs\n";
    std::cout << "up axis: " << (a.options.upAxis == 1 ? "y" : "z") << " ("
              << (!a.up.empty() ? "--up" : stored.recorded ? "recorded in the database" : "not recorded: z, as before the database kept it")
              << ")\n";
    return 0;
}

}  // namespace

void addPath(CLI::App& app, int& status) {
    auto a = std::make_shared<PathArgs>();
    CLI::App* sub = app.add_subcommand("path", "generate a camera path (walk, drive, fly, erratic, line, zigzag) from a database's bounds");
    addDatabaseArgument(*sub, a->db);
    sub->add_option("-o,--output", a->output, "camera path file to write")->required()->check(nonEmptyPath());
    sub->add_option("--kind", a->kind, "walk, drive (10x the walk), fly (whole model in view), erratic, line, zigzag (Robin Hood Table 2)")
        ->check(CLI::IsMember({"walk", "drive", "fly", "erratic", "line", "zigzag"}));
    sub->add_option("--duration", a->options.duration, "seconds, 0 or at least 0.001 (default or 0: one lap; fly 60 s)")
        ->check(finiteIn(0, kMaxCameraTime));
    sub->add_option("--speed", a->options.speed,
                    "metres per second (default or 0: city-like 1.5 walk, 15 drive; object: one lap in 60 s, drive 6 s)")
        ->check(finiteAtLeast(0));
    sub->add_option("--eye-height", a->options.eyeHeight,
                    "metres above the ground estimate (city-like) or the model's bottom (object; default: half its height), "
                    "0 to 1e15 (a camera path's coordinates)")
        ->check(finiteIn(0, kMaxCameraCoordinate));
    addUnitsOption(*sub, a->units);
    sub->add_option("--key-interval", a->options.keyInterval, "seconds between keys, at least " + formatConstant(kMinKeyInterval) +
                                                                  " (default " + formatConstant(PathOptions{}.keyInterval) + ")")
        ->check(finiteIn(kMinKeyInterval, kMaxCameraTime));
    sub->add_option("--seed", a->options.seed, "seed of the erratic turns and teleports")
        ->check(wholeNumber(a->options.seed));
    sub->add_option("--up", a->up, "up axis of the model, y or z (default: the one the database records; z for a database without one)");
    sub->add_flag("--look-at-center", a->options.lookAtCenter,
                  "walk, drive, erratic: look at the model's centre, not ahead (walking around an object scan)");
    sub->callback([a, &status] { status = runGuarded("path", [&] { return runPath(*a); }); });
}

}  // namespace hlod::cli
