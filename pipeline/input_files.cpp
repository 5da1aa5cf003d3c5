// The input files of a build (pipeline/input_files.h).
#include "pipeline/input_files.h"

#include "formats/errors.h"
#include "formats/up_axis.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace hlod {

namespace fs = std::filesystem;

std::string meshExtension(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool isMeshFile(const fs::path& p) {
    const std::string ext = meshExtension(p);
    return ext == ".ply" || ext == ".obj" || ext == ".gltf" || ext == ".glb";
}

// An entry named as a mesh that is not one was left out without a word (a block missing from the
// database, exit 0), a link loop gave a library message (until stop 45).
std::vector<fs::path> folderMeshes(const std::string& input) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (fs::directory_iterator it(input, ec), end; !ec && it != end; it.increment(ec)) {
        if (!isMeshFile(it->path())) continue;
        std::error_code statError;
        const fs::file_status st = fs::status(it->path(), statError);
        if (fs::is_directory(st)) continue;  // a folder named x.obj is not a block
        if (statError) throw InputError(it->path().string() + ": cannot read (" + statError.message() + ")");
        if (!fs::is_regular_file(st)) throw InputError(it->path().string() + ": not a regular file");
        files.push_back(it->path());
    }
    if (ec) throw InputError(input + ": cannot list the folder (" + ec.message() + ")");
    std::sort(files.begin(), files.end());
    return files;
}

UpChoice chooseUpAxis(const std::string& input, const std::string& requested) {
    if (!requested.empty()) {
        parseUpAxis(requested, "--up");
        return {requested, "--up"};
    }
    bool gltf = false, other = false;
    if (fs::is_directory(input)) {
        for (const fs::path& file : folderMeshes(input)) {
            const std::string ext = meshExtension(file);
            (ext == ".gltf" || ext == ".glb" ? gltf : other) = true;
        }
    } else {
        const std::string ext = meshExtension(input);
        (ext == ".gltf" || ext == ".glb" ? gltf : other) = true;
    }
    if (gltf && other) throw InputError(input + ": folder mixes glTF (y up) and OBJ/PLY (z up) meshes; give --up y or --up z");
    if (gltf) return {"y", "glTF is y-up"};
    return {"z", "OBJ/PLY: z up by convention; --up y for a y-up scan"};
}

}  // namespace hlod
