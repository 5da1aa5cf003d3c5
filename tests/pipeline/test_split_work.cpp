// `hlod split` and builds from its work folder (pipeline/split_work.h): split once, shards built
// from the work folder and merged give the bytes of one build (single mesh, textured OBJ, glTF
// with an embedded image, folder input); split and merge speak --progress-json; a missing,
// corrupt or foreign work folder is one line and exit status 2; the split's options are adopted;
// a split killed with SIGKILL anywhere leaves no work folder or a complete one.
#include "helpers.h"

#include "pipeline/split_work.h"
#include "tests/support/run_hlod.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <random>
#include <sstream>
#include <tuple>

namespace hlod::test {
namespace {

namespace fs = std::filesystem;

// Builds INPUT once, splits it, builds the work folder as two shards (blocks [0, cut) and the
// rest; one shard when `cut` is empty) and merges them: the same bytes as the single build.
// `extra`: options given to both the build and the split.
void expectSplitShardsMergeEqualOneBuild(TempDir& dir, const std::string& input, const std::vector<std::string>& extra,
                                         const std::string& cut) {
    auto run = [&](std::vector<std::string> args, const std::vector<std::string>& more = {}) {
        args.insert(args.end(), more.begin(), more.end());
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 0) << r.outAndErr();
        return r;
    };
    run({"build", input, "-o", dir.file("one.hlod")}, extra);
    run({"split", input, "-o", dir.file("work")}, extra);
    ASSERT_TRUE(fs::exists(dir.file("work/manifest.json")));
    if (cut.empty()) {
        run({"build", dir.file("work"), "-o", dir.file("s1"), "--shard"});
        run({"merge", dir.file("s1"), "-o", dir.file("merged.hlod")});
    } else {
        run({"build", dir.file("work"), "-o", dir.file("s1"), "--shard", "--blocks", "0:" + cut, "-j", "1"});
        run({"build", dir.file("work"), "-o", dir.file("s2"), "--shard", "--blocks", cut + ":9999"});
        run({"merge", dir.file("s2"), dir.file("s1"), "-o", dir.file("merged.hlod")});
    }
    EXPECT_EQ(readFile(dir.file("one.hlod")), readFile(dir.file("merged.hlod"))) << input;
    EXPECT_EQ(runHlod({"validate", dir.file("merged.hlod")}).exitCode, 0);
}

TEST(SplitWork, SingleMeshShardsFromTheWorkFolderEqualOneBuild) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(61).mesh, true);  // no grid line on a vertex row: cuts
    expectSplitShardsMergeEqualOneBuild(dir, dir.file("t.ply"), {"--block-triangles", "1500"}, "3");
    std::ifstream in(dir.file("work/manifest.json"));
    const nlohmann::json m = nlohmann::json::parse(in);
    EXPECT_EQ(m.at("format"), kSplitFormat);
    EXPECT_EQ(m.at("input"), dir.file("t.ply"));
    EXPECT_GE(m.at("block_count").get<int>(), 4);
    EXPECT_FALSE(m.at("grid").is_null());
    EXPECT_GT(m.at("lattice").at("position_step").get<double>(), 0);
    uint64_t triangles = 0;
    for (const auto& b : m.at("blocks")) {
        EXPECT_TRUE(fs::exists(dir.file("work/" + b.at("file").get<std::string>())));
        triangles += b.at("triangles").get<uint64_t>();
    }
    EXPECT_GT(triangles, 7442u);  // 2 x 61 x 61, plus the triangles the grid cuts
    // "Input triangles" are the input's, not the cut blocks' sum (which they were until stop 46), for a
    // build from the mesh and from the work folder alike; the manifest carries the count.
    EXPECT_EQ(m.at("input_triangles").get<uint64_t>(), 7442u);
    for (const std::string& input : {dir.file("t.ply"), dir.file("work")}) {
        const RunResult r = runHlod({"build", input, "-o", dir.file("whole.hlod"), "--block-triangles", "1500"});
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
        EXPECT_NE(r.out.find("summary: 7442 input triangles,"), std::string::npos) << r.out;
        std::ifstream report(dir.file("whole.hlod.build.json"));
        EXPECT_EQ(nlohmann::json::parse(report).at("input_triangles").get<uint64_t>(), 7442u);
    }
}

