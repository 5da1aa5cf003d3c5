// `hlod build` / `hlod merge` as a user runs them: exit codes, the one-line error, the summary,
// the <db>.build.json sidecar, and a database `hlod validate` accepts.
#include "helpers.h"

#include "formats/cli/huge_pages.h"
#include "formats/constants.h"
#include "formats/temp_files.h"
#include "tests/support/run_hlod.h"

#include <nlohmann/json.hpp>

namespace hlod::test {
namespace {

TEST(Cli, BuildPrintsConstantsSummaryAndWritesSidecar) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(50).mesh, true);
    const RunResult r = runHlod({"build", dir.file("t.ply"), "-o", dir.file("t.hlod"), "-j", "2", "--set", "c_desiredTris=500"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_NE(r.outAndErr().find("c_desiredTris=500"), std::string::npos) << r.outAndErr();
    EXPECT_NE(r.outAndErr().find("nodes per level: hlod0=1 hlod1=4"), std::string::npos) << r.outAndErr();
    EXPECT_NE(r.outAndErr().find("B/input triangle"), std::string::npos) << r.outAndErr();
    std::ifstream sidecar(dir.file("t.hlod.build.json"));
    const nlohmann::json j = nlohmann::json::parse(sidecar);
    EXPECT_EQ(j.at("input_triangles"), 5000);
    EXPECT_GT(j.at("peak_rss_bytes").get<uint64_t>(), 0u);
    EXPECT_EQ(j.at("output_bytes").get<uint64_t>(), std::filesystem::file_size(dir.file("t.hlod")));
    EXPECT_GE(j.at("stages").size(), 3u);
    const RunResult v = runHlod({"validate", dir.file("t.hlod")});
    EXPECT_EQ(v.exitCode, 0) << v.outAndErr();
    // More threads than the machine runs: a note, not TBB's own warning (until stop 46), the same bytes.
    const RunResult many = runHlod({"build", dir.file("t.ply"), "-o", dir.file("many.hlod"), "-j", "1024", "--set", "c_desiredTris=500"});
    ASSERT_EQ(many.exitCode, 0) << many.outAndErr();
    EXPECT_NE(many.out.find("note: -j 1024 is more than the "), std::string::npos) << many.out;
    EXPECT_EQ(many.outAndErr().find("TBB"), std::string::npos) << many.outAndErr();
    EXPECT_EQ(readFile(dir.file("many.hlod")), readFile(dir.file("t.hlod")));
}

// A coarsest level above 1.25 x its target (fins, edges of three faces, that no simplifier
// collapses) is warned of by the build (only `hlod stats` said so until stop 51); a plain terrain
// gives no warning.
TEST(Cli, BuildWarnsOfAnHlod0AboveItsTarget) {
    TempDir dir;
    Piece finned = terrain(60);
    addFins(finned, 3);
    writePly(dir.file("fins.ply"), finned.mesh, true);
    writePly(dir.file("plain.ply"), terrain(60).mesh, true);
    const RunResult r = runHlod({"build", dir.file("fins.ply"), "-o", dir.file("fins.hlod"), "--set", "c_desiredTris=500"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    const std::string warning = "warning: " + dir.file("fins.hlod") + ": 1 of 1 hlod0 nodes keep more than 1.25 x their target";
    EXPECT_NE(r.out.find(warning), std::string::npos) << r.out;
    const RunResult st = runHlod({"stats", dir.file("fins.hlod")});  // the same check as `hlod stats`
    EXPECT_NE(st.out.find(": MISSED"), std::string::npos) << st.out;
    const RunResult plain = runHlod({"build", dir.file("plain.ply"), "-o", dir.file("plain.hlod"), "--set", "c_desiredTris=500"});
    ASSERT_EQ(plain.exitCode, 0) << plain.outAndErr();
    EXPECT_EQ(plain.out.find("hlod0 nodes keep more"), std::string::npos) << plain.out;
}

// The build runs with its heap on transparent huge pages where the kernel offers them, re-executed
// with glibc.malloc.hugetlb=1 (formats/cli/huge_pages.h), says so, and records it in its report;
// HLOD_HUGE_PAGES=0 keeps 4 KiB pages (and so does a sanitizer's allocator). Both runs give the
// same database.
TEST(Cli, BuildRunsOnHugePagesUnlessOptedOut) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(30).mesh, true);
    std::ifstream modeFile("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(modeFile, mode);
    const bool offered = mode.find("[madvise]") != std::string::npos || mode.find("[always]") != std::string::npos;
    for (const bool optOut : {false, true}) {
        const std::string db = dir.file(optOut ? "small.hlod" : "huge.hlod");
        std::vector<std::string> argv = {"env", "-u", "GLIBC_TUNABLES", "-u", "HLOD_HUGE_PAGES"};
        if (optOut) argv.push_back("HLOD_HUGE_PAGES=0");
        argv.insert(argv.end(), {HLOD_BINARY, "build", dir.file("t.ply"), "-o", db});
        const RunResult r = runProcess(argv);
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
        const bool huge = offered && !optOut && cli::kGlibcMalloc;
        EXPECT_NE(r.out.find(huge ? "heap on 2 MiB pages" : "heap on 4 KiB pages"), std::string::npos) << r.out;
        std::ifstream sidecar(db + ".build.json");
        EXPECT_EQ(nlohmann::json::parse(sidecar).at("huge_pages").get<bool>(), huge) << (optOut ? "opted out" : "default");
    }
    EXPECT_EQ(readFile(dir.file("huge.hlod")), readFile(dir.file("small.hlod")));
}

TEST(Cli, BadInputIsOneLineAndNonZero) {
    TempDir dir;
    std::ofstream(dir.file("bad.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\n";
    const RunResult r = runHlod({"build", dir.file("bad.ply"), "-o", dir.file("bad.hlod")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.outAndErr().find("hlod build: " + dir.file("bad.ply") + ": truncated PLY header"), std::string::npos) << r.outAndErr();
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hlod")));
    const RunResult m = runHlod({"build", "/nonexistent.obj", "-o", dir.file("x.hlod")});
    EXPECT_EQ(m.exitCode, 2);
    EXPECT_NE(m.outAndErr().find("/nonexistent.obj: no such file"), std::string::npos) << m.outAndErr();
}

// A --memory-limit without its unit was a bound of that many bytes, accepted until stop 47 (the
// build spilled everything and warned at its end): below 16M it is a usage error, for split too.
TEST(Cli, MemoryLimitBelowTheLeastIsAUsageError) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(10).mesh, true);
    for (const std::string sub : {"build", "split"}) {
        const RunResult r = runHlod({sub, dir.file("t.ply"), "-o", dir.file("out"), "--memory-limit", "2"});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod " + sub + ": --memory-limit: 2 bytes is below the least, 16M; a size takes its unit, e.g. 512M, 2G (see --help)\n");
        EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
    }
    EXPECT_EQ(runHlod({"build", dir.file("t.ply"), "-o", dir.file("t.hlod"), "--memory-limit", "16M"}).exitCode, 0);
}

// The build report DB.build.json is an output like the database: until stop 47 it replaced a
// constants file or an MTL library of that name, exit 0.
TEST(Cli, TheBuildReportNeverReplacesAnInput) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(10).mesh, true);
    std::ofstream(dir.file("x.build.json")) << "c_desiredTris = 900\n";
    const RunResult config = runHlod({"build", dir.file("t.ply"), "-o", dir.file("x"), "--config", dir.file("x.build.json")});
    EXPECT_EQ(config.exitCode, 2) << config.outAndErr();
    EXPECT_EQ(config.err, "hlod build: " + dir.file("x.build.json") + ": is also an input (" + dir.file("x.build.json") +
                              "); write the output elsewhere\n");
    std::ofstream(dir.file("m.obj")) << "mtllib out.build.json\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
    std::ofstream(dir.file("out.build.json")) << "newmtl m\nKd 1 0 0\n";
    const RunResult mtl = runHlod({"build", dir.file("m.obj"), "-o", dir.file("out")});
    EXPECT_EQ(mtl.exitCode, 2) << mtl.outAndErr();
    EXPECT_NE(mtl.err.find("material library 'out.build.json' is the output of this run"), std::string::npos) << mtl.err;
    EXPECT_EQ(readFile(dir.file("x.build.json")).size(), 20u);
    EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
}

// The sweep of killed runs' temporaries removes only names this host's and PID namespace's runs
// make: until stop 47 a user's `hlod-build-2023-backup` folder beside the output and an input named
// `DB.tmp-2024-v1.ply` were deleted as a killed run's (exit 0), and runs in other containers or
// on other hosts sharing the folder deleted each other's live temporaries.
TEST(Cli, TheSweepOfKilledRunsLeavesOtherFilesOfAlikeNames) {
    TempDir dir;
    std::filesystem::create_directories(dir.file("hlod-build-2023-backup"));
    std::ofstream(dir.file("hlod-build-2023-backup/notes.txt")) << "mine\n";
    writePly(dir.file("db.tmp-2024-v1.ply"), terrain(10).mesh, true);
    const std::string otherHost = dir.file("hlod-build-hlod00000000-999999999-abcdef");
    std::filesystem::create_directories(otherHost);
    std::string ours = temporaryPattern(dir.file("hlod-build"), 999999999);
    ours.replace(ours.size() - 6, 6, "abcdef");
    std::filesystem::create_directories(ours);
    const RunResult r = runHlod({"build", dir.file("db.tmp-2024-v1.ply"), "-o", dir.file("db")});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_TRUE(std::filesystem::exists(dir.file("hlod-build-2023-backup/notes.txt")));
    EXPECT_TRUE(std::filesystem::exists(dir.file("db.tmp-2024-v1.ply")));
    EXPECT_TRUE(std::filesystem::exists(otherHost));
    EXPECT_FALSE(std::filesystem::exists(ours));  // a killed run's of this host: swept
}

// A node holds at most 65,536 blobs (one per material, a texture before a textured one's): more
// failed only at the merge, after the whole build, as a "corrupt block record file" (until stop 47).
TEST(Cli, ANodeOfMoreMaterialsThanItsBlobsHoldIsOneLine) {
    TempDir dir;
    std::ofstream obj(dir.file("m.obj")), mtl(dir.file("m.mtl"));
    obj << "mtllib m.mtl\n";
    constexpr int kMaterials = 65537;
    for (int i = 0; i < kMaterials; ++i) obj << "v " << i % 300 << " " << i / 300 << " 0\nv " << i % 300 + 1 << " " << i / 300 << " 0\nv " << i % 300 << " " << i / 300 + 1 << " 0\n";
    for (int i = 0; i < kMaterials; ++i) {
        obj << "usemtl m" << i << "\nf " << 3 * i + 1 << " " << 3 * i + 2 << " " << 3 * i + 3 << "\n";
        mtl << "newmtl m" << i << "\nKd 1 1 1\n";
    }
    obj.close(), mtl.close();
    const RunResult r = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--set", "c_desiredTris=100000", "-j", "1"});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_EQ(r.err, "hlod build: block 0: a level-0 node of 65537 materials needs 65537 blobs, more than the 65536 a node holds (formats/FORMAT.md)\n");
    EXPECT_FALSE(std::filesystem::exists(dir.file("m.hlod")));
}

// A name the folder takes but its temporary's does not: refused before the build (until stop 47
// the whole build ran, then failed creating the temporary, or wrote the database and failed on its report).
TEST(Cli, AnOutputNameWithoutRoomForItsTemporaryIsAUsageError) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(10).mesh, true);
    for (const size_t length : {230u, 220u}) {  // the database's temporary; the report's (DB.build.json's)
        const std::string out = dir.file(std::string(length, 'd'));
        const RunResult r = runHlod({"build", dir.file("t.ply"), "-o", out});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_NE(r.err.find(": its name of "), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
}

TEST(Cli, ShardsAndMerge) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(40).mesh, true);
    const auto build = [&](std::vector<std::string> args) {
        args.insert(args.begin(), {"build", dir.file("t.ply")});
        args.insert(args.end(), {"--block-triangles", "800", "--set", "c_desiredTris=300"});
        return runHlod(args);
    };
    ASSERT_EQ(build({"-o", dir.file("one.hlod")}).exitCode, 0);
    ASSERT_EQ(build({"-o", dir.file("s1"), "--shard", "--blocks", "0:2"}).exitCode, 0);
    ASSERT_EQ(build({"-o", dir.file("s2"), "--shard", "--blocks", "2:99", "-j", "1"}).exitCode, 0);
    const RunResult m = runHlod({"merge", dir.file("s1"), dir.file("s2"), "-o", dir.file("merged.hlod")});
    ASSERT_EQ(m.exitCode, 0) << m.outAndErr();
    EXPECT_EQ(readFile(dir.file("one.hlod")), readFile(dir.file("merged.hlod")));
    // the one constant a merge uses, the shards' c_textured (eq. 3.1), printed as every run does
    EXPECT_NE(m.out.find("constants: c_textured=" + hlod::formatConstant(hlod::Constants{}.textured) + " (the shards')\n"),
              std::string::npos) << m.out;
    const RunResult bad = runHlod({"merge", dir.file("s1"), "-o", dir.file("half.hlod")});
    EXPECT_EQ(bad.exitCode, 2);  // the shards given do not make a database: a usage error
    EXPECT_NE(bad.err.find("hlod merge: " + dir.file("s1") + ": block 2 of "), std::string::npos) << bad.outAndErr();
    EXPECT_NE(bad.err.find(" is in none of the 1 shard(s) given\n"), std::string::npos) << bad.outAndErr();

