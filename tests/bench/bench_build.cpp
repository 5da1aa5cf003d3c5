// Benchmark of `hlod build`: for a ~1 M triangle real scan (Lucy 100k, midpoint-
// subdivided twice: 1.6 M) and a ~17 M triangle single generated terrain mesh (one PLY, so the
// out-of-core read and block split are measured too), runs the build in a child process and prints input triangles per CPU-second, wall time, peak RSS
// (the child's ru_maxrss) and output bytes per input triangle, then per level the largest and the
// mean geometric error the build stored (error.cpp's two-sided distance, or with --bottom-up-error
// simplifier meshoptimizer's estimate; input units).
// Reference (nxsbuild, same kind of machine): 43-58 k tri/CPU-s, 30.5 B/tri, ~430 MB RSS.
//   hlod_bench_build [--dir DIR] [--sizes 1,17] [--simplifier meshopt|openmesh|both]
//                    [--mode top-down|bottom-up|both] [--bottom-up-error bound|exact|simplifier]
//                    [-j N] [--memory-limit BYTES]
#include "formats/cli/huge_pages.h"
#include "pipeline/pipeline.h"
#include "tests/support/child_usage.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

namespace fs = std::filesystem;
using namespace hlod;

namespace {

void writePly(const std::string& path, const MeshData& m) {
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << m.vertexCount()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << m.triangleCount()
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    out.write(reinterpret_cast<const char*>(m.positions.data()), static_cast<std::streamsize>(m.positions.size() * 4));
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const unsigned char three = 3;
        out.write(reinterpret_cast<const char*>(&three), 1);
        out.write(reinterpret_cast<const char*>(&m.indices[3 * t]), 12);
    }
}

// Midpoint subdivision, 1 triangle -> 4, new vertices shared through an edge map.
MeshData subdivide(const MeshData& m) {
    MeshData out;
    out.positions = m.positions;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto middle = [&](uint32_t a, uint32_t b) {
        auto [it, added] = mid.try_emplace({std::min(a, b), std::max(a, b)}, static_cast<uint32_t>(out.vertexCount()));
        if (added)
            for (int k = 0; k < 3; ++k) out.positions.push_back(0.5f * (m.positions[3 * a + k] + m.positions[3 * b + k]));
        return it->second;
    };
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t a = m.indices[3 * t], b = m.indices[3 * t + 1], c = m.indices[3 * t + 2];
        const uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
        out.indices.insert(out.indices.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    return out;
}

// An n x n-quad wavy terrain over 100 n / 707 units, written row by row (never held whole).
void writeTerrainPly(const std::string& path, uint32_t n) {
    std::ofstream out(path, std::ios::binary);
    const uint64_t vertices = uint64_t(n + 1) * (n + 1), triangles = 2ull * n * n;
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << vertices
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << triangles
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    const float size = 100.0f * n / 707;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            const float x = size * i / n, y = size * j / n;
            const float p[3] = {x, y, 3 * std::sin(x * 0.13f) * std::cos(y * 0.07f) + 0.2f * std::sin(x * 1.7f + y)};
            out.write(reinterpret_cast<const char*>(p), sizeof p);
        }
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            const unsigned char three = 3;
            for (const std::array<uint32_t, 3>& tri : {std::array<uint32_t, 3>{a, b, d}, std::array<uint32_t, 3>{a, d, c}}) {
                out.write(reinterpret_cast<const char*>(&three), 1);
                out.write(reinterpret_cast<const char*>(tri.data()), 12);
            }
        }
}

std::string prepare(const std::string& dir, int size) {
    fs::create_directories(dir);
    if (size == 1) {
        const std::string path = dir + "/lucy_1m6.ply";
        if (fs::exists(path)) return path;
        MeshData m = readMesh(std::string(HLOD_SHARED_DIR) + "/datasets/A3_stanford_lucy_100k/Lucy100k.ply").piece.mesh;
        m.texcoords.clear(), m.normals.clear(), m.colors.clear();
        writePly(path, subdivide(subdivide(m)));
        return path;
    }
    const std::string path = dir + "/terrain_" + std::to_string(size) + "m.ply";
    if (!fs::exists(path)) writeTerrainPly(path, static_cast<uint32_t>(std::lround(std::sqrt(size * 1e6 / 2))));
    return path;
}

struct Result {
    double wall = 0, cpu = 0;
    uint64_t peakRss = 0, triangles = 0, bytes = 0;
    std::string errors;  // per level, from the build's measures
};

