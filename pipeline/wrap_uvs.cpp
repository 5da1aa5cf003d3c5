// UV charts moved into the texture by whole periods of its wrap mode. A texture coordinate
// beyond [0, 1] samples the texture as its sampler says: glTF 2.0 §3.8.4.6 (Samplers: wrapS,
// wrapT; REPEAT when none is given, MIRRORED_REPEAT, CLAMP_TO_EDGE), and in an OBJ's MTL the map
// option `-clamp on|off` (off, i.e. repeat, by default; Wavefront MTL specification). Node atlases
// copy the blocks a chart reaches on the texture's own grid (texture.cpp) and the player samples
// them clamped, so a chart drawn from a repeat of the texture (UVs in [k, k + 1]) is moved by -k,
// which samples the same texels: REPEAT repeats every 1, MIRRORED_REPEAT every 2, its odd periods
// mirrored (u in [2j + 1, 2j + 2] reads 2j + 2 - u; until stop 46 they were sampled clamped). A
// chart that straddles a period's edge would need its triangles cut there; it stays as it is (its
// UVs then read the texture's border blocks, as before this pass) and is counted, so the build can
// say so; one under CLAMP_TO_EDGE stays as it is, as its sampler says.
#include "pipeline/texture_charts.h"

#include <cmath>

namespace hlod {

namespace {

// An axis's map into [0, 1]: u' = sign u + offset. The identity when the span [lo, hi] lies in
// [0, 1] already or the texture does not repeat; `straddles` when the span crosses a period's edge.
struct AxisMap {
    double sign = 1, offset = 0;
    bool straddles = false;
};

AxisMap axisMap(double lo, double hi, float period) {
    if (period <= 0 || (lo >= 0 && hi <= 1)) return {};
    const double k = std::floor(lo / period) * period;  // the period's start
    if (hi - k <= 1) return {1, -k, false};
    if (period == 2 && lo - k >= 1 && hi - k <= 2) return {-1, k + 2, false};  // MIRRORED_REPEAT's mirrored half
    return {1, 0, true};
}

}  // namespace

uint32_t wrapUvCharts(Piece& piece, const std::vector<Material>& materials) {
    MeshData& mesh = piece.mesh;
    if (mesh.texcoords.empty()) return 0;
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
    std::vector<AxisMap> map(2 * size_t(count));
    uint32_t straddling = 0;
    for (uint32_t c = 0; c < count; ++c)
        if (const Material* m = materialOf[c]; m && (m->image || !m->texturePath.empty())) {
            for (int a = 0; a < 2; ++a) map[2 * c + a] = axisMap(lo[2 * c + a], hi[2 * c + a], m->uvPeriod[a]);
            straddling += map[2 * c].straddles || map[2 * c + 1].straddles;
        }
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a)
            if (const AxisMap& k = map[2 * chart[v] + a]; k.sign != 1 || k.offset != 0)
                mesh.texcoords[2 * v + a] = static_cast<float>(k.sign * mesh.texcoords[2 * v + a] + k.offset);
    return straddling;
}

}  // namespace hlod