    // A damaged shard is one line naming the record file, status 2, no database: before stop 36 a
    // flipped byte merged (status 0, fresh checksums), an absurd blob size zero-filled 2 GB and
    // an absurd count ended in std::bad_alloc without a file name.
    const std::string records = dir.file("s1/block_000000.nodes");
    const std::vector<uint8_t> original = readFile(records);
    std::vector<uint8_t> flipped = original;
    flipped[flipped.size() - 100] ^= 0x10;  // inside the last blob's bytes
    const auto mergeFails = [&](const std::vector<uint8_t>& bytes, const std::string& problem) {
        writeFile(records, bytes);
        const RunResult r = runHlod({"merge", dir.file("s1"), dir.file("s2"), "-o", dir.file("bad.hlod")});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod merge: " + records + ": " + problem + "\n");
        EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hlod")));
    };
    mergeFails(flipped, "corrupt block record file (blob checksum mismatch)");
    std::vector<uint8_t> blobCount = original;  // the root record: tag, parent, level, block, bounds, cost, benefit, normal, error
    const size_t countAt = 4 * 4 + sizeof(Box3f) + 4 + 4 + sizeof(Vec3f) + 4;
    std::memset(blobCount.data() + countAt, 0xFF, 4);
    mergeFails(blobCount, "corrupt block record file (4294967295 blobs in one node)");
    std::vector<uint8_t> blobSize = original;  // the first blob's size, after its BlobRef and texture slot
    const uint64_t huge = uint64_t(1) << 31;
    std::memcpy(blobSize.data() + countAt + 4 + sizeof(BlobRef) + 4, &huge, 8);
    mergeFails(blobSize, "truncated block record file");
    std::vector<uint8_t> level = original;  // the root record's level: no blob covers it, the record's XXH3 does
    level[8] ^= 0x01;
    mergeFails(level, "corrupt block record file (record checksum mismatch)");
    // another block's record file in its place: a database of two roots for one block (until stop 45)
    mergeFails(readFile(dir.file("s2/block_000002.nodes")), "holds block 2's nodes (corrupt shard)");
    writeFile(records, original);

