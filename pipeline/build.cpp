// The whole build (thesis §3.2): find the blocks (a folder: one block per mesh file, by name; one
// mesh: read, split on a grid into per-block temporary files), build the selected blocks with TBB
// (a block's nodes in parallel; more blocks at once only with more cores than one keeps busy, and
// at most as many as --memory-limit allows), each into its own record
// file, then merge the records into the database in block order. The result does not depend on
// -j, and building subsets of blocks as shards and merging them gives the same bytes.
#include "pipeline/lattice_flattened.h"
#include "pipeline/pipeline.h"
#include "pipeline/texture_store.h"
#include "pipeline/split_work.h"
#include "pipeline/tbb_sync.h"

#include "formats/build_report.h"
#include "formats/constants.h"
#include "formats/interrupt.h"
#include "formats/offset.h"
#include "formats/temp_files.h"
#include "formats/up_axis.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <malloc.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <regex>
#include <set>
#include <span>

#ifndef HLOD_VERSION
#define HLOD_VERSION "0.0.0"
#endif

namespace hlod {
namespace {

namespace fs = std::filesystem;

// A temporary folder removed with everything in it when the build ends, however it ends.
struct TempDir {
    std::string path;
    explicit TempDir(const std::string& parent) {
        const std::string prefix = (fs::path(parent) / "hlod-build").string();
        removeStaleTemporaries(prefix);  // of builds killed before they removed theirs
        std::string pattern = temporaryPattern(prefix);
        if (createTemporary(pattern, true) < 0) {
            const int error = errno;
            throw std::runtime_error(parent + ": cannot create a temporary folder (" + std::strerror(error) + ")");
        }
        path = pattern;
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
        forgetTemporary(path);
    }
};

// The automatic block size does not depend on --memory-limit, so the database does not either:
// the triangles whose working set filled a quarter of the default 1 GiB limit when it was chosen
// (400 B a triangle, memory_gate.cpp). A literal: refitting the gate's model must not move every
// database's grid. A smaller limit only admits fewer blocks at once (MemoryGate).
constexpr uint64_t kAutoBlockTriangles = 671'088;
uint64_t blockTarget(const BuildOptions& o) { return o.blockTriangles ? o.blockTriangles : kAutoBlockTriangles; }

bool isStreamable(const std::string& input) {
    return isMeshFile(input) && fs::is_regular_file(input);
}

// The textures rule (README "Textures: one rule"): with --strict the first unusable texture ends the
// build (InputError, exit 2) before any block is built; otherwise its material is untextured.
void enforceTextures(const std::vector<TextureProblem>& problems, const BuildOptions& options) {
    if (options.strict && !problems.empty()) throw InputError(problems.front().what + " (--strict)");
}

std::string untexturedWarning(const TextureProblem& p) {
    return "warning: " + p.what + "; material '" + p.material + "' left untextured";
}

void reportRead(const std::string& input, const ReadStats& stats, Progress& progress) {
    for (const std::string& w : stats.warnings) progress.message("warning: " + w);
    for (const TextureProblem& p : stats.textureProblems) progress.message(untexturedWarning(p));
    if (stats.degenerateDropped)
        progress.message(input + ": dropped " + std::to_string(stats.degenerateDropped) + " degenerate triangles");
}

// glibc raises its mmap threshold to the largest block freed (up to 32 MiB); after that a node's
// large arrays come from the arenas, whose freed pages stay in the process (~50 MiB of Lucy's
// peak), and so do the split's cell buffers once the parse has freed arrays held in memory (+16 MiB
// on the 17 M terrain, whose parse spills midway). A fixed threshold maps and unmaps them
// (pipeline/MEMORY.md "Jobs"). Not during the parse, nor in the split of a parse held in memory:
// mapped cell buffers fault every page afresh (+0.3–0.5 CPU-s on Lucy 1.6 M for 6 MiB of peak).
void fixMmapThreshold() {
    constexpr int kMmapThreshold = 1 << 20;  // bytes: larger allocations are mapped, returned when freed
    mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
}

// One PLY, OBJ or glTF mesh, out of core: parsed once (in memory within limit/4, beyond that into
// spill files), then streamed to the grid; a glTF's embedded images wait, still encoded, in
// TEMP/gltf-images for the texture store.
SplitInputs streamBlocks(const std::string& input, const BuildOptions& options, const std::string& tempDir, Progress& progress) {
    const std::string rawDir = (fs::path(tempDir) / "raw").string();
    fs::create_directories(rawDir);
    SplitInputs in;
    {
        RawMesh raw;
        raw.spillBeyond(options.memoryLimit / 4, rawDir);  // in memory while the arrays fit limit/4
        raw.progress = &progress;
        progress.beginStage("read", fs::file_size(input), "B");
        const std::string ext = meshExtension(input);
        ReadOptions readOptions = options.read;
        readOptions.imageDir = (fs::path(tempDir) / "gltf-images").string();
        if (ext == ".ply") parsePly(input, raw, options.read);
        else if (ext == ".obj") parseObj(input, raw, options.read);
        else parseGltf(input, raw, readOptions);
        progress.endStage();
        if (raw.triangles.size() == 0) throw InputError(input + ": empty mesh (no valid triangles)");
        checkTextures(raw.materials, raw.hasTexcoords, input, raw.stats);
        enforceTextures(raw.stats.textureProblems, options);
        const Box3f bounds = usedBounds(raw);
        checkModelExtent(input, bounds);
        const GridSpec grid = chooseGrid(bounds, raw.triangles.size(), blockTarget(options), options.blockSize);
        checkPositionStep(input, gridCell(bounds, grid), options.draco.positionStep);  // before the split's work
        in.positionStep = gridPositionStep(bounds, grid, options.draco.positionBits);
        const double step = options.draco.positionStep > 0 ? options.draco.positionStep : in.positionStep;
        const std::string precision = floatPrecisionWarning(input, bounds, step, options.read.offset);
        if (!precision.empty()) raw.stats.warnings.push_back(precision);
        in.grid = grid, in.bounds = bounds, in.inputTriangles = raw.triangles.size();
        if (raw.positions.spilled()) fixMmapThreshold();  // arrays held, then freed: the threshold rose
        progress.beginStage("split", raw.triangles.size());
        try {
            for (const CellFile& cell : streamSplit(raw, grid, tempDir, options.memoryLimit / 4, input, raw.stats, &progress))
                in.blocks.push_back({cell.file, true, cell.triangles});
        } catch (const InputError& e) {  // every triangle collapsed in float: say why, as the warning would have
            if (precision.empty()) throw;
            throw InputError(std::string(e.what()) + "; " + precision.substr(input.size() + 2));
        }
        progress.endStage();
        reportRead(input, raw.stats, progress);
        in.textureProblems = raw.stats.textureProblems;
        in.materials = std::move(raw.materials);
    }
    fs::remove_all(rawDir);
    return in;
}

}  // namespace

SplitInputs findBlocks(const std::string& input, const BuildOptions& options, const std::string& tempDir, Progress& progress) {
    SplitInputs in;
    if (fs::is_directory(input)) {
        const std::vector<fs::path> files = folderMeshes(input);
        if (files.empty()) throw InputError(input + ": folder has no .ply, .obj, .gltf or .glb files");
        for (const auto& f : files) {
            resolveReference(input, input, f.filename().string(), "mesh", options.read);  // a link may not leave the folder
            in.blocks.push_back({f.string(), false, 0});
        }
        return in;
    }
    if (isStreamable(input)) return streamBlocks(input, options, tempDir, progress);
    progress.beginStage("read", 0);
    SourceMesh source = readMesh(input, options.read);
    progress.advance(source.piece.mesh.triangleCount());
    progress.endStage();
    enforceTextures(source.stats.textureProblems, options);
    reportRead(input, source.stats, progress);
    in.textureProblems = source.stats.textureProblems;
    progress.beginStage("split", source.piece.mesh.triangleCount());
    checkModelExtent(input, pieceBounds(source.piece.mesh));
    const GridSpec grid = chooseGrid(pieceBounds(source.piece.mesh), source.piece.mesh.triangleCount(), blockTarget(options),
                                     options.blockSize);
    checkPositionStep(input, gridCell(pieceBounds(source.piece.mesh), grid), options.draco.positionStep);
    in.positionStep = gridPositionStep(pieceBounds(source.piece.mesh), grid, options.draco.positionBits);
    in.grid = grid, in.bounds = pieceBounds(source.piece.mesh);
    const double step = options.draco.positionStep > 0 ? options.draco.positionStep : in.positionStep;
    if (const std::string w = floatPrecisionWarning(input, in.bounds, step, options.read.offset); !w.empty()) progress.message("warning: " + w);
    std::vector<Piece> cells = splitByGrid(source.piece, grid);
    source.piece = {};
    for (size_t c = 0; c < cells.size(); ++c) {
        if (cells[c].mesh.triangleCount() == 0) continue;
        const std::string file = (fs::path(tempDir) / ("cell_" + std::to_string(c) + ".piece")).string();
        appendPiece(file, cells[c]);
        in.blocks.push_back({file, true, cells[c].mesh.triangleCount()});
        progress.advance(cells[c].mesh.triangleCount());
        cells[c] = {};
    }
    progress.endStage();
    in.materials = std::move(source.materials);
    return in;
}

namespace {

struct GateTicket {
    MemoryGate& gate;
    uint64_t bytes;
    GateTicket(MemoryGate& g, uint64_t b) : gate(g), bytes(b) { gate.acquire(bytes); }
    ~GateTicket() { gate.release(bytes); }
};

void buildOne(const BlockSource& source, const SplitInputs& inputs, uint32_t index, const std::string& dir, const BuildOptions& options,
              MemoryGate& gate, Progress& progress, BlockStats& stats) {
    const std::vector<Material>& materials = inputs.materials;
    SourceMesh mesh;
    Box3f fileBounds;  // a folder's file: its bounds; its lattice step when its floats step coarser
    double floatStepOver = 0;
    if (source.isPiece) {
        mesh.piece = loadPiece(source.file);
        mesh.materials = materials;
        for (uint32_t m : mesh.piece.materials)  // a work folder's manifest lists them apart from its cells
            if (m >= materials.size())
                throw InputError(source.file + ": a triangle has material " + std::to_string(m) + " but the input lists " +
                                 std::to_string(materials.size()) + " (corrupt work folder? split again)");
    } else {  // a folder's mesh file; a glTF's embedded images wait, encoded, in TEMP/gltf-images/N
        ReadOptions read = options.read;
        if (!read.imageDir.empty()) read.imageDir = (fs::path(read.imageDir) / std::to_string(index)).string();
        mesh = readMesh(source.file, read);
        enforceTextures(mesh.stats.textureProblems, options);
        const Box3f bounds = pieceBounds(mesh.piece.mesh);  // the block's lattice, as buildBlock fixes it
        checkPositionStep(source.file, bounds, options.draco.positionStep);
        const double step =
            options.draco.positionStep > 0 ? options.draco.positionStep : positionLatticeStep(bounds, options.draco.positionBits);
        fileBounds = bounds;  // the folder's warning, once for all its files (floatPrecisionOfFiles)
        if (!floatPrecisionWarning(source.file, bounds, step).empty()) floatStepOver = step;
    }
    const TextureHeader textures = usedTextures(mesh, options.textures);
    const uint64_t workingSet = blockWorkingSet(mesh.piece.mesh.triangleCount(), textures.texels, options.constants.desiredTris);
    // A progressive JPEG's coefficients, on the block's own ticket: its textures decode one at a
    // time (BlockTextures::source), so the node threads beyond it are not charged them again.
    const GateTicket ticket(gate, workingSet + textures.wholeImageBytes);
    // The block's nodes run on 1 + extra.nodes threads (build_tree.cpp), each extra one on a
    // further working set of the block the gate grants beside what is in use (pipeline/MEMORY.md "Jobs").
    struct ExtraNodes {
        MemoryGate& gate;
        uint64_t bytes;
        int nodes = 0;
        ~ExtraNodes() { gate.release(bytes * nodes); }
    } extra{gate, workingSet};
    while (extra.nodes + 1 < tbb::this_task_arena::max_concurrency() && gate.tryAcquire(workingSet)) ++extra.nodes;
    tbb::task_arena nodes(1 + extra.nodes);
    BlockRecordWriter records(blockRecordPath(dir, index));
    const auto build = [&] {
        taskBegin();  // tbb_sync.h
        // A grid cell shares its border only across the grid's lines; a folder's mesh file may abut any other.
        const Sides shared = source.isPiece && inputs.grid ? blockSides(pieceBounds(mesh.piece.mesh), *inputs.grid) : kAllSides;
        BlockStats s = buildBlock(mesh.piece, mesh.materials, index, options, &progress, [&](NodeRecord&& r) { records.add(r); }, shared);
        taskEnd();
        return s;
    };
    taskEnd();
    stats = nodes.execute(build);
    taskBegin();
    records.setGeometricErrors(stats.geometricErrors);
    records.finish();
    malloc_trim(0);  // a worker thread's heap keeps a finished block's memory otherwise (glibc arenas)
    stats.degenerateDropped = mesh.stats.degenerateDropped;
    stats.warnings = mesh.stats.warnings;
    stats.fileBounds = fileBounds, stats.floatStepOver = floatStepOver;
    stats.textureProblems.insert(stats.textureProblems.begin(), mesh.stats.textureProblems.begin(), mesh.stats.textureProblems.end());
}

// Blocks built at once with `cores` threads (pipeline/MEMORY.md "Jobs"): a block's nodes are built
// in parallel (build_tree.cpp), so one block keeps kCoresPerBlock cores busy and each further
// kCoresPerBlock cores admit one more block (and its working set), within the memory gate.
constexpr int kCoresPerBlock = 4;
size_t blocksAtOnce(int cores) { return static_cast<size_t>(std::max(1, cores / kCoresPerBlock)); }

// Triangles the §3.2 recursion will visit (each level goes over the block's originals), for
// the progress percentage; 0 (unknown) for folder inputs, whose blocks are read as they build.
uint64_t expectedWork(const std::vector<BlockSource>& blocks, uint32_t first, uint32_t last, const Constants& c) {
    uint64_t total = 0;
    for (uint32_t b = first; b < last; ++b) {
        if (!blocks[b].triangles) return 0;
        uint64_t levels = 1;
        for (double f = blocks[b].triangles / c.desiredTris; f > 1; f /= c.levelFactor) ++levels;
        total += blocks[b].triangles * levels;
    }
    return total;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> buildMeta(const std::string& input, const BuildOptions& o) {
    const char* simplifier = o.simplifier == Simplifier::Meshopt ? "meshopt" : "openmesh";
    std::vector<std::pair<std::string, std::string>> meta = {{"tool", std::string("hlod ") + HLOD_VERSION}, {"input", input}};
    std::string command = "hlod build " + shellWord(input) + " --simplifier " + simplifier + " --leaf-rule " +
                          leafRuleName(o.leafRule) + " --planes " + planesName(o.planes);
    command += o.blockSize > 0 ? " --block-size " + formatConstant(o.blockSize)  // exact (6 decimals until stop 48)
                               : " --block-triangles " + std::to_string(blockTarget(o));
    command += " --draco-position-bits " + std::to_string(o.draco.positionBits) + " --draco-texcoord-bits " +
               std::to_string(o.draco.texcoordBits) + " --draco-level " + std::to_string(o.draco.compressionLevel) +
               " --jpeg-quality " + std::to_string(o.jpegQuality) + " --jpeg-chroma " + jpegChromaName(o.jpegChroma);
    if (o.draco.positionStep > 0) command += " --draco-position-step " + formatConstant(o.draco.positionStep);  // exact
    if (!o.up.empty()) command += " --up " + o.up;
    const bool offset = o.read.offset != Offset{};
    if (offset) command += " --offset " + offsetText(o.read.offset);
    if (o.mode == BuildMode::BottomUp) command += " --mode bottom-up";  // absent: top-down, as before the option
    if (o.mode == BuildMode::BottomUp && o.bottomUpError != BottomUpError::Bound)  // absent: bound, as before the option
        command += std::string(" --bottom-up-error ") + bottomUpErrorName(o.bottomUpError);
    command += std::string(" --error-cap ") + (errorCapped(o) ? "on" : "off");
    for (const auto& [name, value] : constantsAsPairs(o.constants, kUsedByBuild)) command += " --set " + name + "=" + value;
    meta.emplace_back("command", command);
    for (const auto& pair : constantsAsPairs(o.constants, kUsedByBuild)) meta.push_back(pair);
    meta.emplace_back("simplifier", simplifier);
    meta.emplace_back("tree.leafRule", leafRuleName(o.leafRule));
    meta.emplace_back("tree.planes", planesName(o.planes));
    if (o.mode == BuildMode::BottomUp) meta.emplace_back("tree.mode", buildModeName(o.mode));
    if (o.mode == BuildMode::BottomUp) meta.emplace_back("tree.error", bottomUpErrorName(o.bottomUpError));
    meta.emplace_back("tree.errorCap", errorCapped(o) ? "on" : "off");  // absent: off (before stop 41)
    meta.emplace_back("blocks.triangles", o.blockSize > 0 ? "" : std::to_string(blockTarget(o)));
    meta.emplace_back("blocks.size", o.blockSize > 0 ? formatConstant(o.blockSize) : "");
    meta.emplace_back("draco.positionBits", std::to_string(o.draco.positionBits));
    meta.emplace_back("draco.texcoordBits", std::to_string(o.draco.texcoordBits));
    meta.emplace_back("draco.colorBits", std::to_string(o.draco.colorBits));
    meta.emplace_back("draco.compressionLevel", std::to_string(o.draco.compressionLevel));
    meta.emplace_back("draco.positionStep", o.draco.positionStep > 0 ? formatConstant(o.draco.positionStep) : "auto");
    meta.emplace_back("jpeg.quality", std::to_string(o.jpegQuality));
    meta.emplace_back("jpeg.chroma", jpegChromaName(o.jpegChroma));
    if (!o.up.empty()) meta.emplace_back("up", o.up);
    if (offset) meta.emplace_back("offset", offsetText(o.read.offset));  // absent: nothing subtracted, as before the option
    return meta;
}

namespace {
// A shard's output may be absent, an empty folder or an earlier shard holding nothing else
// (replaced); anything else is refused rather than deleted.
void checkReplaceableShard(const std::string& output) {
    std::error_code ec;
    if (!fs::exists(output, ec)) return;
    if (!fs::is_directory(output, ec) || !(fs::is_empty(output, ec) || fs::exists(fs::path(output) / "shard.json", ec)))
        throw std::invalid_argument(output + ": exists and is not a shard folder (refusing to replace it)");
    const auto other = foreignEntry(output, [](const std::string& entry, bool isFolder) {
        static const std::regex record(R"(block_[0-9]+\.nodes)");
        return !isFolder && (entry == "shard.json" || std::regex_match(entry, record));
    });
    if (other) throw std::invalid_argument(output + ": holds " + *other + ", which a shard build does not write (refusing to replace it)");
}
}  // namespace

BuildSummary runBuild(const BuildRequest& request, Progress& progress) {
    BuildOptions options = request.options;
    if (request.shard) refuseOutputOverInputs(request.output, {request.input});  // a folder: replaceableShard below
    else checkOutputFile(request.output, "database", {request.input});  // before hours of work, not at the end
    checkOutputFile(buildReportPath(request.output), "build report", {request.input});  // written last, beside it
    options.read.outputs = {request.output, buildReportPath(request.output)};  // nor any file the input refers to
    validateConstants(options.constants, kUsedByBuild);
    checkBuildOptions(options);
    if (request.shard) checkReplaceableShard(request.output);
    std::optional<SplitWork> work;  // an `hlod split` work folder: its blocks, options and input
    if (isSplitWork(request.input)) {
        refuseOutputInsideFolder(request.output, request.input);  // -o WORK/manifest.json ruined it (until stop 44)
        work = openSplitWork(request.input, options, request.firstBlock, request.lastBlock);
        // The files the work folder names by path: a folder input's meshes, a mesh's textures
        // (overwritten by `-o` without a word until stop 47; a direct build refuses them).
        for (const std::string& output : options.read.outputs) {
            for (const BlockSource& b : work->inputs.blocks)
                if (!b.isPiece) refuseOutputOverInputs(output, {b.file});
            for (const Material& m : work->inputs.materials) refuseOutputOverInputs(output, {m.texturePath});
        }
    }
    const std::string input = work ? work->input : request.input;
    const UpChoice up = work ? work->up : chooseUpAxis(input, options.up);
    progress.message("up axis: " + up.axis + " (" + up.reason + ")");
    const fs::path outputParent = fs::absolute(request.output).parent_path();
    TempDir temp(options.tempDir.empty() ? outputParent.string() : options.tempDir);
    const SplitInputs inputs = work ? std::move(work->inputs) : findBlocks(input, options, temp.path, progress);
    if (work && inputs.grid) checkPositionStep(request.input, gridCell(inputs.bounds, *inputs.grid), options.draco.positionStep);
    malloc_trim(0);  // the split's freed buffers go back to the system, not to the main thread's heap alone
    fixMmapThreshold();
    const uint32_t blockCount = static_cast<uint32_t>(inputs.blocks.size());
    const uint32_t first = std::min(request.firstBlock, blockCount), last = std::min(request.lastBlock, blockCount);
    if (first >= last)  // a range past the end is cut to it (a workflow may ask for more than there are)
        throw std::invalid_argument(request.input + ": --blocks " + std::to_string(request.firstBlock) + ":" +
                                    std::to_string(request.lastBlock) + " selects none of its " + std::to_string(blockCount) +
                                    " blocks");

    // A shard is written into a staging folder next to it and renamed into place when complete.
    std::optional<StagingFolder> staging;
    if (request.shard) staging.emplace(fs::absolute(request.output).lexically_normal().string());
    const std::string recordDir = staging ? staging->path : (fs::path(temp.path) / "records").string();
    fs::create_directories(recordDir);

    // At most the threads the machine runs at once (its cores, as TBB counts them): a larger -j only
    // admitted more blocks at once to the memory gate, and TBB printed its own warning (until stop 46).
    const int cores = options.jobs > 0 ? std::min(options.jobs, tbb::info::default_concurrency()) : tbb::info::default_concurrency();
    if (options.jobs > cores)
        progress.message("note: -j " + std::to_string(options.jobs) + " is more than the " + std::to_string(cores) +
                         " threads this machine runs at once; " + std::to_string(cores) + " used");
    std::vector<BlockStats> stats(blockCount);
    MemoryGate gate(options.memoryLimit);
    TextureStore textures((fs::path(temp.path) / "textures").string(), options.memoryLimit);  // each file decoded once, read by rectangles
    BuildOptions blockOptions = options;  // a grid's blocks share one position lattice: no cracks between them
    blockOptions.textures = &textures;
    blockOptions.tempDir = temp.path;  // a bottom-up block's finished nodes wait there (blob_spill.h)
    if (blockOptions.draco.positionStep <= 0) blockOptions.draco.positionStep = inputs.positionStep;
    blockOptions.up = up.axis;
    blockOptions.read.imageDir = (fs::path(temp.path) / "gltf-images").string();
    progress.beginStage("build", expectedWork(inputs.blocks, first, last, options.constants));
    tbb::task_arena arena(std::max(1, cores));
    const auto buildBlocks = [&] {  // blocks in order, at most blocksAtOnce of them; every thread helps with their nodes
        taskBegin();
        uint32_t next = first;
        const auto take = [&](tbb::flow_control& control) {
            taskBegin();
            if (next == last) control.stop();
            const uint32_t b = next == last ? 0 : next++;
            taskEnd();
            return b;
        };
        const auto buildIt = [&](uint32_t b) {
            taskBegin();
            buildOne(inputs.blocks[b], inputs, b, recordDir, blockOptions, gate, progress, stats[b]);
            taskEnd();
        };
        const tbb::filter<void, void> filters = tbb::make_filter<void, uint32_t>(tbb::filter_mode::serial_in_order, take) &
                                                tbb::make_filter<uint32_t, void>(tbb::filter_mode::parallel, buildIt);
        taskEnd();  // tbb_sync.h
        tbb::parallel_pipeline(blocksAtOnce(cores), filters);
        taskBegin();
        taskEnd();
    };
    taskEnd();
    arena.execute(buildBlocks);
    taskBegin();
    progress.endStage();

    BuildSummary summary;
    summary.blockCount = blockCount;
    summary.gatePeak = gate.peak();
    std::set<TextureProblem> problems(inputs.textureProblems.begin(), inputs.textureProblems.end());
    for (uint32_t b = first; b < last; ++b) {
        for (const std::string& w : stats[b].warnings) progress.message("warning: " + w);
        for (const TextureProblem& p : stats[b].textureProblems)
            if (problems.insert(p).second) progress.message(untexturedWarning(p));  // a source shared by blocks: once
        if (stats[b].degenerateDropped)
            progress.message(inputs.blocks[b].file + ": dropped " + std::to_string(stats[b].degenerateDropped) +
                             " degenerate triangles");
        summary.inputTriangles += stats[b].inputTriangles;  // a block's, after the grid cuts
        if (summary.nodesPerLevel.size() < stats[b].nodesPerLevel.size()) summary.nodesPerLevel.resize(stats[b].nodesPerLevel.size());
        for (size_t l = 0; l < stats[b].nodesPerLevel.size(); ++l) summary.nodesPerLevel[l] += stats[b].nodesPerLevel[l];
        const BlockStats& st = stats[b];
        for (uint32_t i = 0; i < st.measured.size(); ++i)
            summary.nodes.push_back({b, i, st.levels[i], st.triangles[i], st.texels[i], st.measured[i].oneSided, st.measured[i].mean,
                                     st.measured[i].max, st.baked[i] != 0, st.bakePsnr[i], st.fidelity[i].texels,
                                     st.fidelity[i].samples, st.fidelity[i].squaredError});
    }
    summary.textureProblems.assign(problems.begin(), problems.end());
    uint64_t flattened = 0, triangles = 0, straddling = 0;
    for (uint32_t b = first; b < last; ++b)
        flattened += stats[b].flattened, triangles += stats[b].inputTriangles, straddling += stats[b].straddling;
    if (const std::string w = latticeFlattenedWarning(input, flattened, triangles); !w.empty()) progress.message("warning: " + w);
    const std::string files = first == 0 && last == blockCount ? input : input + " blocks " + std::to_string(first) + ":" + std::to_string(last);
    if (const std::string w = floatPrecisionOfFiles(files, std::span(stats).subspan(first, last - first), options.read.offset); !w.empty())
        progress.message("warning: " + w);  // a shard's: its own files' bounds
    if (straddling)  // wrap_uvs.cpp (without a word until stop 46)
        progress.message("warning: " + input + ": " + std::to_string(straddling) +
                         " UV charts cross an edge of their repeating texture; they read its border texels there "
                         "instead of repeating it (hlod stores no repeating textures)");
    // The whole input's count as read (the blocks' sum counts a triangle the grid cut once per piece:
    // +0.5 % on Lucy 1.6 M, +4 % on Lucy 100k in blocks of 20,000, until stop 46); a shard's, its blocks'.
    if (first == 0 && last == blockCount && inputs.inputTriangles) summary.inputTriangles = inputs.inputTriangles;
    ShardInfo shard{blockCount, {}, buildMeta(input, blockOptions)};
    for (uint32_t b = first; b < last; ++b) shard.blocks.push_back(b);
    writeShardInfo(recordDir, shard);
    if (staging) {
        staging->publish([&] {
            if (fs::exists(request.output)) fs::remove_all(request.output);  // an earlier shard, or an empty folder
            fs::rename(staging->path, request.output);
        });
    } else {
        progress.beginStage("write", blockCount, "blocks");
        mergeShards({recordDir}, request.output, options.constants.textured);
        progress.advance(blockCount);
        progress.endStage();
    }
    return summary;
}

}  // namespace hlod
