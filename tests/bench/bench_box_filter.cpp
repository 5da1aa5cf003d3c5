// The texture box filter's cost per output texel (pipeline/texture_store.cpp scaledRegion; issue
// #14's textured speed goal, pipeline/TEXTURE_SPEED.md round 8): a 4096² RGB image of noise, in
// memory with its pyramid, scaled to sides whose level ratio is below 2 (3238: a level-4 node of
// the 4:2:0 facade, ~1.26 source texels per output texel per side) and read by bands of 64 rows,
// as copyBlocks reads a node's rows. CPU time of this process, the best of --repeat runs; the
// XXH3-64 of the output, so a faster filter can be checked to give the same bytes. The heap on
// 2 MiB pages as in `hlod` (HLOD_HUGE_PAGES=0: 4 KiB pages).
//
//   bench_box_filter [--repeat N]
#include "formats/cli/huge_pages.h"
#include "pipeline/texture_store.h"

#include <xxhash.h>

#include <algorithm>
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

}  // namespace

int main(int argc, char** argv) {
    hlod::cli::reexecWithHugePages(argv);
    int repeat = 5;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
        else return std::fprintf(stderr, "usage: bench_box_filter [--repeat N]\n"), 2;
    }
    constexpr uint32_t kSide = 4096, kBand = 64;
    hlod::Image image{kSide, kSide, 3, std::vector<uint8_t>(size_t(kSide) * kSide * 3)};
    uint32_t state = 1;
    for (uint8_t& p : image.pixels) state = state * 1664525u + 1013904223u, p = uint8_t(state >> 24);
    const std::vector<hlod::Image> mips = hlod::mipLevels(image);
    const hlod::TextureSource source = hlod::textureView(image, mips);
    std::printf("%-8s %12s %14s   %s\n", "side", "CPU-ms", "ns/out texel", "XXH3-64 of bands");
    for (const uint32_t side : {3238u, 2900u, 1500u, 700u}) {
        double best = 1e30;
        uint64_t hash = 0;
        for (int r = 0; r < repeat; ++r) {
            const double start = cpuSeconds();
            hash = 0;
            for (uint32_t y = 0; y < side; y += kBand) {
                const hlod::Image band = hlod::scaledRegion(source, side, side, 0, y, side, std::min(side, y + kBand));
                hash = hash * 31 + XXH3_64bits(band.pixels.data(), band.pixels.size());
            }
            best = std::min(best, cpuSeconds() - start);
        }
        std::printf("%-8u %12.1f %14.2f   %016llx\n", side, 1e3 * best, 1e9 * best / (double(side) * side), (unsigned long long)hash);
    }
    return 0;
}
