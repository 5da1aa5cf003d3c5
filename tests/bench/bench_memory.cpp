// Benchmark of `hlod build`'s memory bound (issue #14) on a textured scan like real
// photogrammetry deliveries (41-80 x 4K JPEG atlases, ~1 M triangles): writes a chunked scan
// (tests/support/chunked_scan.h: a generated facade, one material and one JPEG atlas per chunk,
// fragmented charts) into DIR once, then builds it in a child process per --memory-limit and
// prints the child's peak RSS (ru_maxrss) against the limit, the memory gate's largest
// estimate (BuildSummary::gatePeak), CPU time, source texels per CPU-second and input triangles
// per CPU-second. Figures in pipeline/MEMORY.md.
//   bench_memory [--dir DIR] [--chunks 40] [--texture 4096] [--facade 1000] [--charts 4]
//                [--limits 256M,512M,1G,default] [-j N] [--input FILE]
// --input builds FILE (any input hlod builds) instead of the generated scan.
#include "pipeline/pipeline.h"
#include "tests/support/child_usage.h"
#include "tests/support/chunked_scan.h"


#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

namespace fs = std::filesystem;
using namespace hlod;

namespace {

uint64_t parseBytes(const std::string& s) {
    if (s == "default") return 0;
    const double v = std::strtod(s.c_str(), nullptr);
    const char unit = s.empty() ? 0 : s.back();
    const double scale = unit == 'G' ? 1 << 30 : unit == 'M' ? 1 << 20 : unit == 'K' ? 1 << 10 : 1;
    return static_cast<uint64_t>(v * scale);
}

// Texels of the input's textures (their headers), the figure texels per CPU-second divides.
uint64_t sourceTexels(const std::string& input) {
    uint64_t texels = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(input).parent_path())) {
        const std::string ext = entry.path().extension().string();
        if (ext == ".jpg" || ext == ".png") texels += textureTexels(entry.path().string());
    }
    return texels;
}

}  // namespace

int main(int argc, char** argv) {
    std::string dir = (fs::temp_directory_path() / "hlod-bench-memory").string(), limits = "256M,512M,1G,default", input;
    ChunkedScanOptions scan;
    scan.chunks = 40, scan.textureSize = 4096, scan.chartCells = 4, scan.jpeg = true;
    uint32_t facade = 1000;
    int jobs = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--dir") dir = v;
        else if (a == "--chunks") scan.chunks = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--texture") scan.textureSize = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--facade") facade = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--charts") scan.chartCells = static_cast<uint32_t>(std::atoi(v.c_str()));
        else if (a == "--limits") limits = v;
        else if (a == "-j") jobs = std::atoi(v.c_str());
        else if (a == "--input") input = v;
    }
    if (input.empty()) {
        const std::string name = "facade_" + std::to_string(scan.chunks) + "x" + std::to_string(scan.textureSize) + "_" +
                                 std::to_string(facade) + "_" + std::to_string(scan.chartCells);
        const fs::path folder = fs::path(dir) / name;
        input = (folder / (name + ".obj")).string();
        if (!fs::exists(input)) {
            fs::create_directories(folder);
            const test::ChildUsage g = test::runInChild([&] { writeChunkedScan(folder.string(), name, facadeMesh(facade), scan); });
            if (!g.ok) return 1;
            std::printf("wrote %s in %.1f s\n", input.c_str(), g.wall);
        }
    }
    const uint64_t texels = sourceTexels(input);
    std::printf("input %s: %.1f Mtexel of source textures\n", input.c_str(), texels / 1e6);
    std::printf("%-9s %10s %10s %9s %12s %8s %8s %14s %12s %10s\n", "limit", "peak RSS", "over", "gate peak", "model/RSS",
                "wall s", "CPU s", "texel/CPU-s", "tri/CPU-s", "db MB");
    std::stringstream list(limits);
    for (std::string item; std::getline(list, item, ',');) {
        const uint64_t limit = parseBytes(item);
        const std::string output = dir + "/out.hlod", figures = dir + "/out.figures";
        const test::ChildUsage c = test::runInChild([&] {
            std::ostringstream log;
            Progress progress(log, false);
            BuildRequest r;
            r.input = input, r.output = output;
            r.options.jobs = jobs;
            if (limit) r.options.memoryLimit = limit;
            const BuildSummary s = runBuild(r, progress);
            std::ofstream(figures) << s.inputTriangles << " " << s.gatePeak << " " << r.options.memoryLimit;
        });
        if (!c.ok) return 1;
        uint64_t triangles = 0, gatePeak = 0, used = 0;
        std::ifstream(figures) >> triangles >> gatePeak >> used;
        const double over = double(c.peakRss) - double(used);
        std::printf("%-9s %7.0f MB %7.0f MB %6.0f MB %12.2f %8.1f %8.1f %14.0f %12.0f %10.1f\n", item.c_str(), c.peakRss / 1e6,
                    over / 1e6, gatePeak / 1e6, c.peakRss ? double(gatePeak) / c.peakRss : 0.0, c.wall, c.cpu,
                    c.cpu > 0 ? texels / c.cpu : 0.0, c.cpu > 0 ? triangles / c.cpu : 0.0, fs::file_size(output) / 1e6);
        std::fflush(stdout);
    }
    return 0;
}
