// Benchmark of texture baking (pipeline/bake.cpp; figures in pipeline/BAKE.md): time, PSNR and
// covered texels of bakeTexture for
//   - a generated node: a 128 x 128-quad wavy terrain (32,768 triangles, two materials with smooth
//     1024^2 textures) simplified to ~900 triangles, baked into 256^2 texels;
//   - the banana scan (../shared/datasets/A2_ycb_011_banana_textured_scan, 15,728 triangles, one
//     4096^2 atlas), welded by position (so UV seams do not stop simplification) and simplified
//     20x, baked into 4096^2 / 20 texels (the texel count texture.cpp's downsampling would give)
//     and into 256^2;
// and the chart count of the banana node for normal cones of 30-70 degrees. Beside the baker's
// own PSNR, a reference PSNR against each sub-sample's own closest original point
// (bake_reference.h), which a cheaper correspondence cannot raise by taking smoother colours.
//   hlod_bench_bake [--runs N]   (median CPU time of N runs, default 9; single thread)
#include "pipeline/chart.h"
#include "pipeline/pipeline.h"
#include "tests/bench/bake_reference.h"
#include "tests/support/synthetic.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <time.h>

using namespace hlod;

namespace {

// n x n quads over [0, 100]^2, u = x / 100, v = y / 100; material 1 for x >= 50.
Piece terrain(uint32_t n) {
    Piece p;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            const float x = 100.0f * i / n, y = 100.0f * j / n;
            p.mesh.positions.insert(p.mesh.positions.end(), {x, y, 2.0f * std::sin(x * 0.11f) * std::cos(y * 0.07f)});
            p.mesh.texcoords.insert(p.mesh.texcoords.end(), {x / 100, y / 100});
        }
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            p.mesh.indices.insert(p.mesh.indices.end(), {a, b, d, a, d, c});
            p.materials.insert(p.materials.end(), 2, 2 * i >= n ? 1u : 0u);
        }
    return p;
}

// Positions and indices only, vertices welded by exact position.
MeshData weldByPosition(const MeshData& m) {
    MeshData out;
    std::map<std::array<float, 3>, uint32_t> ids;
    for (uint32_t v : m.indices) {
        const std::array<float, 3> p = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
        auto [it, added] = ids.emplace(p, static_cast<uint32_t>(ids.size()));
        if (added) out.positions.insert(out.positions.end(), p.begin(), p.end());
        out.indices.push_back(it->second);
    }
    return out;
}

double medianMs(int runs, const std::function<void()>& f) {
    std::vector<double> ms;
    for (int i = 0; i < runs; ++i) {
        timespec t0{}, t1{};  // CPU time: the machine is shared, wall time would count the others' load
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t0);
        f();
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t1);
        ms.push_back((t1.tv_sec - t0.tv_sec) * 1e3 + (t1.tv_nsec - t0.tv_nsec) * 1e-6);
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

// Charts of the triangles bakeTexture keeps (the non-zero-area ones).
size_t chartCount(const MeshData& m, double cone = kChartConeDegrees) {
    MeshData solid;
    solid.positions = m.positions;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t* i = &m.indices[3 * t];
        if (!zeroArea(&m.positions[3 * i[0]], &m.positions[3 * i[1]], &m.positions[3 * i[2]])) solid.indices.insert(solid.indices.end(), i, i + 3);
    }
    return flattenCharts(solid, cone).size();
}

void report(const char* name, const MeshData& simplified, const std::vector<BakeSource>& sources, uint64_t budget, int runs) {
    BakedTexture baked;
    const double ms = medianMs(runs, [&] { baked = bakeTexture(simplified, sources, budget); });
    uint64_t original = 0;
    for (const BakeSource& s : sources) original += s.mesh->triangleCount();
    std::printf("%-26s %7zu tri (original %7llu) budget %8llu: atlas %4ux%-4u covered %7llu (%4.1f %%), %3zu charts, "
                "PSNR %5.2f dB (reference %5.2f dB), %6.1f CPU-ms\n",
                name, simplified.triangleCount(), static_cast<unsigned long long>(original), static_cast<unsigned long long>(budget),
                baked.image.width, baked.image.height, static_cast<unsigned long long>(baked.coveredTexels),
                100.0 * double(baked.coveredTexels) / (double(baked.image.width) * baked.image.height), chartCount(simplified),
                baked.psnr, bench::referencePsnr(baked, sources), ms);
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 9;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else return std::fprintf(stderr, "usage: hlod_bench_bake [--runs N]\n"), 2;
    }
    const Piece piece = terrain(128);
    const std::vector<SubMesh> parts = splitByMaterial(piece);
    const std::vector<Image> images = {smoothTexture(1024, 0), smoothTexture(1024, 1)};
    const MeshData node = simplifyMesh(weldByPosition(piece.mesh), piece.mesh.triangleCount() / 900.0, Simplifier::Meshopt);
    const std::vector<BakeSource> terrainSources = {{&parts[0].mesh, &images[0]}, {&parts[1].mesh, &images[1]}};
    report("terrain node", node, terrainSources, 256 * 256, runs);
    report("terrain node", node, terrainSources, 128 * 128, runs);
    report("terrain node", node, terrainSources, 32 * 32, runs);

    const std::string banana = std::string(HLOD_SHARED_DIR) + "/datasets/A2_ycb_011_banana_textured_scan/textured_simple_reoriented.obj";
    if (!std::filesystem::exists(banana)) return std::printf("no %s: banana skipped\n", banana.c_str()), 0;
    const SourceMesh scan = readObj(banana);
    const Image atlas = loadTexture(scan.materials.at(0).texturePath);
    const MeshData coarse = simplifyMesh(weldByPosition(scan.piece.mesh), 20, Simplifier::Meshopt);
    const std::vector<BakeSource> bananaSources = {{&scan.piece.mesh, &atlas}};
    report("banana 20x", coarse, bananaSources, uint64_t(atlas.width) * atlas.height / 20, runs);
    report("banana 20x", coarse, bananaSources, 256 * 256, runs);
    for (double cone : {30.0, 40.0, 50.0, 60.0, 70.0})
        std::printf("banana 20x: normal cone %2.0f deg -> %zu charts\n", cone, chartCount(coarse, cone));
    return 0;
}