// A file name that is not UTF-8 (Latin-1 "café") travels through the build report, the work
// folder's manifest, the shard description and --progress-json as U+FFFD (before stop 44 each of
// these JSON writers threw nlohmann's type_error 316 once the work was done: exit 1, no output).
// The work and shard folders are readable by others (mkdtemp's 0700 before).
TEST(SplitWork, NamesThatAreNotUtf8AndFoldersOthersCanRead) {
    TempDir dir;
    const std::string input = dir.file("caf\xe9.ply");
    writePly(input, terrain(20).mesh, true);
    expectSplitShardsMergeEqualOneBuild(dir, input, {"--block-triangles", "300"}, "");
    const fs::perms others = fs::perms::others_read | fs::perms::others_exec;
    for (const char* folder : {"work", "s1"}) EXPECT_EQ(fs::status(dir.file(folder)).permissions() & others, others) << folder;
    std::ifstream report(dir.file("one.hlod.build.json"));
    EXPECT_FALSE(nlohmann::json::parse(report, nullptr, false).is_discarded());
    const RunResult r = runHlod({"build", input, "-o", dir.file("p.hlod"), "--progress-json"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    std::istringstream lines(r.err + r.out);
    size_t parsed = 0;
    for (std::string line; std::getline(lines, line);)
        if (!line.empty() && line[0] == '{') {
            EXPECT_FALSE(nlohmann::json::parse(line, nullptr, false).is_discarded()) << line;
            ++parsed;
        }
    EXPECT_GT(parsed, 0u);
}

// One line "hlod build: FILE: problem" and exit status 2, no shard written.
void expectRefused(const TempDir& dir, const std::vector<std::string>& args, const std::string& problem) {
    const RunResult r = runHlod(args);
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_NE(r.err.find(problem), std::string::npos) << problem << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir.file("shard/shard.json")));
}

// A vertex no triangle uses, far off, moves neither the grid nor the lattice (until stop 47 it set
// both: a 1.4 M-triangle grid became one block).
TEST(SplitWork, AnUnusedFarVertexMovesNeitherGridNorLattice) {
    TempDir dir;
    MeshData mesh = terrain(61).mesh;
    writePly(dir.file("t.ply"), mesh, true);
    mesh.positions.insert(mesh.positions.end(), {1e5f, 1e5f, 0.0f});
    if (!mesh.normals.empty()) mesh.normals.insert(mesh.normals.end(), {0.0f, 0.0f, 1.0f});
    if (!mesh.texcoords.empty()) mesh.texcoords.insert(mesh.texcoords.end(), {0.0f, 0.0f});
    if (!mesh.colors.empty()) mesh.colors.insert(mesh.colors.end(), {0, 0, 0, 255});
    writePly(dir.file("stray.ply"), mesh, true);
    for (const char* name : {"t", "stray"})
        ASSERT_EQ(runHlod({"split", dir.file(std::string(name) + ".ply"), "-o", dir.file(std::string(name) + "_work"), "--block-triangles", "2000"}).exitCode, 0);
    const auto manifest = [&](const char* name) {
        std::ifstream in(dir.file(std::string(name) + "_work/manifest.json"));
        return nlohmann::json::parse(in);
    };
    const nlohmann::json a = manifest("t"), b = manifest("stray");
    EXPECT_GT(a.at("block_count").get<int>(), 1);
    EXPECT_EQ(a.at("grid"), b.at("grid"));
    EXPECT_EQ(a.at("lattice"), b.at("lattice"));
    EXPECT_EQ(a.at("block_count"), b.at("block_count"));
}

