// Input checks shared by every reader: non-finite attributes and
// out-of-range indices are errors, degenerate triangles are dropped and counted, texture paths
// and every other reference stay inside the input's folder (resolveReference), unusable textures
// (missing, empty, not an image, absurd size) are TextureProblems: the material is untextured. readMesh picks the reader.
#include "pipeline/pipeline.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

namespace hlod {
namespace {

namespace fs = std::filesystem;

void checkFinite(const std::vector<float>& values, size_t perVertex, const char* what, const std::string& name, double limit = INFINITY) {
    for (size_t i = 0; i < values.size(); ++i) {
        if (!std::isfinite(values[i]))
            throw InputError(name + ": vertex " + std::to_string(i / perVertex) + " has a NaN/Inf " + what);
        if (std::abs(values[i]) > limit)
            throw InputError(name + ": vertex " + std::to_string(i / perVertex) + " has a " + what + " beyond 1e15 (the limit)");
    }
}

template <class T>
void dropIfShort(std::vector<T>& values, size_t perVertex, size_t vertices) {
    if (values.size() != perVertex * vertices) values.clear();
}

bool degenerate(const MeshData& m, uint32_t a, uint32_t b, uint32_t c) {
    const float* p = m.positions.data();
    return a == b || b == c || a == c || zeroArea(p + 3 * a, p + 3 * b, p + 3 * c);
}

// The one file of `wanted`'s folder whose name equals wanted's but for case; empty if none or several.
fs::path sameNameButCase(const fs::path& wanted) {
    const auto lower = [](std::string text) {
        for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return text;
    };
    const std::string name = lower(wanted.filename().string());
    fs::path found;
    std::error_code error;
    for (fs::directory_iterator it(wanted.parent_path(), error), end; !error && it != end; it.increment(error))
        if (lower(it->path().filename().string()) == name) {
            if (!found.empty()) return {};
            found = it->path();
        }
    return found;
}

// `relative` under `base`, each component as written or, when it does not exist so, the one
// entry of its folder whose name equals it but for case; empty when some component has neither.
fs::path ignoringCase(const fs::path& base, const fs::path& relative) {
    fs::path at = base;
    for (const fs::path& part : relative) {
        std::error_code error;
        if (fs::exists(at / part, error)) {
            at /= part;
            continue;
        }
        at = sameNameButCase(at / part);
        if (at.empty()) return {};
    }
    return at;
}

// A reference as Windows tools write it, where this file system has it: the reference itself,
// then with backslashes as separators, then, for a reference with a backslash or a drive letter,
// its last name alone in the input's folder (an exporter's absolute path to its own disk,
// `C:\scan\atlas_1.jpg`; a POSIX `lod1/atlas.jpg` is never taken for another `atlas.jpg`); each component's case is
// ignored when exactly one entry of its folder so matches. Empty when none exists. A slashed
// form that is absolute or has a '..' component is not tried.
fs::path windowsFallback(const fs::path& base, const std::string& reference) {
    std::string slashed = reference;
    std::replace(slashed.begin(), slashed.end(), '\\', '/');
    const fs::path posix(slashed);
    std::vector<fs::path> candidates{reference};
    const bool up = std::any_of(posix.begin(), posix.end(), [](const fs::path& part) { return part == ".."; });
    if (slashed != reference && !posix.is_absolute() && !up) candidates.push_back(posix);
    const fs::path name = posix.filename();
    const bool windows = slashed != reference || (reference.size() > 1 && std::isalpha(static_cast<unsigned char>(reference[0])) &&
                                                  reference[1] == ':');
    if (windows && !name.empty() && name != "." && name != ".." && name != posix) candidates.push_back(name);
    for (const fs::path& candidate : candidates)
        if (fs::path found = ignoringCase(base, candidate); !found.empty()) return found;
    return {};
}

}  // namespace

bool zeroArea(const float* a, const float* b, const float* c) {
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return n[0] == 0 && n[1] == 0 && n[2] == 0;
}

std::string folderOf(const std::string& meshPath) {
    const fs::path parent = fs::path(meshPath).parent_path();
    return parent.empty() ? "." : parent.string();
}

std::string resolveReference(const std::string& input, const std::string& folder, const std::string& reference,
                             const std::string& kind, const ReadOptions& options) {
    std::string shown = reference;  // one line whatever the reference holds (a glTF URI may hold "\n")
    for (char& c : shown)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    const auto fail = [&](const std::string& why, bool refusal) {
        throw InputError(input + ": " + kind + " '" + shown + "' " + why +
                         (refusal ? " (refused; --allow-outside-input allows it)" : ""));
    };
    const fs::path ref(reference);
    if (!options.allowOutsideInput) {
        if (reference.empty()) fail("is empty", true);
        if (ref.is_absolute()) fail("is an absolute path", true);
        for (const fs::path& part : ref)
            if (part == "..") fail("has a '..' component", true);
    }
    std::error_code error;
    const fs::path base = fs::weakly_canonical(fs::absolute(fs::path(folder), error), error);
    fs::path resolved = error ? fs::path() : fs::weakly_canonical(base / ref, error);
    if (error) fail("cannot be resolved (" + error.message() + ")", false);  // e.g. a name longer than 255 bytes
    if (std::error_code unknown; !fs::exists(resolved, unknown))
        if (const fs::path found = windowsFallback(base, reference); !found.empty()) resolved = fs::weakly_canonical(found, error);
    if (error) fail("cannot be resolved (" + error.message() + ")", false);
    for (const std::string& output : options.outputs)
        if (fs::equivalent(resolved, output, error)) fail("is the output of this run (" + output + "; refused)", false);
    if (options.allowOutsideInput) return resolved.string();
    const auto b = std::mismatch(base.begin(), base.end(), resolved.begin(), resolved.end()).first;
    if (b != base.end())
        fail("resolves outside the input's folder (to " + resolved.string() + ", through a symbolic link)", true);
    return resolved.string();
}

void sanitize(SourceMesh& source, const std::string& name) {
    MeshData& m = source.piece.mesh;
    const size_t vertices = m.vertexCount();
    if (m.positions.size() % 3 != 0) throw InputError(name + ": corrupt mesh (incomplete vertex)");
    dropIfShort(m.texcoords, 2, vertices);
    dropIfShort(m.normals, 3, vertices);
    dropIfShort(m.colors, 4, vertices);
    checkFinite(m.positions, 3, "coordinate", name, kMaxCoordinate);
    checkFinite(m.texcoords, 2, "texture coordinate", name);
    checkFinite(m.normals, 3, "normal", name);
    size_t kept = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t a = m.indices[3 * t], b = m.indices[3 * t + 1], c = m.indices[3 * t + 2];
        for (uint32_t i : {a, b, c})
            if (i >= vertices)
                throw InputError(name + ": triangle " + std::to_string(t) + " uses vertex " + std::to_string(i) +
                                 " but there are only " + std::to_string(vertices));
        if (source.piece.materials[t] >= source.materials.size())
            throw InputError(name + ": triangle " + std::to_string(t) + " has an unknown material");
        if (degenerate(m, a, b, c)) {
            ++source.stats.degenerateDropped;
            continue;
        }
        m.indices[3 * kept] = a, m.indices[3 * kept + 1] = b, m.indices[3 * kept + 2] = c;
        source.piece.materials[kept++] = source.piece.materials[t];
    }
    m.indices.resize(3 * kept);
    source.piece.materials.resize(kept);
    if (kept == 0) throw InputError(name + ": empty mesh (no valid triangles)");
    checkTextures(source.materials, !m.texcoords.empty(), name, source.stats);
}