Result runChild(const std::string& input, const std::string& output, Simplifier simplifier, BuildMode mode,
                BottomUpError error, int jobs, uint64_t memoryLimit) {
    const test::ChildUsage child = test::runInChild([&] {
        std::ostringstream log;
        Progress progress(log, false);
        BuildRequest r;
        r.input = input, r.output = output;
        r.options.simplifier = simplifier, r.options.jobs = jobs, r.options.mode = mode, r.options.bottomUpError = error;
        if (memoryLimit) r.options.memoryLimit = memoryLimit;
        const BuildSummary s = runBuild(r, progress);
        std::ofstream(output + ".tris") << s.inputTriangles;
        std::vector<double> worst, sum, count;  // per level, non-leaf nodes (leaves measure 0)
        for (const NodeQuality& n : s.nodes) {
            if (n.errorMax <= 0) continue;
            if (worst.size() <= n.level) worst.resize(n.level + 1), sum.resize(n.level + 1), count.resize(n.level + 1);
            worst[n.level] = std::max(worst[n.level], n.errorMax), sum[n.level] += n.errorMax, ++count[n.level];
        }
        std::ofstream errors(output + ".errors");
        for (size_t l = 0; l < worst.size(); ++l)
            if (count[l] > 0) errors << "  level " << l << ": error max " << worst[l] << ", mean of nodes " << sum[l] / count[l] << "\n";
    });
    Result res;
    res.wall = child.wall, res.cpu = child.cpu, res.peakRss = child.peakRss;
    if (!child.ok) return res;
    std::ifstream(output + ".tris") >> res.triangles;
    std::ifstream errors(output + ".errors");
    res.errors.assign(std::istreambuf_iterator<char>(errors), {});
    res.bytes = fs::file_size(output);
    return res;
}

int usage(const char* why, int status = 2) {
    std::fprintf(status ? stderr : stdout, "hlod_bench_build: %s\nusage: hlod_bench_build [--dir DIR] [--sizes 1,17] [--simplifier meshopt|openmesh|both]\n"
                         "  [--mode top-down|bottom-up|both] [--bottom-up-error bound|exact|simplifier] [-j N] [--memory-limit BYTES]\n", why);
    return status;
}

}  // namespace

int main(int argc, char** argv) {
    hlod::cli::reexecWithHugePages(argv);  // as `hlod` does: its builds run in this process's children
    std::string dir = (fs::temp_directory_path() / "hlod-bench").string(), sizes = "1,17", which = "both", modes = "top-down";
    std::string errorName = "bound";
    int jobs = 0;
    uint64_t memoryLimit = 0;  // bytes; 0 = the build's default (1 GiB)
    for (int i = 1; i < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") return usage("builds the inputs (written into DIR when absent) and prints figures", 0);
        if (i + 1 == argc) return usage((a + " needs a value").c_str());
        if (a == "--dir") dir = argv[i + 1];
        else if (a == "--sizes") sizes = argv[i + 1];
        else if (a == "--simplifier") which = argv[i + 1];
        else if (a == "--mode") modes = argv[i + 1];
        else if (a == "--bottom-up-error") errorName = argv[i + 1];
        else if (a == "-j") jobs = std::atoi(argv[i + 1]);
        else if (a == "--memory-limit") memoryLimit = std::strtoull(argv[i + 1], nullptr, 10);
        else return usage(("unknown option " + a).c_str());
    }
    BottomUpError error = BottomUpError::Bound;
    if (!parseBottomUpError(errorName, error)) return usage("bad --bottom-up-error");
    std::printf("%-22s %-9s %-20s %12s %9s %9s %14s %10s %8s\n", "input", "simplify", "mode", "input tris", "wall s", "CPU s",
                "tri/CPU-s", "peak RSS", "B/tri");
    std::stringstream list(sizes);
    for (std::string item; std::getline(list, item, ',');) {
        const int size = std::atoi(item.c_str());
        const std::string input = prepare(dir, size);
        for (Simplifier s : {Simplifier::Meshopt, Simplifier::OpenMesh}) {
            const bool isMeshopt = s == Simplifier::Meshopt;
            if ((which == "meshopt" && !isMeshopt) || (which == "openmesh" && isMeshopt)) continue;
            if (!isMeshopt && size > 1 && which == "both") continue;  // ~50 k tri/s: 1 M only
            for (BuildMode mode : {BuildMode::TopDown, BuildMode::BottomUp}) {
                if (modes != "both" && modes != buildModeName(mode)) continue;
                const bool bottomUp = mode == BuildMode::BottomUp;
                if (bottomUp && !isMeshopt && error == BottomUpError::Simplifier) continue;  // refused: meshopt only
                const std::string modeName = std::string(buildModeName(mode)) + (bottomUp ? std::string("/") + bottomUpErrorName(error) : "");
                const Result r = runChild(input, dir + "/out.hlod", s, mode, error, jobs, memoryLimit);
                std::printf("%-22s %-9s %-20s %12llu %9.1f %9.1f %14.0f %7.0f MB %8.2f\n%s", fs::path(input).filename().c_str(),
                            isMeshopt ? "meshopt" : "openmesh", modeName.c_str(), static_cast<unsigned long long>(r.triangles),
                            r.wall, r.cpu, r.cpu > 0 ? r.triangles / r.cpu : 0.0, r.peakRss / 1e6,
                            r.triangles ? double(r.bytes) / r.triangles : 0.0, r.errors.c_str());
            }
            std::fflush(stdout);
        }
    }
    return 0;
}
