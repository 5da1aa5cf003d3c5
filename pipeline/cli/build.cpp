// `hlod build INPUT -o DB`: prints the constants it uses first, the up axis it records and why,
// progress while it runs (a line at least every --progress-interval seconds when stdout is not
// a terminal, or JSON lines with --progress-json), a final summary (nodes per level, time per
// stage, bytes per input triangle, the heap's page size, unusable textures) and writes the run's figures to the build
// report DB.build.json (formats/build_report.h; the database itself holds nothing that varies
// run to run). --strict makes an unusable texture fatal (exit 2) instead of a warning.
#include "pipeline/cli/subcommands.h"

#include "formats/calibration.h"
#include "formats/temp_files.h"
#include "formats/cli/huge_pages.h"
#include "formats/offset.h"
#include "pipeline/pipeline.h"
#include "pipeline/stats/stats.h"
#include "pipeline/tree_rules.h"

#include <CLI/CLI.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <chrono>
#include <filesystem>
#include <iostream>

namespace hlod::cli {
namespace {

struct BuildArgs {
    BuildRequest request;
    ConstantOptions constants{"build", kUsedByBuild};
    std::string calibration;
    std::string simplifier = "meshopt";
    std::string leafRule = "below-one";
    std::string mode = "top-down";
    std::string bottomUpError;  // empty: not given (bound)
    std::string errorCap;  // empty: not given (on, but off with --bottom-up-error simplifier)
    std::string planes = "balanced";
    std::string blocks;  // "A:B" shard selection
    ProgressOptions progress;
};

double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

// FIRST:LAST, two whole numbers below 2^32 and nothing else (no sign, no third part).
void parseBlockRange(const std::string& text, BuildRequest& r) {
    const size_t colon = text.find(':');
    const auto whole = [](std::string_view digits, uint32_t& value) {
        const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        return !digits.empty() && error == std::errc() && end == digits.data() + digits.size();
    };
    const std::string_view all(text);
    if (colon == std::string::npos || !whole(all.substr(0, colon), r.firstBlock) || !whole(all.substr(colon + 1), r.lastBlock))
        throw std::invalid_argument("--blocks '" + text + "': expected FIRST:LAST (block indices, LAST excluded)");
}

void writeReport(const std::string& db, const std::vector<BuildStage>& stages, const BuildSummary& summary, double wall,
                 double cpu, uint64_t memoryLimit) {
    BuildReport r;
    r.stages = stages;
    r.peakRssBytes = peakRss();
    r.memoryLimitBytes = memoryLimit;
    r.inputTriangles = summary.inputTriangles;
    r.wallSeconds = wall;
    r.cpuSeconds = cpu;
    r.hugePages = heapOnHugePages();
    r.outputBytes = std::filesystem::file_size(db);
    r.nodesPerLevel = summary.nodesPerLevel;
    r.nodes = summary.nodes;
    for (const TextureProblem& p : summary.textureProblems) r.textureProblems.push_back(p.what + "; material '" + p.material + "' left untextured");
    writeBuildReport(buildReportPath(db), r);
}

void printSummary(const std::string& db, const BuildSummary& s, double wall, double cpu, uint64_t memoryLimit) {
    std::cout << "nodes per level:";
    uint64_t nodes = 0;
    for (size_t l = 0; l < s.nodesPerLevel.size(); ++l) std::cout << " hlod" << l << "=" << s.nodesPerLevel[l], nodes += s.nodesPerLevel[l];
    const uint64_t bytes = std::filesystem::file_size(db);
    std::cout << " (" << nodes << " nodes, " << s.blockCount << " blocks)\n"
              << "summary: " << s.inputTriangles << " input triangles, " << bytes << " bytes ("
              << (s.inputTriangles ? double(bytes) / s.inputTriangles : 0) << " B/input triangle), wall " << wall << " s, cpu "
              << cpu << " s (" << (cpu > 0 ? s.inputTriangles / cpu / 1000 : 0) << " k input tri/CPU-s), peak RSS "
              << formatBytes(peakRss()) << " (--memory-limit " << formatBytes(memoryLimit) << "), heap on "
              << (heapOnHugePages() ? "2 MiB" : "4 KiB") << " pages\n";
    if (!s.textureProblems.empty())
        std::cout << "textures: " << s.textureProblems.size()
                  << " unusable, their materials left untextured (warnings above; --strict makes them fatal)\n";
    if (peakRss() > memoryLimit)
        std::cout << "warning: peak RSS " << formatBytes(peakRss()) << " exceeded --memory-limit " << formatBytes(memoryLimit) << "\n";
}

}  // namespace

// The level drawn whatever the frame's budget (thesis §4.2): above its target, no budget below its
// cost is reachable. Until stop 51 only `hlod stats` said so (a non-manifold scan's hlod0 at 17 x).
void warnHlod0Missed(const std::string& db) {
    const stats::LevelCheck c = stats::hlod0Check(Database::open(db));
    if (c.missing == 0) return;
    char worst[32];
    std::snprintf(worst, sizeof worst, "%.1f", c.worstRatio);
    std::cout << "warning: " << db << ": " << c.missing << " of " << c.simplifiedNodes << " hlod0 nodes keep more than "
              << kTargetSlack << " x their target of triangles (the worst " << worst
              << " x): the coarsest level, drawn whatever the budget; `hlod stats` lists every level\n";
}

namespace {

int runBuildCommand(BuildArgs& a) {
    const auto start = std::chrono::steady_clock::now();
    BuildOptions& o = a.request.options;
    for (const std::string& output : {a.request.output, buildReportPath(a.request.output)})  // the mesh: runBuild
        refuseOutputOverInputs(output, {a.calibration, a.constants.configFile});
    applyConstantOptions(a.constants, o.constants, std::cout);
    if (!a.calibration.empty()) o.constants.textured = readCalibration(a.calibration).cTextured;
    o.simplifier = a.simplifier == "openmesh" ? Simplifier::OpenMesh : Simplifier::Meshopt;
    o.leafRule = a.leafRule == "stop-before" ? LeafRule::StopBefore : LeafRule::BelowOne;
    o.mode = a.mode == "bottom-up" ? BuildMode::BottomUp : BuildMode::TopDown;
    if (!a.bottomUpError.empty() && o.mode != BuildMode::BottomUp)  // a subcommand takes only what it uses
        throw std::invalid_argument("--bottom-up-error needs --mode bottom-up (top-down measures against the original)");
    if (!a.bottomUpError.empty() && !parseBottomUpError(a.bottomUpError, o.bottomUpError))  // CLI11 checked it already
        throw std::invalid_argument("--bottom-up-error: unknown value " + a.bottomUpError);
    if (a.errorCap == "on" && o.simplifier == Simplifier::OpenMesh)
        throw std::invalid_argument("--error-cap on needs --simplifier meshopt (OpenMesh's decimater reports no error of its own)");
    if (!a.errorCap.empty()) o.errorCap = a.errorCap == "on";
    o.planes = a.planes == "even" ? Planes::Even : Planes::Balanced;
    if (!a.blocks.empty()) parseBlockRange(a.blocks, a.request);
    printConstants(std::cout, o.constants, kUsedByBuild);
    std::cout << std::flush;
    BuildSummary summary;
    std::vector<BuildStage> stages;
    {
        a.progress.live = !a.progress.json && isatty(STDOUT_FILENO) != 0;
        Progress progress(std::cout, a.progress);
        summary = runBuild(a.request, progress);
        stages = progress.stages();
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (a.request.shard) {
        std::cout << "shard " << a.request.output << ": blocks " << a.request.firstBlock << ".."
                  << std::min(a.request.lastBlock, summary.blockCount) << " of " << summary.blockCount << "\n";
        return 0;
    }
    printSummary(a.request.output, summary, wall, cpuSeconds(), o.memoryLimit);
    writeReport(a.request.output, stages, summary, wall, cpuSeconds(), o.memoryLimit);
    warnHlod0Missed(a.request.output);
    return 0;
}

}  // namespace

void addProgressOptions(CLI::App* sub, ProgressOptions& progress) {
    sub->add_flag("--progress-json", progress.json,
                  "progress as one JSON object per line (stage, done, total, unit, textures, texels, elapsed_s, eta_s; "
                  "null eta_s until the stage has a rate) instead of the progress line");
    sub->add_option("--progress-interval", progress.interval, "seconds between progress lines when stdout is not a terminal (default 5)")
        ->check(finitePositive());
}

void addOffsetOption(CLI::App* sub, std::array<double, 3>& offset) {
    const CLI::Validator xyz(
        [](std::string& text) {
            try {
                parseOffset(text, "value");  // CLI11 names the option
                return std::string();
            } catch (const std::invalid_argument& e) {
                return std::string(e.what());
            }
        },
        "X,Y,Z");
    sub->add_option_function<std::string>(
           "--offset", [&offset](const std::string& text) { offset = parseOffset(text, "--offset"); },
           "subtracted from every input position before it is stored as a 32-bit float, recorded in the database "
           "(META offset): for a model far from the origin, e.g. a scan in UTM metres (README \"Far from the origin\")")
        ->check(xyz);
}

void addMemoryLimitOption(CLI::App* sub, uint64_t& limit, const std::string& what) {
    // Checked after the size transform (a check runs after every transform): `--memory-limit 1`
    // was a 1-byte bound until stop 47, accepted, and the build spilled everything to files.
    const CLI::Validator floor(
        [](std::string& bytes) {
            return std::stoull(bytes) >= kMinMemoryLimit
                       ? std::string()
                       : bytes + " bytes is below the least, 16M; a size takes its unit, e.g. 512M, 2G";
        },
        "");
    sub->add_option("--memory-limit", limit, what + ", e.g. 512M, 2G (default 1G, at least 16M)")
        ->transform(CLI::AsSizeValue(false))
        ->transform(wholeNumber(limit))  // inserted before the size transform: "-1" is refused, not wrapped
        ->check(floor);
}

void addBuild(CLI::App& app, int& status) {
    auto a = std::make_shared<BuildArgs>();
    BuildOptions& o = a->request.options;
    CLI::App* sub = app.add_subcommand("build", "build an HLOD database from a mesh (PLY, OBJ, glTF) or a folder of block meshes");
    sub->add_option("INPUT", a->request.input, "mesh file, folder of meshes (one block per file, ordered by name), or work folder of `hlod split`")->required();
    sub->add_option("-o,--output", a->request.output, "database to write (a shard folder with --shard)")
        ->required()->check(nonEmptyPath());
    sub->add_option("-j,--jobs", o.jobs, "threads (default: all cores): the nodes of a block are built in parallel, one more block at once per 4 threads")
        ->check(CLI::Range(0, kMaxJobs));
    sub->add_option("--simplifier", a->simplifier, "meshopt (fast, default) or openmesh (Decimater, ModQuadric)")
        ->check(CLI::IsMember({"meshopt", "openmesh"}));
    sub->add_option("--leaf-rule", a->leafRule,
                    "below-one (default: divide until the factor is below 1) or stop-before (stop before a level "
                    "whose factor would be below 1); pipeline/TREE.md")
        ->check(CLI::IsMember({"below-one", "stop-before"}));
    sub->add_option("--mode", a->mode,
                    "top-down (default, thesis 3.2: every level simplified from the original triangles) or bottom-up "
                    "(each level from the level below, faster); pipeline/BUILD_SPEED.md")
        ->check(CLI::IsMember({"top-down", "bottom-up"}));
    sub->add_option("--bottom-up-error", a->bottomUpError,
                    "with --mode bottom-up: bound (default: distance to the children's simplified surface + their "
                    "error, an upper bound), exact (distance to the original, slower) or simplifier (the children's "
                    "error + meshoptimizer's own quadric estimate: fastest, measures no distance (nor does nxsbuild), NOT a bound: "
                    "below the exact distance on 87-93 % of the nodes (Lucy, a terrain), as low as 1 % of it, and up to "
                    "9.6 x above it at the roots; needs --simplifier meshopt); pipeline/BUILD_SPEED.md")
        ->check(CLI::IsMember({"bound", "exact", "simplifier"}));
    sub->add_option("--error-cap", a->errorCap,
                    "on (the default: locked borders cost triangles, not accuracy: a block root with shared sides "
                    "stops at twice the error it reaches with no border locked, every other node at its parent's "
                    "error; bottom-up every node with shared sides but the leaves' parents at twice its input's; a "
                    "node may keep more triangles than its factor) or off (the factor alone; the default with "
                    "--bottom-up-error simplifier, the mode for speed, whose cap costs ~10 % of it); meshopt only; "
                    "pipeline/TREE.md")
        ->check(CLI::IsMember({"on", "off"}));
    sub->add_option("--planes", a->planes,
                    "balanced (default: triangle-count quantiles avoiding dense surfaces) or even (evenly spaced, "
                    "empty pieces dropped)")
        ->check(CLI::IsMember({"balanced", "even"}));
    sub->add_option("--block-triangles", o.blockTriangles, "target triangles per block of a single mesh (default and 0: 671,088, whatever the memory limit)")
        ->check(wholeNumber(o.blockTriangles));
    sub->add_option("--block-size", o.blockSize, "block side length in input units (overrides --block-triangles; 0: not given)")
        ->check(finiteAtLeast(0));
    addMemoryLimitOption(sub, o.memoryLimit, "working-set bound");
    sub->add_option("--draco-position-bits", o.draco.positionBits,
                    "Draco position bits over the largest block (one lattice for all nodes, FORMAT.md; default " +
                        std::to_string(DracoOptions{}.positionBits) + ")")
        ->check(CLI::Range(kMinPositionBits, kMaxPositionBits));
    sub->add_option("--draco-texcoord-bits", o.draco.texcoordBits,
                    "Draco texture coordinate bits for every node; 0 (default): per node, a quarter texel of its own texture")
        ->check(CLI::Range(0, kMaxTexcoordBits));
    sub->add_option("--draco-position-step", o.draco.positionStep,
                    "position lattice step in input units, rounded down to a power of two (default and 0: from the block grid; "
                    "a folder input gets one per block unless this is given)")
        ->check(finiteAtLeast(0));
    sub->add_option("--draco-level", o.draco.compressionLevel, "Draco compression level 0..10 (default " + std::to_string(DracoOptions{}.compressionLevel) + ")")->check(CLI::Range(0, 10));
    sub->add_option("--jpeg-quality", o.jpegQuality,
                    "JPEG quality of node textures (at most a JPEG source's own; pipeline/TEXTURE_SIZE.md; default " +
                        std::to_string(BuildOptions{}.jpegQuality) + ")")
        ->check(CLI::Range(1, 100));
    sub->add_option_function<std::string>(
           "--jpeg-chroma",
           [options = &o](const std::string& v) {
               options->jpegChroma = v == "4:2:0" ? JpegChroma::Half : v == "4:4:4" ? JpegChroma::Full : JpegChroma::Source;
           },
           "JPEG chroma of node textures: source (default: a 4:2:0 JPEG source's nodes 4:2:0, others 4:4:4), "
           "4:4:4 or 4:2:0 (pipeline/TEXTURE_SIZE.md)")
        ->check(CLI::IsMember({"source", "4:4:4", "4:2:0"}));
    sub->add_flag("--leaf-psnr", o.leafPsnr,
                  "measure each leaf's stored textures against the source texels they copy (PSNR per level in the "
                  "build report; `hlod stats` shows it)");
    CLI::Option* shard = sub->add_flag("--shard", a->request.shard, "write a shard folder (merge shards with `hlod merge`)");
    sub->add_option("--blocks", a->blocks, "with --shard: build only blocks FIRST:LAST (LAST excluded; cut to the blocks there are)")
        ->needs(shard);  // a database of some blocks failed after the whole build (until stop 44)
    sub->add_option("--temp-dir", o.tempDir, "folder for temporary files (default: next to the output)")->check(nonEmptyPath());
    sub->add_flag("--allow-outside-input", o.read.allowOutsideInput,
                  "let an input refer to files outside its folder (absolute paths, '..', symbolic links): MTL "
                  "textures, glTF buffers and images, the meshes of a folder input");
    sub->add_option("--up", o.up, "up axis of the input, recorded in the database (default: y for glTF, z for OBJ/PLY)")
        ->check(CLI::IsMember({"y", "z"}));
    addOffsetOption(sub, o.read.offset);
    addProgressOptions(sub, a->progress);
    sub->add_flag("--strict", o.strict,
                  "an unusable texture (missing, empty, not an image, absurd size, corrupt) is fatal (exit 2) instead "
                  "of a warning that leaves its material untextured");
    sub->add_option("--calibration", a->calibration, "calibration file of `hlod calibrate`: sets c_textured (eq. 3.1)");
    addConstantOptions(*sub, a->constants);
    sub->callback([a, &status] { status = runGuarded("build", [&] { return runBuildCommand(*a); }); });
}

}  // namespace hlod::cli
