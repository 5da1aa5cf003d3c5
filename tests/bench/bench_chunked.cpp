// Chunked multi-atlas scans (issue #16): writes the chunked inputs of tests/support/chunked_scan.h
// (a generated facade, and the Stanford bunny when given, each with one chart per chunk and with
// fragmented charts) into OUTDIR/<name>/<name>.obj, so `hlod build` of any version can be run on
// them, then builds each as one block (buildBlock) and prints per level: nodes, triangles against
// the §3.2 target, nodes simplified as geometry only (baked) and their smallest PSNR, texels,
// and the one-sided, two-sided (max)
// and mean geometric error (error.cpp). Figures in pipeline/TREE.md "Chunked multi-atlas scans".
// Usage: bench_chunked OUTDIR [bun_zipper.ply]
#include "pipeline/pipeline.h"
#include "tests/support/chunked_scan.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

using namespace hlod;

namespace {

void report(const std::string& name, const std::string& obj) {
    const SourceMesh source = readObj(obj);
    struct Level {
        uint64_t nodes = 0, triangles = 0, maxTriangles = 0, baked = 0, texels = 0;
        double minPsnr = 0;
        double oneSided = 0, twoSided = 0, mean = 0;
    };
    std::vector<Level> levels;
    struct Node {
        uint32_t level;
        uint64_t triangles, texels;
    };
    std::vector<Node> nodes;
    const BlockStats stats = buildBlock(source.piece, source.materials, 0, BuildOptions{}, nullptr, [&](NodeRecord&& r) {
        uint64_t triangles = 0, texels = 0;
        for (const EncodedBlob& b : r.node.blobs) {
            if (b.info.kind == BlobKind::Geometry) triangles += b.info.triangles;
            else texels += uint64_t(b.info.width) * b.info.height;
        }
        nodes.push_back({r.node.level, triangles, texels});
    });
    for (size_t i = 0; i < nodes.size(); ++i) {
        const auto [level, triangles, texels] = nodes[i];
        if (levels.size() <= level) levels.resize(level + 1);
        Level& L = levels[level];
        const SurfaceError& e = stats.measured[i];
        ++L.nodes, L.triangles += triangles, L.maxTriangles = std::max(L.maxTriangles, triangles), L.baked += stats.baked[i];
        L.texels += texels;
        if (stats.baked[i]) L.minPsnr = L.minPsnr > 0 ? std::min(L.minPsnr, double(stats.bakePsnr[i])) : stats.bakePsnr[i];
        L.oneSided = std::max(L.oneSided, e.oneSided), L.twoSided = std::max(L.twoSided, e.max), L.mean += e.mean;
    }
    const Constants c;
    const double input = double(source.piece.mesh.triangleCount());
    std::printf("%s: %s, %.0f triangles, %zu materials\n", name.c_str(), obj.c_str(), input, source.materials.size());
    std::printf("%5s %6s %9s %9s %6s %8s %6s %9s %10s %10s %10s %10s\n", "level", "nodes", "tris", "target", "ratio", "max/node",
                "baked", "min PSNR", "texels", "err 1-side", "err 2-side", "err mean");
    for (size_t l = 0; l < levels.size(); ++l) {
        const Level& L = levels[l];
        const double factor = input / c.desiredTris / std::pow(c.levelFactor, double(l));
        const double target = factor > 1 ? input / factor : input;
        std::printf("%5zu %6llu %9llu %9.0f %6.2f %8llu %6llu %9.1f %10llu %10.4f %10.4f %10.5f%s\n", l, (unsigned long long)L.nodes,
                    (unsigned long long)L.triangles, target, double(L.triangles) / target, (unsigned long long)L.maxTriangles,
                    (unsigned long long)L.baked, L.minPsnr, (unsigned long long)L.texels, L.oneSided, L.twoSided, L.mean / double(L.nodes), factor > 1 ? "" : "  (leaves)");
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_chunked OUTDIR [bun_zipper.ply]\n");
        return 2;
    }
    const std::filesystem::path out = argv[1];
    std::vector<std::pair<std::string, MeshData>> meshes{{"facade", facadeMesh(250)}};
    if (argc > 2) meshes.emplace_back("bunny", readPly(argv[2]).piece.mesh);
    for (const auto& [name, mesh] : meshes)
        for (uint32_t chartCells : {1u, 4u}) {
            ChunkedScanOptions options;
            options.chartCells = chartCells;
            const std::string folder = name + (chartCells > 1 ? "-fragmented" : "");
            std::filesystem::create_directories(out / folder);
            const ChunkedScan scan = writeChunkedScan((out / folder).string(), folder, mesh, options);
            std::printf("\n%s: %u chunks, %u charts, %llu duplicated vertices\n", folder.c_str(), scan.chunks, scan.charts,
                        (unsigned long long)scan.duplicatedVertices);
            report(folder, scan.obj);
        }
    return 0;
}