void checkTextures(std::vector<Material>& materials, bool hasTexcoords, const std::string& name, ReadStats& stats) {
    for (Material& material : materials) {
        if (material.texturePath.empty() && !material.image) continue;
        if (!hasTexcoords) {  // a warning apart from the textures rule, which --strict let pass, until stop 46
            stats.textureProblems.push_back({name + ": texture '" + material.texturePath +
                                                 "' cannot be mapped: not every face has texture coordinates",
                                             material.name});
        } else if (material.image) {
            continue;  // embedded, already decoded
        } else if (const std::string problem = textureProblem(material.texturePath); !problem.empty()) {
            stats.textureProblems.push_back({name + ": texture '" + material.texturePath + "' " + problem, material.name});
        } else {
            continue;
        }
        material.texturePath.clear();
        material.image.reset();
    }
}

SourceMesh readMesh(const std::string& path, const ReadOptions& options) {
    const std::string ext = meshExtension(path);
    if (!fs::exists(path)) throw InputError(path + ": no such file");
    if (ext == ".ply") return readPly(path, options);
    if (ext == ".obj") return readObj(path, options);
    if (ext == ".gltf" || ext == ".glb") return readGltf(path, options);
    throw InputError(path + ": unsupported format '" + ext + "' (expected .ply, .obj, .gltf or .glb)");
}

}  // namespace hlod