    // A shard of an hlod before stop 36 (records without checksums) is named as such.
    const std::string info = dir.file("s1/shard.json");
    std::string text = readText(info);
    text.replace(text.find("hlod-shard-2"), 12, "hlod-shard-1");
    std::ofstream(info) << text;
    const RunResult old = runHlod({"merge", dir.file("s1"), dir.file("s2"), "-o", dir.file("bad.hlod")});
    EXPECT_EQ(old.exitCode, 2);
    EXPECT_EQ(old.err, "hlod merge: " + info + ": a shard of an older hlod (hlod-shard-1): build it again\n");

    // shard.json has no checksum: a block count the shards do not list sizes nothing (2^32 - 1 ended in
    // std::bad_alloc, 10^8 took 3 GB first), and 0 blocks is no database (a 0-node one was written).
    text.replace(text.find("hlod-shard-1"), 12, "hlod-shard-2");
    const std::string current = text, second = readText(dir.file("s2/shard.json"));
    const std::string blocks = std::to_string(nlohmann::json::parse(current)["blockCount"].get<uint32_t>());
    const std::string count = "\"blockCount\": " + blocks;
    ASSERT_NE(current.find(count), std::string::npos) << current;
    for (const auto& [blockCount, problem] : std::vector<std::pair<std::string, std::string>>{
             {"4294967295", dir.file("s1") + ": block " + blocks + " of 4294967295 is in none of the 2 shard(s) given"},
             {"0", info + ": corrupt shard description (0 blocks)"}}) {
        for (const auto& [file, original] : {std::pair{info, current}, std::pair{dir.file("s2/shard.json"), second}}) {
            std::string changed = original;
            changed.replace(changed.find(count), count.size(), "\"blockCount\": " + blockCount);
            std::ofstream(file) << changed;
        }
        const RunResult r = runHlod({"merge", dir.file("s1"), dir.file("s2"), "-o", dir.file("bad.hlod")});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod merge: " + problem + "\n");
        EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hlod")));
    }
    // c_textured outside (0, 1] merged into a database no player opens, exit 0 (until stop 45).
    const std::string textured = "\"" + hlod::formatConstant(hlod::Constants{}.textured) + "\"";
    ASSERT_NE(current.find(textured), std::string::npos) << current;
    std::string changed = current;
    changed.replace(changed.find(textured), textured.size(), "\"-1\"");
    std::ofstream(info) << changed;
    std::ofstream(dir.file("s2/shard.json")) << second;
    const RunResult r = runHlod({"merge", dir.file("s1"), dir.file("s2"), "-o", dir.file("bad.hlod")});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_EQ(r.err, "hlod merge: " + info + ": c_textured = -1: must be in (0, 1]\n");
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hlod")));
}