TEST(SplitWork, TexturedObjAndFolderInputsEqualOneBuild) {
    TempDir dir;
    fs::create_directories(dir.file("scan"));
    writeObj(dir.file("scan/t.obj"), terrain(40, 100, true), "atlas.png");
    writeFile(dir.file("scan/atlas.png"), encodeTexture(testImage(64, 64), Codec::Png).bytes);
    expectSplitShardsMergeEqualOneBuild(dir, dir.file("scan/t.obj"), {"--block-triangles", "800"}, "2");
    // A texture changed or removed after the split: a shard refuses it (until stop 47 it was read as
    // it then was, so shards built before and after merged into a database of both versions).
    // Nor may its output be one of the files the work folder names (a texture, a folder's mesh):
    // they were overwritten, exit 0, until stop 47, as a direct build never allowed.
    expectRefused(dir, {"build", dir.file("work"), "-o", dir.file("scan/atlas.png")}, dir.file("scan/atlas.png") + ": is also an input");
    const std::string atlas = fs::canonical(dir.file("scan/atlas.png")).string();
    std::vector<uint8_t> changed = readFile(atlas);  // one byte changed, the length kept: the checksum tells
    changed[changed.size() / 2] ^= 0x5a;
    writeFile(atlas, changed);
    expectRefused(dir, {"build", dir.file("work"), "-o", dir.file("shard"), "--shard"},
                  atlas + ": texture of material 'mat0' of " + dir.file("work") + " differs from the split's (changed or corrupt since; split again)");
    fs::remove(atlas);
    expectRefused(dir, {"build", dir.file("work"), "-o", dir.file("shard"), "--shard"}, atlas + ": texture of material 'mat0' of " + dir.file("work") + " is missing (moved or deleted since the split; split again)");

    TempDir folder;
    for (const char* name : {"a", "b", "c"}) writePly(folder.file(std::string(name) + ".ply"), terrain(20).mesh, false);
    fs::create_directories(folder.file("in"));
    for (const char* name : {"a", "b", "c"}) fs::rename(folder.file(std::string(name) + ".ply"), folder.file(std::string("in/") + name + ".ply"));
    expectSplitShardsMergeEqualOneBuild(folder, folder.file("in"), {}, "1");
    const std::vector<uint8_t> mesh = readFile(folder.file("in/b.ply"));
    expectRefused(folder, {"build", folder.file("work"), "-o", folder.file("in/b.ply")}, folder.file("in/b.ply") + ": is also an input");
    EXPECT_EQ(readFile(folder.file("in/b.ply")), mesh);
}

// A texture's wrap travels in the manifest: charts exported a period away from a clamped texture
// stay where they are in the shards as in one build (a repeating one would move them).
TEST(SplitWork, TextureWrapTravelsInTheManifest) {
    TempDir dir;
    Piece p = terrain(40, 100, true);
    for (size_t v = 0; v < p.mesh.vertexCount(); ++v) p.mesh.texcoords[2 * v] += 2;
    writeObj(dir.file("t.obj"), p, "-clamp on atlas.png");
    writeFile(dir.file("atlas.png"), encodeTexture(testImage(64, 64), Codec::Png).bytes);
    expectSplitShardsMergeEqualOneBuild(dir, dir.file("t.obj"), {"--block-triangles", "800"}, "2");
    std::ifstream in(dir.file("work/manifest.json"));
    EXPECT_EQ(nlohmann::json::parse(in).at("materials").at(0).at("uv_period"), nlohmann::json::array({0, 0}));
}

// A glTF is split as a PLY is (streamed); its embedded image waits, still encoded, inside the
// work folder, named relative to it, so a moved work folder still builds the same database.
TEST(SplitWork, GltfEmbeddedImageTravelsInTheWorkFolder) {
    TempDir dir;
    std::ofstream(dir.file("t.gltf")) << texturedTriangleGltf(R"({"name": "skin", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}})",
                                                              R"({"source": 0})");
    expectSplitShardsMergeEqualOneBuild(dir, dir.file("t.gltf"), {}, "");
    std::ifstream in(dir.file("work/manifest.json"));
    EXPECT_EQ(nlohmann::json::parse(in).at("materials").at(0).at("texture"), "cells/gltf-images/image_0.png");
    EXPECT_TRUE(fs::exists(dir.file("work/cells/gltf-images/image_0.png")));
    fs::rename(dir.file("work"), dir.file("moved"));
    const RunResult moved = runHlod({"build", dir.file("moved"), "-o", dir.file("moved.hlod")});
    ASSERT_EQ(moved.exitCode, 0) << moved.outAndErr();
    EXPECT_EQ(readFile(dir.file("moved.hlod")), readFile(dir.file("one.hlod")));
}

