// The stages of `hlod export tiles` (formats/export_tiles.h), one per file: a node's GLB
// (tiles_glb.cpp), the tileset JSON (tiles_tileset.cpp), the .3tz archive (tiles_3tz.cpp); the
// export itself (tiles_export.cpp) runs them. Internal to formats/.
#pragma once

#include "formats/export_tiles.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace hlod::tiles {

// One node as glTF 2.0 binary: one mesh, one primitive per geometry blob (its Draco bytes as a
// KHR_draco_mesh_compression buffer view), one image per texture blob (its JPEG/PNG bytes as a
// buffer view), unlit textured materials. `bounds` is the exact box of the decoded positions in
// the database's frame (z up; the GLB's node matrix turns it y-up for glTF).
struct Glb {
    std::vector<uint8_t> bytes;
    Box3f bounds{};
    uint64_t triangles = 0;
};
// nullopt for a node without geometry. Throws FormatError for a blob that fails its checksum,
// does not decode, or decodes to other counts or attributes than its record says.
std::optional<Glb> nodeGlb(const Database& db, uint32_t node);

// The tileset.json document. `content[n]` is node n's content box (nullopt: no content), at
// contentUri(n); `name` (the database) starts error messages. Throws FormatError.
nlohmann::json tilesetJson(const Skeleton& s, const std::vector<std::optional<Box3f>>& content,
                           const TilesOptions& options, const std::string& name);

// Packs every file under `folder` into `file` as a 3D Tiles archive: a ZIP without compression,
// the tileset at its root, and the index "@3dtilesIndex1@" (MD5 of each path and its local header
// offset, sorted by hash) as the last entry. Throws std::runtime_error.
void write3tz(const std::string& folder, const std::string& file);

// The path of node n's content inside the tileset.
std::string contentUri(uint32_t node);

// "PATH: cannot write (reason)" for a stream that failed with `error` (errno; 0: no reason known),
// as every writer of hlod says why (a full disk: "File too large", "No space left on device").
inline std::string writeFailure(const std::string& path, int error) {
    return path + ": cannot write" + (error ? " (" + std::string(std::strerror(error)) + ")" : std::string());
}

}  // namespace hlod::tiles
