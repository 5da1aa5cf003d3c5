// `hlod synth city -o DIR [--scale S] [--seed N]`: writes the thesis-like city of synth.h and
// prints what it wrote (blocks, triangles, texels, bytes, seconds).
#include "pipeline/cli/subcommands.h"

#include "pipeline/synth/synth.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>

namespace hlod::cli {

void addSynth(CLI::App& app, int& status) {
    CLI::App* synth = app.add_subcommand("synth", "generate synthetic input models");
    synth->require_subcommand(1);
    CLI::App* city = synth->add_subcommand(
        "city", "a scanned-city-like model (thesis §1.1): one OBJ+MTL+JPEG per block, plus city.json");
    auto options = std::make_shared<synth::CityOptions>();
    auto dir = std::make_shared<std::string>();
    city->add_option("-o,--output", *dir, "output folder")->required()->check(nonEmptyPath());
    city->add_option("--scale", options->scale,
                     "fraction of the thesis model (1 = 114 blocks, 8.95 M triangles, 937 M texels)")
        ->check(finiteAboveAtMost(0, 4));
    city->add_option("--seed", options->seed, "random seed (same seed and scale = same bytes)")
        ->check(wholeNumber(options->seed));
    city->add_option("--jpeg-quality", options->jpegQuality, "JPEG quality 1..100")
        ->check(CLI::Range(1, 100));
    city->add_option("--city-blocks", options->cityBlocks, "number of city blocks (default round(25 sqrt(scale)))")
        ->check(wholeNumber(options->cityBlocks));
    city->callback([options, dir, &status] {
        status = runGuarded("synth city", [&] {
            const auto start = std::chrono::steady_clock::now();
            synth::CityResult r = synth::generateCity(*options, *dir);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            std::printf("synth city: %zu blocks, %llu triangles, %llu texels, %.1f MB in %s/ (%.1f s)\n",
                        r.blocks.size(), static_cast<unsigned long long>(r.triangles),
                        static_cast<unsigned long long>(r.texels), double(r.bytes) / 1e6, dir->c_str(), seconds);
            return kExitOk;
        });
    });
}

}  // namespace hlod::cli
