// The closest-point queries' cost (pipeline/closest_point.h squaredDistance and largestDistance:
// the geometric error's and the texture baker's queries, issue #14's speed goals,
// pipeline/CLOSEST_POINT.md). On a mesh of yours (PLY, OBJ or glTF), for
// hierarchies of its first 1/64, 1/8 and all triangles:
// - `hinted`: one query per triangle, at its centroid moved off the surface by up to 1/2 of its
//   longest edge (a fixed pseudo-random sequence), in the mesh's order, each seeded by the previous
//   answer, as the baker queries texel after texel;
// - `largest`: largestDistance of the `hinted` points, as the error measures a node;
// - `near`: ten queries per triangle, on a grid over it (barycentric (i + 0.3) / 4.5,
//   (j + 0.3) / 4.5, i + j < 4) moved off the surface by +-1/4 of its longest edge, in the mesh's
//   order, each seeded by the previous answer: most answers are the hint's triangle, as in the
//   baker (the 4:2:0 facade's: 70 % answer their hint's triangle, 88 % lie within 1/4 of its
//   longest edge; pipeline/TEXTURE_SPEED_ROUND9.md).
// For the hinted patterns, the share of queries whose answer is their hint's triangle.
// CPU time per query or per point, the best of --repeat runs, and a checksum of the answers (the
// distances and triangles found), so a faster query can be checked to give the same answers.
// The heap on 2 MiB pages as in `hlod` (HLOD_HUGE_PAGES=0: 4 KiB pages).
//
//   bench_closest_point MESH [--repeat N]
#include "formats/cli/huge_pages.h"
#include "pipeline/closest_point.h"
#include "pipeline/pipeline.h"

#include <xxhash.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

namespace {

double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// One point per triangle of `indices`: its centroid moved along its normal by up to half its
// longest edge; or (`near`) ten on a grid over it, moved by +-1/4 of its longest edge.
std::vector<double> queryPoints(const std::vector<float>& positions, const std::vector<uint32_t>& indices, bool near) {
    std::vector<double> points;
    uint32_t state = 7;
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        double v[3][3];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) v[j][k] = positions[3 * size_t(indices[t + j]) + k];
        double e[3][3], n[3], longest = 0;
        for (int j = 0; j < 3; ++j) {
            double l = 0;
            for (int k = 0; k < 3; ++k) e[j][k] = v[(j + 1) % 3][k] - v[j][k], l += e[j][k] * e[j][k];
            longest = std::max(longest, std::sqrt(l));
        }
        n[0] = e[0][1] * e[2][2] - e[0][2] * e[2][1], n[1] = e[0][2] * e[2][0] - e[0][0] * e[2][2], n[2] = e[0][0] * e[2][1] - e[0][1] * e[2][0];
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (length == 0) continue;
        if (near) {
            for (int i = 0; i < 4; ++i)
                for (int j = 0; i + j < 4; ++j) {
                    const double b = (i + 0.3) / 4.5, c = (j + 0.3) / 4.5, off = ((i + j) % 2 ? 0.25 : -0.25) * longest / length;
                    for (int k = 0; k < 3; ++k) points.push_back((1 - b - c) * v[0][k] + b * v[1][k] + c * v[2][k] + off * n[k]);
                }
            continue;
        }
        state = state * 1664525u + 1013904223u;
        const double off = 0.5 * longest * (double(state >> 8) / double(1u << 24) * 2 - 1) / length;
        for (int k = 0; k < 3; ++k) points.push_back((v[0][k] + v[1][k] + v[2][k]) / 3 + off * n[k]);
    }
    return points;
}

}  // namespace

int main(int argc, char** argv) {
    hlod::cli::reexecWithHugePages(argv);
    int repeat = 3;
    const char* path = nullptr;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
        else if (!path && argv[i][0] != '-') path = argv[i];
        else return std::fprintf(stderr, "usage: bench_closest_point MESH [--repeat N]\n"), 2;
    }
    if (!path) return std::fprintf(stderr, "usage: bench_closest_point MESH [--repeat N]\n"), 2;
    hlod::SourceMesh source;
    try {
        source = hlod::readMesh(path);
    } catch (const std::exception& e) {
        return std::fprintf(stderr, "%s\n", e.what()), 2;
    }
    const hlod::MeshData& mesh = source.piece.mesh;
    std::printf("%-10s %-8s %12s %12s %10s   %-16s   %s\n", "triangles", "queries", "count", "CPU-ms", "ns each", "checksum", "answer = hint");
    for (const size_t share : {64u, 8u, 1u}) {
        const std::vector<uint32_t> indices(mesh.indices.begin(), mesh.indices.begin() + 3 * (mesh.triangleCount() / share));
        const hlod::TriangleBvh bvh = hlod::buildTriangleBvh(mesh.positions, indices);
        const std::vector<double> centroids = queryPoints(mesh.positions, indices, false), grid = queryPoints(mesh.positions, indices, true);
        for (const char* pattern : {"hinted", "largest", "near"}) {
            const bool largest = std::strcmp(pattern, "largest") == 0;
            const std::vector<double>& points = std::strcmp(pattern, "near") == 0 ? grid : centroids;  // `largest` queries the `hinted` points
            const size_t count = points.size() / 3;
            double best = 1e30;
            uint64_t checksum = 0;
            size_t kept = 0;  // hinted queries answered by their hint's triangle
            for (int r = 0; r < repeat; ++r) {
                const double start = cpuSeconds();
                XXH3_state_t* hash = XXH3_createState();
                XXH3_64bits_reset(hash);
                if (largest) {
                    double sum = 0;
                    std::vector<std::array<double, 3>> reordered(count);  // largestDistance reorders them
                    for (size_t q = 0; q < count; ++q) std::copy_n(&points[3 * q], 3, reordered[q].begin());
                    const double worst = hlod::largestDistance(bvh, reordered, sum);
                    XXH3_64bits_update(hash, &worst, sizeof worst), XXH3_64bits_update(hash, &sum, sizeof sum);
                } else {
                    uint32_t hint = ~0u;
                    kept = 0;
                    for (size_t q = 0; q < count; ++q) {
                        const uint32_t before = hint;
                        const double d = hlod::squaredDistance(bvh, &points[3 * q], hint);
                        kept += hint == before;
                        XXH3_64bits_update(hash, &d, sizeof d), XXH3_64bits_update(hash, &hint, sizeof hint);
                    }
                }
                best = std::min(best, cpuSeconds() - start);
                checksum = XXH3_64bits_digest(hash);
                XXH3_freeState(hash);
            }
            std::printf("%-10zu %-8s %12zu %12.1f %10.1f   %016llx", bvh.input.size(), pattern, count, 1e3 * best,
                        1e9 * best / double(count), (unsigned long long)checksum);
            if (!largest) std::printf("   %5.1f %%", 100.0 * double(kept) / double(count));
            std::printf("\n");
        }
    }
    return 0;
}
