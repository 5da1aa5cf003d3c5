// Speed of the database layer (not run by ctest): writing the synthetic database, opening a
// skeleton, reading + verifying blobs, Draco and JPEG encode/decode.
#include "formats/codec.h"
#include "tests/support/synthetic.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace {

std::string tempPath(const char* name) {
    return (std::filesystem::temp_directory_path() / (std::string("hlod-bench-") + std::to_string(::getpid()) + name))
        .string();
}

hlod::MeshData wavyGrid(uint32_t n) {
    hlod::MeshData m;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            float x = float(i), y = float(j);
            m.positions.insert(m.positions.end(), {x, y, 3 * std::sin(x * 0.1f) * std::cos(y * 0.13f)});
            m.texcoords.insert(m.texcoords.end(), {x / float(n), y / float(n)});
        }
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}

void BM_WriteSyntheticDefault(benchmark::State& state) {
    const std::string path = tempPath("default.hlod");
    for (auto _ : state) hlod::writeSyntheticDatabase(path, {});
    state.counters["bytes"] = double(std::filesystem::file_size(path));
    std::filesystem::remove(path);
}

void BM_OpenSkeleton(benchmark::State& state) {
    const std::string path = tempPath("big.hlod");
    hlod::SyntheticOptions o;
    o.blocksX = o.blocksY = 8;
    o.levels = 4;
    o.trianglesPerNode = 32;
    o.textureSize = 8;
    hlod::writeSyntheticDatabase(path, o);
    size_t nodes = 0;
    for (auto _ : state) nodes = hlod::Database::open(path).skeleton().nodes.size();
    state.counters["nodes"] = double(nodes);
    state.counters["nodes/s"] = benchmark::Counter(double(nodes), benchmark::Counter::kIsIterationInvariantRate);
    std::filesystem::remove(path);
}

void BM_DracoDecode(benchmark::State& state) {
    const auto n = uint32_t(state.range(0));
    hlod::EncodedBlob blob = hlod::encodeGeometry(wavyGrid(n), {});
    for (auto _ : state) benchmark::DoNotOptimize(hlod::decodeGeometry(blob.bytes, "bench"));
    state.counters["tri/s"] =
        benchmark::Counter(double(blob.info.triangles), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["B/tri"] = double(blob.bytes.size()) / blob.info.triangles;
}

void BM_DracoEncode(benchmark::State& state) {
    const auto n = uint32_t(state.range(0));
    hlod::MeshData m = wavyGrid(n);
    for (auto _ : state) benchmark::DoNotOptimize(hlod::encodeGeometry(m, {}));
    state.counters["tri/s"] = benchmark::Counter(double(m.triangleCount()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_JpegDecode(benchmark::State& state) {
    const auto side = uint32_t(state.range(0));
    hlod::Image img{side, side, 3, std::vector<uint8_t>(size_t(side) * side * 3)};
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = uint8_t(i * 31 / 7);
    hlod::EncodedBlob blob = hlod::encodeTexture(img, hlod::Codec::Jpeg);
    for (auto _ : state) benchmark::DoNotOptimize(hlod::decodeTexture(blob.bytes, hlod::Codec::Jpeg, "bench"));
    state.counters["pix/s"] = benchmark::Counter(double(side) * side, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_WriteSyntheticDefault)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OpenSkeleton)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DracoDecode)->Arg(16)->Arg(180)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DracoEncode)->Arg(16)->Arg(180)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_JpegDecode)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
