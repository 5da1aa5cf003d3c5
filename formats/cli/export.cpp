// `hlod export tiles DB -o DIR [--origin LAT,LON,HEIGHT] [--3tz]`: the database as a 3D Tiles 1.1
// tileset (formats/export_tiles.h; README "Export to 3D Tiles"). `hlod export` holds the export
// formats as sub-subcommands; 3D Tiles is the one there is.
#include "formats/cli/subcommands.h"

#include "formats/export_tiles.h"
#include "formats/up_axis.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>

namespace hlod::cli {

namespace {

struct TilesArgs {
    std::string db, out, origin, up;
    bool archive = false;
};

int runTiles(const TilesArgs& a) {
    TilesOptions options;
    if (!a.origin.empty()) options.origin = parseGeodetic(a.origin);
    options.archive = a.archive;
    options.up = a.up;
    const Database db = Database::open(a.db);
    const auto start = std::chrono::steady_clock::now();
    const TilesReport r = exportTiles(db, a.out, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: 3D Tiles 1.1 tileset%s, %llu tiles (%llu with content), %llu triangles, %.1f MiB "
                "(GLBs %.1f MiB, tileset.json %.1f KiB), %.1f s\n",
                a.out.c_str(), a.archive ? " (.3tz)" : "", (unsigned long long)r.tiles,
                (unsigned long long)r.contentTiles, (unsigned long long)r.triangles, r.outputBytes / 1048576.0,
                r.contentBytes / 1048576.0, r.tilesetBytes / 1024.0, seconds);
    if (options.origin)
        std::printf("placed: local x, y, z = east, north, up at %.8f, %.8f, %.3f m (WGS84)\n", options.origin->latitude,
                    options.origin->longitude, options.origin->height);
    else
        std::printf("note: no --origin: the tileset stays in the database's local frame (metres, z up), "
                    "at the earth's centre in a globe viewer\n");
    const bool yUp = (a.up.empty() ? upAxisOf(db.skeleton(), a.db).axis : parseUpAxis(a.up, "--up")) == 1;
    std::printf("up axis: %s (%s)%s\n", yUp ? "y" : "z", a.up.empty() ? "the database's" : "--up",
                yUp ? ": the root transform turns it to the tileset's z up" : "");
    return kExitOk;
}

}  // namespace

void addExport(CLI::App& app, int& status) {
    CLI::App* sub = app.add_subcommand("export", "write a database in another format (tiles: 3D Tiles 1.1)");
    sub->require_subcommand(1);
    auto args = std::make_shared<TilesArgs>();
    CLI::App* tiles = sub->add_subcommand(
        "tiles", "write a 3D Tiles 1.1 tileset: one tile per node, glTF with the stored Draco geometry and JPEG textures");
    addDatabaseArgument(*tiles, args->db);
    tiles->add_option("-o,--output", args->out, "output folder (with --3tz: the .3tz file)")
        ->required()
        ->check(nonEmptyPath());
    tiles->add_option("--origin", args->origin,
                      "place the model's local frame (x east, y north, z up) at this WGS84 point; "
                      "without it the tileset stays in local coordinates")
        ->type_name("LAT,LON,HEIGHT");
    tiles->add_option("--up", args->up, "up axis of the database, y or z (default: the one it records; z for a database without one)")
        ->check(CLI::IsMember({"y", "z"}));
    tiles->add_flag("--3tz", args->archive, "write one .3tz archive (3D Tiles archive: stored ZIP with an index)");
    tiles->callback([args, &status] { status = runGuarded("export tiles", [&] { return runTiles(*args); }); });
}

}  // namespace hlod::cli
