// UV charts moved into the texture by whole periods of its wrap mode. A texture coordinate
// beyond [0, 1] samples the texture as its sampler says: glTF 2.0 §3.8.4.6 (Samplers: wrapS,
// wrapT; REPEAT when none is given, MIRRORED_REPEAT, CLAMP_TO_EDGE), and in an OBJ's MTL the map
// option `-clamp on|off` (off, i.e. repeat, by default; Wavefront MTL specification). Node atlases
// copy the blocks a chart reaches on the texture's own grid (texture.cpp) and the player samples
// them clamped, so a chart drawn from a repeat of the texture (UVs in [k, k + 1]) is moved by -k,
// which samples the same texels: REPEAT repeats every 1, MIRRORED_REPEAT every 2. A chart that
// straddles a period's edge would need its triangles cut there; it stays as it is (its UVs then
// read the texture's border blocks, as before this pass), as does one under CLAMP_TO_EDGE.
#include "pipeline/texture_charts.h"

#include <cmath>

namespace hlod {

namespace {

// The whole periods to subtract from an axis whose coordinates span [lo, hi]: 0 when the span
// lies in [0, 1] already, does not fit into one period's [0, 1] window, or does not repeat.
double shiftOf(double lo, double hi, float period) {
    if (period <= 0 || (lo >= 0 && hi <= 1)) return 0;
    const double k = std::floor(lo / period) * period;
    return hi - k <= 1 ? k : 0;
}

}  // namespace

void wrapUvCharts(Piece& piece, const std::vector<Material>& materials) {
    MeshData& mesh = piece.mesh;
    if (mesh.texcoords.empty()) return;
    uint32_t count = 0;
    const std::vector<uint32_t> chart = uvCharts(mesh, count);
    std::vector<const Material*> materialOf(count, nullptr);  // welded: a chart's vertices serve one material
    for (size_t t = 0; t < mesh.triangleCount(); ++t)
        if (piece.materials[t] < materials.size()) materialOf[chart[mesh.indices[3 * t]]] = &materials[piece.materials[t]];
    std::vector<double> lo(2 * size_t(count), INFINITY), hi(2 * size_t(count), -INFINITY);
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a) {
            const double c = mesh.texcoords[2 * v + a];
            lo[2 * chart[v] + a] = std::fmin(lo[2 * chart[v] + a], c), hi[2 * chart[v] + a] = std::fmax(hi[2 * chart[v] + a], c);
        }
    std::vector<double> shift(2 * size_t(count), 0);
    for (uint32_t c = 0; c < count; ++c)
        if (const Material* m = materialOf[c]; m && (m->image || !m->texturePath.empty()))
            for (int a = 0; a < 2; ++a) shift[2 * c + a] = shiftOf(lo[2 * c + a], hi[2 * c + a], m->uvPeriod[a]);
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a)
            if (const double k = shift[2 * chart[v] + a]; k != 0) mesh.texcoords[2 * v + a] = static_cast<float>(mesh.texcoords[2 * v + a] - k);
}

}  // namespace hlod