TEST(SplitWork, SplitAndMergeSpeakProgressJson) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(30).mesh, true);
    const RunResult s = runHlod({"split", dir.file("t.ply"), "-o", dir.file("work"), "--progress-json", "--block-triangles", "600"});
    ASSERT_EQ(s.exitCode, 0) << s.outAndErr();
    for (const char* stage : {R"({"stage": "read")", R"({"stage": "split")", R"({"message": "up axis: z)"})
        EXPECT_NE(("\n" + s.out).find(std::string("\n") + stage), std::string::npos) << stage << "\n" << s.out;
    ASSERT_EQ(runHlod({"build", dir.file("work"), "-o", dir.file("s"), "--shard", "--progress-json"}).exitCode, 0);
    const RunResult m = runHlod({"merge", dir.file("s"), "-o", dir.file("m.hlod"), "--progress-json"});
    ASSERT_EQ(m.exitCode, 0) << m.outAndErr();
    EXPECT_EQ(m.out.rfind(R"({"stage": "write", "done": 0)", 0), 0u) << m.out;
    EXPECT_NE(m.out.find(R"("end": true})"), std::string::npos) << m.out;
}

TEST(SplitWork, BadWorkFoldersAreOneLineAndStatusTwo) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(30).mesh, true);
    ASSERT_EQ(runHlod({"split", dir.file("t.ply"), "-o", dir.file("work"), "--block-triangles", "600"}).exitCode, 0);
    const std::vector<uint8_t> manifest = readFile(dir.file("work/manifest.json"));
    const std::vector<std::string> build = {"build", dir.file("work"), "-o", dir.file("shard"), "--shard", "--blocks", "0:2"};
    ASSERT_EQ(runHlod(build).exitCode, 0);
    fs::remove_all(dir.file("shard"));

    const std::string cell = dir.file("work/cells/cell_0.piece");
    const std::vector<uint8_t> original = readFile(cell);
    std::vector<uint8_t> bytes = original;
    bytes[bytes.size() / 2] ^= 0x40;  // same size, other content
    writeFile(cell, bytes);
    expectRefused(dir, build, cell + ": block 0 of " + dir.file("work") + " differs from");
    ASSERT_EQ(runHlod({"build", dir.file("work"), "-o", dir.file("other"), "--shard", "--blocks", "2:4"}).exitCode, 0)
        << "blocks outside the range are checked by size only";
    fs::remove(cell);
    expectRefused(dir, build, cell + ": block 0 of " + dir.file("work") + " is missing");

    writeFile(dir.file("work/manifest.json"), std::vector<uint8_t>(manifest.begin(), manifest.begin() + manifest.size() / 2));
    expectRefused(dir, build, dir.file("work/manifest.json") + ": corrupt manifest");
    std::string text(manifest.begin(), manifest.end());
    text.replace(text.find(kSplitFormat), std::string(kSplitFormat).size(), "hlod-split-0");
    writeFile(dir.file("work/manifest.json"), std::vector<uint8_t>(text.begin(), text.end()));
    expectRefused(dir, build, dir.file("work/manifest.json") + ": not a hlod-split-2 manifest");
    std::string noBlocks(manifest.begin(), manifest.end());
    noBlocks.replace(noBlocks.find("\"blocks\""), 8, "\"blockz\"");
    writeFile(dir.file("work/manifest.json"), std::vector<uint8_t>(noBlocks.begin(), noBlocks.end()));
    expectRefused(dir, build, dir.file("work/manifest.json") + ": corrupt manifest");
    nlohmann::json noMaterials = nlohmann::json::parse(manifest.begin(), manifest.end());  // crashed before stop 36
    noMaterials["materials"] = nlohmann::json::array();
    const std::string emptied = noMaterials.dump();
    writeFile(dir.file("work/manifest.json"), std::vector<uint8_t>(emptied.begin(), emptied.end()));
    writeFile(cell, original);
    expectRefused(dir, build, cell + ": a triangle has material 0 but the input lists 0 (corrupt work folder? split again)");

    // Values no split writes (until stop 44: a step of 1e300 built a database of collapsed blocks
    // with status 0, an up axis 'x' or an offset of 1e300 one that validate refused).
    const nlohmann::json good = nlohmann::json::parse(manifest.begin(), manifest.end());
    const std::vector<std::tuple<std::string, nlohmann::json, std::string>> changes = {
        {"/lattice/position_step", 1e300, "lattice position_step is not its grid's"},
        {"/lattice/position_step", 1e-300, "lattice position_step is not its grid's"},
        {"/lattice/position_bits", 99, "position_bits out of range"},
        {"/up/axis", "x", "up axis 'x' is neither y nor z"},
        {"/options/up", "w", "--up 'w' is neither y nor z"},
        {"/options/offset", {1e300, 0, 0}, "offset beyond +-1e15"},
        {"/bounds/1/0", -1e30, "bounds out of range"},
        {"/grid/size_u", 0, "grid out of range"},
        {"/materials/0/texture", "../../x.png", "'../../x.png' is outside the work folder"},
        {"/materials/0/image", "../x.png", "'../x.png' is outside the work folder"}};
    for (const auto& [pointer, value, reason] : changes) {
        nlohmann::json changed = good;
        changed[nlohmann::json::json_pointer(pointer)] = value;
        const std::string text = changed.dump();
        writeFile(dir.file("work/manifest.json"), std::vector<uint8_t>(text.begin(), text.end()));
        expectRefused(dir, build, dir.file("work/manifest.json") + ": corrupt manifest (" + reason + ")");
    }
    nlohmann::json negative = good;  // a count no split writes
    negative["input_triangles"] = -1;
    std::string changedText = negative.dump();
    writeFile(dir.file("work/manifest.json"), std::vector<uint8_t>(changedText.begin(), changedText.end()));
    expectRefused(dir, build, dir.file("work/manifest.json") + ": corrupt manifest (input_triangles is not a whole number)");
    nlohmann::json missing = good;  // nlohmann's "[json.exception.out_of_range.403] " was shown until stop 46
    missing.erase("block_count");
    changedText = missing.dump();
    writeFile(dir.file("work/manifest.json"), std::vector<uint8_t>(changedText.begin(), changedText.end()));
    expectRefused(dir, build, dir.file("work/manifest.json") + ": corrupt manifest (key 'block_count' not found)\n");
    // An output inside the work folder would replace what it reads (exit 0 and a ruined folder before).
    writeFile(dir.file("work/manifest.json"), manifest);
    for (const std::string& out : {dir.file("work/manifest.json"), dir.file("work/cells/cell_0.piece"), dir.file("work/x.hlod")})
        expectRefused(dir, {"build", dir.file("work"), "-o", out}, out + ": is inside an input folder (" + dir.file("work") + ")");
    EXPECT_EQ(readFile(dir.file("work/manifest.json")), manifest);
    EXPECT_EQ(readFile(cell), original);
}

