// The input files of a build (input_files.cpp): the up axis they imply, a mesh file's format by
// its extension, the mesh files of a folder input (one block each).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hlod {

// The up axis recorded in the database (META "up", FORMAT.md) and why: `requested`
// (--up) when given; otherwise y for glTF (glTF 2.0 is y-up) and z for OBJ and PLY (the
// convention of scanners and of every database before the key). A folder takes its meshes'
// convention; one that mixes glTF with OBJ/PLY is an InputError asking for --up.
struct UpChoice {
    std::string axis;    // "y" or "z"
    std::string reason;
};
UpChoice chooseUpAxis(const std::string& input, const std::string& requested);
// A path's extension in lower case (".obj"); whether it names a mesh format hlod reads (.ply,
// .obj, .gltf, .glb, by the extension alone); the mesh files of a folder input, sorted, where an entry so named that is not a regular file (a link
// leading nowhere or in a loop, a FIFO) is an InputError naming it.
std::string meshExtension(const std::filesystem::path& p);
bool isMeshFile(const std::filesystem::path& p);
std::vector<std::filesystem::path> folderMeshes(const std::string& folder);

}  // namespace hlod
