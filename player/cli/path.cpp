// `hlod path DB --kind walk|drive|fly|erratic -o FILE`: camera paths of thesis Chapter 6 (walk,
// 10x faster drive, fly-over) and the erratic viewpoint path of Funkhouser & Séquin 1993, in the format of
// player/CAMERA_PATH.md.
#include "player/cli/subcommands.h"

#include "formats/db.h"
#include "formats/up_axis.h"
#include "player/camera_path.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>

namespace hlod::cli {
namespace {

struct PathArgs {
    std::string db, output, kind = "walk", up, units = "m";  // up empty: the database's (FORMAT.md META "up")
    PathOptions options;
};

int runPath(PathArgs& a) {
    a.options.kind = parsePathKind(a.kind);
    if (!a.up.empty()) a.options.upAxis = parseUpAxis(a.up, "--up");
    a.options.metresPerUnit = parseUnits(a.units);
    Database db = Database::open(a.db);
    const UpAxis stored = upAxisOf(db.skeleton(), a.db);
    if (a.up.empty()) a.options.upAxis = stored.axis;
    const PathPlan plan = planPath(db.skeleton(), a.options);
    CameraPath path = generatePath(db.skeleton(), a.options);
    writeCameraPathFile(a.output, path);
    std::cout << a.output << ": " << a.kind << " path, " << path.keys.size() << " keys, duration " << path.duration()
              << " s\n";
    std::cout << "scale: " << (plan.object ? "object" : "city-like") << " (horizontal extent " << plan.horizontalExtent
              << ", height " << plan.verticalExtent << " units; 1 unit = " << a.options.metresPerUnit << " m)";
    if (a.options.kind != PathKind::Fly)
        std::cout << "; speed " << plan.speed << " units/s, eye " << plan.eyeHeight << " units above the "
                  << (plan.object ? "model's bottom" : "ground estimate");
    std::cout << '\n';
    std::cout << "up axis: " << (a.options.upAxis == 1 ? "y" : "z") << " ("
              << (!a.up.empty() ? "--up" : stored.recorded ? "recorded in the database" : "not recorded: z, as before the database kept it")
              << ")\n";
    return 0;
}

}  // namespace

void addPath(CLI::App& app, int& status) {
    auto a = std::make_shared<PathArgs>();
    CLI::App* sub = app.add_subcommand("path", "generate a camera path (walk, drive, fly, erratic) from a database's bounds");
    addDatabaseArgument(*sub, a->db);
    sub->add_option("-o,--output", a->output, "camera path file to write")->required();
    sub->add_option("--kind", a->kind, "walk, drive (10x the walk), fly (whole model in view), erratic")
        ->check(CLI::IsMember({"walk", "drive", "fly", "erratic"}));
    sub->add_option("--duration", a->options.duration, "seconds (default: one lap; fly 60 s)");
    sub->add_option("--speed", a->options.speed,
                    "metres per second (default: city-like 1.5 walk, 15 drive; object: one lap in 60 s, drive 6 s)");
    sub->add_option("--eye-height", a->options.eyeHeight,
                    "metres above the ground estimate (city-like) or the model's bottom (object; default: half its height)");
    sub->add_option("--units", a->units, "what one database unit is: m (default), cm, mm, km or a number of metres");
    sub->add_option("--key-interval", a->options.keyInterval, "seconds between keys");
    sub->add_option("--seed", a->options.seed, "seed of the erratic turns and teleports");
    sub->add_option("--up", a->up, "up axis of the model, y or z (default: the one the database records; z for a database without one)");
    sub->add_flag("--indoors", a->options.indoors,
                  "an interior scan: keep the eye above the floor (the lowest bottom of the finest node boxes) "
                  "instead of the lowest box top, which in a room is its ceiling (player/CAMERA_PATH.md)");
    sub->add_flag("--look-at-center", a->options.lookAtCenter,
                  "walk, drive, erratic: look at the model's centre, not ahead (walking around an object scan)");
    sub->callback([a, &status] { status = runGuarded("path", [&] { return runPath(*a); }); });
}

}  // namespace hlod::cli
