// Triangles the position lattice flattens (lattice_flattened.h): the corners rounded as the codec
// rounds them (round(x / step), codec_draco.cpp), their edge vectors' cross product tested for zero.
// Exact: a block spans at most 2^23 steps, so the products stay below 2^48 in doubles.
#include "pipeline/lattice_flattened.h"

#include "pipeline/pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace hlod {

uint64_t latticeFlattened(const MeshData& mesh, double step) {
    if (!(step > 0)) return 0;
    const double lattice = std::ldexp(1.0, std::ilogb(step));
    const auto corner = [&](uint32_t vertex, double q[3]) {
        for (int k = 0; k < 3; ++k) q[k] = std::round(double(mesh.positions[3 * size_t(vertex) + k]) / lattice);
    };
    uint64_t flattened = 0;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        double a[3], b[3], c[3];
        corner(mesh.indices[3 * t], a), corner(mesh.indices[3 * t + 1], b), corner(mesh.indices[3 * t + 2], c);
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        if (u[1] * v[2] - u[2] * v[1] == 0 && u[2] * v[0] - u[0] * v[2] == 0 && u[0] * v[1] - u[1] * v[0] == 0) ++flattened;
    }
    return flattened;
}

std::string latticeFlattenedWarning(const std::string& input, uint64_t flattened, uint64_t triangles) {
    if (triangles == 0 || double(flattened) <= kFlattenedWarning * double(triangles)) return "";
    std::vector<char> text(input.size() + 512);
    std::snprintf(text.data(), text.size(),
                  "%s: the position lattice flattens %llu of its %llu triangles (%.1f %%) to lines or points: the model "
                  "is thinner or finer than the lattice's steps; build with more --draco-position-bits or a finer "
                  "--draco-position-step to keep them, or a smaller --block-size when parts far apart share a block "
                  "(one lattice spans its block)",
                  input.c_str(), static_cast<unsigned long long>(flattened), static_cast<unsigned long long>(triangles),
                  100.0 * double(flattened) / double(triangles));
    return text.data();
}

std::string floatPrecisionOfFiles(const std::string& input, std::span<const BlockStats> files, const std::array<double, 3>& offset) {
    if (files.empty()) return "";
    Box3f all = files[0].fileBounds;
    double step = 0;
    uint32_t over = 0;
    for (const BlockStats& file : files) {
        const Box3f& f = file.fileBounds;
        all.min = {std::min(all.min.x, f.min.x), std::min(all.min.y, f.min.y), std::min(all.min.z, f.min.z)};
        all.max = {std::max(all.max.x, f.max.x), std::max(all.max.y, f.max.y), std::max(all.max.z, f.max.z)};
        if (file.floatStepOver > 0) step = over++ ? std::min(step, file.floatStepOver) : file.floatStepOver;
    }
    if (!over) return "";  // a single mesh's cells set no floatStepOver
    return floatPrecisionWarning(input + " (" + std::to_string(over) + " of its " + std::to_string(files.size()) + " files)", all, step,
                                 offset);
}

}  // namespace hlod