TEST(SplitWork, SplitOptionsBelongToTheSplitAndForeignFoldersAreNotReplaced) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(30).mesh, true);
    ASSERT_EQ(runHlod({"split", dir.file("t.ply"), "-o", dir.file("work"), "--block-triangles", "600"}).exitCode, 0);
    const RunResult conflict = runHlod({"build", dir.file("work"), "-o", dir.file("s"), "--shard", "--block-triangles", "700"});
    EXPECT_EQ(conflict.exitCode, 2) << conflict.outAndErr();
    EXPECT_NE(conflict.err.find("--block-triangles differs from the split of " + dir.file("work")), std::string::npos) << conflict.err;
    EXPECT_EQ(runHlod({"build", dir.file("work"), "-o", dir.file("s"), "--shard", "--block-triangles", "600"}).exitCode, 0);

    // An earlier work folder is replaced; any other non-empty folder is left alone.
    const RunResult again = runHlod({"split", dir.file("t.ply"), "-o", dir.file("work"), "--block-triangles", "300"});
    EXPECT_EQ(again.exitCode, 0) << again.outAndErr();
    EXPECT_NE(again.out.find("blocks"), std::string::npos);
    fs::create_directories(dir.file("mine"));
    writeFile(dir.file("mine/keep.txt"), {'x'});
    const RunResult foreign = runHlod({"split", dir.file("t.ply"), "-o", dir.file("mine")});
    EXPECT_EQ(foreign.exitCode, 2) << foreign.outAndErr();
    EXPECT_NE(foreign.err.find(dir.file("mine") + ": exists and is not an hlod split work folder"), std::string::npos) << foreign.err;
    EXPECT_TRUE(fs::exists(dir.file("mine/keep.txt")));
    for (const auto& e : fs::directory_iterator(dir.path))
        EXPECT_EQ(e.path().filename().string().find("work.tmp"), std::string::npos) << "staging folder left: " << e.path();
    const RunResult missing = runHlod({"split", dir.file("nope.ply"), "-o", dir.file("w2")});
    EXPECT_EQ(missing.exitCode, 2) << missing.outAndErr();
    EXPECT_FALSE(fs::exists(dir.file("w2")));

    // The same for a shard folder: an earlier shard is replaced, a foreign folder refused.
    const RunResult shardAgain = runHlod({"build", dir.file("work"), "-o", dir.file("s"), "--shard"});
    EXPECT_EQ(shardAgain.exitCode, 0) << shardAgain.outAndErr();
    EXPECT_TRUE(fs::exists(dir.file("s/shard.json")));
    const RunResult foreignShard = runHlod({"build", dir.file("work"), "-o", dir.file("mine"), "--shard"});
    EXPECT_EQ(foreignShard.exitCode, 2) << foreignShard.outAndErr();
    EXPECT_NE(foreignShard.err.find(dir.file("mine") + ": exists and is not a shard folder"), std::string::npos) << foreignShard.err;
    EXPECT_TRUE(fs::exists(dir.file("mine/keep.txt")));
    EXPECT_FALSE(fs::exists(dir.file("mine/shard.json")));

    // A marker file alone does not make a folder hlod's: a work folder or shard holding anything
    // else (a user's notes beside an earlier split's files) is refused, not replaced (until stop
    // 45 the whole folder was deleted, exit 0).
    writeFile(dir.file("work/notes.txt"), {'x'});
    const RunResult noted = runHlod({"split", dir.file("t.ply"), "-o", dir.file("work"), "--block-triangles", "300"});
    EXPECT_EQ(noted.exitCode, 2) << noted.outAndErr();
    EXPECT_EQ(noted.err, "hlod split: " + dir.file("work") + ": holds notes.txt, which hlod split does not write (refusing to replace it)\n");
    EXPECT_TRUE(fs::exists(dir.file("work/notes.txt")));
    EXPECT_TRUE(fs::exists(dir.file("work/manifest.json")));
    fs::create_directories(dir.file("s/plots"));
    const RunResult plotted = runHlod({"build", dir.file("work"), "-o", dir.file("s"), "--shard"});
    EXPECT_EQ(plotted.exitCode, 2) << plotted.outAndErr();
    EXPECT_EQ(plotted.err, "hlod build: " + dir.file("s") + ": holds plots, which a shard build does not write (refusing to replace it)\n");
    EXPECT_TRUE(fs::exists(dir.file("s/plots")));
    EXPECT_TRUE(fs::exists(dir.file("s/shard.json")));
}