// An output inside a shard folder replaced the merge's own input, exit 0 (until stop 44); --blocks
// without --shard built everything, then failed naming a temporary folder.
TEST(Cli, MergeNeverWritesIntoItsShardsAndBlocksNeedShard) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(20).mesh, true);
    ASSERT_EQ(runHlod({"build", dir.file("t.ply"), "-o", dir.file("s"), "--shard"}).exitCode, 0);
    const std::vector<uint8_t> info = readFile(dir.file("s/shard.json"));
    for (const std::string& out : {dir.file("s/shard.json"), dir.file("s/new.hlod")}) {
        const RunResult r = runHlod({"merge", dir.file("s"), "-o", out});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod merge: " + out + ": is inside an input folder (" + dir.file("s") + "); write the output elsewhere\n");
    }
    EXPECT_EQ(readFile(dir.file("s/shard.json")), info);
    EXPECT_FALSE(std::filesystem::exists(dir.file("s/new.hlod")));
    // The shard folder itself: an input, status 2 ("exists and is not a regular file", 1, until stop 47).
    const RunResult self = runHlod({"merge", dir.file("s"), "-o", dir.file("s")});
    EXPECT_EQ(self.exitCode, 2) << self.outAndErr();
    EXPECT_EQ(self.err, "hlod merge: " + dir.file("s") + ": is also an input (" + dir.file("s") + "); write the output elsewhere\n");
    const RunResult blocks = runHlod({"build", dir.file("t.ply"), "-o", dir.file("part.hlod"), "--blocks", "0:1"});
    EXPECT_EQ(blocks.exitCode, 2);
    EXPECT_EQ(blocks.err, "hlod build: --blocks requires --shard (see --help)\n");
    EXPECT_FALSE(std::filesystem::exists(dir.file("part.hlod")));
    // A range past the last block: one line naming the input ("no blocks selected" until stop 46).
    const RunResult none = runHlod({"build", dir.file("t.ply"), "-o", dir.file("none"), "--shard", "--blocks", "57:114"});
    EXPECT_EQ(none.exitCode, 2) << none.outAndErr();
    EXPECT_EQ(none.err.rfind("hlod build: " + dir.file("t.ply") + ": --blocks 57:114 selects none of its ", 0), 0u) << none.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("none")));
}

}  // namespace
}  // namespace hlod::test
