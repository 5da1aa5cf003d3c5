// Loader throughput (thesis §4.3): nodes, stored MB and decoded MB per second through the
// loading thread's path (chunked positioned reads, XXH3 check, Draco + JPEG decode) on a
// synthetic database, and the figures of the disk model (player/LOADERS.md): per node, the read
// time fitted as seek + stored bytes / bandwidth (least squares over the nodes, each read whole,
// best of 5) and the decode time per decoded byte (sum over the nodes). Reads come from the page
// cache (the file was just written; caches are not dropped). Prints figures; not run by ctest.
//   bench_loader [blocks] [trianglesPerNode] [textureSize]
#include "player/loader_thesis.h"
#include "tests/support/synthetic.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <unistd.h>

using namespace hlod;

int main(int argc, char** argv) {
    SyntheticOptions o;
    o.blocksX = o.blocksY = argc > 1 ? uint32_t(std::atoi(argv[1])) : 3;
    o.levels = 4;
    o.trianglesPerNode = argc > 2 ? uint32_t(std::atoi(argv[2])) : 2048;
    o.textureSize = argc > 3 ? uint32_t(std::atoi(argv[3])) : 128;
    auto dir = std::filesystem::temp_directory_path() / ("hlod_bench_loader_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    std::string file = (dir / "bench.hlod").string();
    writeSyntheticDatabase(file, o);
    Database db = Database::open(file);
    auto source = databaseSource(db);
    const Skeleton& s = db.skeleton();

    for (bool threaded : {false, true}) {
        ThesisLoader loader(source, {});
        std::vector<PriorityUpdate> all;
        for (const Node& n : s.nodes) all.push_back({n.id, 1.0 / (1 + n.level) + n.id * 1e-9});
        auto t0 = std::chrono::steady_clock::now();
        loader.updateAndEvict(all, {}, [](uint32_t) { return false; });
        size_t taken = 0;
        if (threaded) loader.start();
        while (taken < s.nodes.size()) {
            if (threaded)
                std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the render thread's frames
            else
                loader.step(16);
            taken += loader.takeReady(1 << 30, ~0ull).size();
        }
        double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        LoaderCounters k = loader.counters();
        std::printf("%s: %zu nodes (%u tri, %ux%u texels each) in %.3f s: %.0f nodes/s, %.1f MB/s stored, %.1f MB/s decoded\n",
                    threaded ? "loading thread" : "synchronous   ", taken, o.trianglesPerNode, o.textureSize,
                    o.textureSize, sec, taken / sec, k.bytesRead / sec / 1e6, k.bytesDecoded / sec / 1e6);
    }

    // Disk model: t_read(node) = seek + bytes / bandwidth, t_decode = bytes_decoded x ns.
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, decodeSec = 0, decoded = 0;
    for (const Node& node : s.nodes) {
        std::vector<uint8_t> data(source->nodeSize(node.id));
        double best = 1e30;
        for (int rep = 0; rep < 5; ++rep) {
            auto t0 = std::chrono::steady_clock::now();
            source->readChunk(node.id, 0, data);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        auto t0 = std::chrono::steady_clock::now();
        DecodedNode d = source->decode(node.id, data);
        decodeSec += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        decoded += double(d.bytes());
        double x = double(data.size()), y = best * 1e3;  // bytes, ms
        n += 1;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);  // ms per byte
    double seekMs = (sy - slope * sx) / n;
    std::printf("disk model (page cache, %.0f nodes, %.0f stored bytes mean): seek %.4f ms, bandwidth %.0f MB/s, "
                "decode %.2f ns per decoded byte (%.1f MB decoded)\n",
                n, sx / n, seekMs, slope > 0 ? 1e-3 / slope : 0.0, decodeSec * 1e9 / decoded, decoded / 1e6);
    std::filesystem::remove_all(dir);
}