TEST(SplitWork, KilledAnywhereLeavesNoWorkFolderOrACompleteOne) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(250).mesh, true);
    const std::vector<std::string> split = {"split", dir.file("t.ply"), "-o", dir.file("work"), "--block-triangles", "20000"};
    const auto start = std::chrono::steady_clock::now();
    ASSERT_EQ(runHlod(split).exitCode, 0);
    const auto duration = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start);
    std::mt19937 random(14);
    std::uniform_int_distribution<int64_t> at(duration.count() / 4, duration.count() * 6 / 5);
    int absent = 0;
    for (int k = 0; k < 20; ++k) {
        fs::remove_all(dir.file("work"));
        ASSERT_TRUE(test::runHlodAndKill(split, std::chrono::microseconds(at(random))));
        if (!fs::exists(dir.file("work"))) {
            ++absent;
            continue;
        }
        BuildOptions options;
        EXPECT_NO_THROW(openSplitWork(dir.file("work"), options, 0, UINT32_MAX)) << k;  // complete: every checksum holds
    }
    std::cout << "[ sweep    ] split: " << absent << " of 20 kills left no work folder\n";
    fs::remove_all(dir.file("work"));
    ASSERT_EQ(runHlod(split).exitCode, 0);
    for (const auto& e : fs::directory_iterator(dir.path))  // the killed splits' staging folders are gone
        EXPECT_EQ(e.path().filename().string().find("work.tmp-"), std::string::npos) << e.path();
}

}  // namespace
}  // namespace hlod::test
