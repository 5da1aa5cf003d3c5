// `hlod export tiles`: an HLOD database as a 3D Tiles 1.1 tileset (README "Export to 3D Tiles").
// One tile per node, glTF 2.0 binary content whose geometry is the node's stored Draco blobs
// (KHR_draco_mesh_compression) and whose images are its stored JPEG/PNG blobs, byte for byte;
// refine REPLACE; geometric errors from the database; the hlod0 nodes are the root's children.
#pragma once

#include "formats/db.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace hlod {

// A point on the WGS84 ellipsoid: degrees, degrees, metres above the ellipsoid.
struct Geodetic {
    double latitude = 0, longitude = 0, height = 0;
};

// Parses "LAT,LON,HEIGHT" (degrees, degrees, metres); throws std::invalid_argument.
Geodetic parseGeodetic(const std::string& text);

// The column-major 4x4 matrix taking east-north-up coordinates at `origin` (x east, y north,
// z up, metres) to earth-centred earth-fixed ones (WGS84), as 3D Tiles' tile.transform.
std::array<double, 16> eastNorthUpToEcef(const Geodetic& origin);

struct TilesOptions {
    std::optional<Geodetic> origin;  // none: the tileset stays in the database's local frame
    bool archive = false;            // one .3tz file (a stored ZIP with its index) instead of a folder
    std::string up;                  // "y" or "z"; empty: the database's (upAxisOf)
};

struct TilesReport {
    uint64_t tiles = 0;          // the root and one per node
    uint64_t contentTiles = 0;   // tiles with a GLB (nodes with geometry)
    uint64_t triangles = 0;      // Σ triangles of every GLB
    uint64_t contentBytes = 0;   // Σ GLB sizes
    uint64_t tilesetBytes = 0;   // tileset.json
    uint64_t outputBytes = 0;    // the folder's files, or the .3tz file
};

// Writes the tileset to `out` (a folder, or with options.archive a .3tz file), atomically: it is
// written as OUT.tmp-hlodSPACE-PID-XXXXXX next to `out` (tileset.json last) and renamed onto `out` at the end, so
// a failed export leaves nothing at `out` that looks complete. An earlier export at `out` is
// replaced; a non-empty folder that is not one is refused (InputError). A blob that fails its
// checksum or does not decode throws FormatError.
TilesReport exportTiles(const Database& db, const std::string& out, const TilesOptions& options);

}  // namespace hlod
