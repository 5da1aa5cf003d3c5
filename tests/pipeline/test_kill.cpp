// kill -9 sweeps and a full disk (README "Reliability"): `hlod build` (whole and --shard) and `hlod merge` are
// killed with SIGKILL at 30 seeded random points over an uninterrupted run's duration. After
// each kill nothing half-written opens as a database (the output is absent or complete; a whole
// one may remain under its temporary name when the kill lands between its magic and its rename), and
// the rerun removes the killed run's temporaries (formats/temp_files.h) and writes a database
// byte-identical to the uninterrupted one.
#include "helpers.h"

#include "tests/support/run_hlod.h"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <iostream>
#include <random>

namespace hlod::test {
namespace {

namespace fs = std::filesystem;

constexpr int kKills = 30;

// The files under `dir` (recursively) except `keep`.
std::vector<fs::path> filesUnder(const fs::path& dir, const std::vector<fs::path>& keep) {
    std::vector<fs::path> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && std::find(keep.begin(), keep.end(), e.path()) == keep.end()) out.push_back(e.path());
    return out;
}

bool opensAsDatabase(const fs::path& file) {
    try {
        Database::open(file.string());
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

struct KillSweep : ::testing::Test {
    TempDir dir;
    fs::path input = dir.path / "in" / "t.ply", out = dir.path / "out";
    std::vector<std::string> options = {"-j", "2", "--set", "c_desiredTris=300", "--block-triangles", "4000"};
    std::vector<uint8_t> reference;
    std::chrono::microseconds duration{0};

    void SetUp() override {
        fs::create_directories(input.parent_path());
        fs::create_directories(out);
        writePly(input.string(), terrain(60).mesh, true);
        const auto start = std::chrono::steady_clock::now();
        const RunResult r = runHlod(build((dir.path / "ref.hlod").string()));
        duration = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start);
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
        reference = readFile((dir.path / "ref.hlod").string());
    }
    std::vector<std::string> build(const std::string& output, const std::vector<std::string>& extra = {}) const {
        std::vector<std::string> a = {"build", input.string(), "-o", output};
        a.insert(a.end(), options.begin(), options.end());
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    }
    // Kills `args` at kKills points (seeded) in [0.25, 1.2) x `span` (before a quarter of the run
    // the process is still starting); after each,
    // every file under out/ but `complete` (absent or equal to `reference`) must not open as a
    // database unless it equals `reference` (a whole one left under its temporary name). Then
    // reruns `args`; the callers check that nothing but their kept files is left.
    void sweep(const std::vector<std::string>& args, const fs::path& complete, uint32_t seed,
               std::chrono::microseconds span) {
        std::mt19937 random(seed);
        interrupted = 0;
        std::uniform_int_distribution<int64_t> at(span.count() / 4, span.count() * 6 / 5);
        for (int k = 0; k < kKills; ++k) {
            ASSERT_TRUE(test::runHlodAndKill(args, std::chrono::microseconds(at(random))));
            if (fs::is_regular_file(complete)) {
                EXPECT_EQ(readFile(complete.string()), reference) << k;
            }
            // No half-written database opens. The writer puts the magic in just before the rename
            // (formats/writer.cpp), so a kill between the two leaves the whole database under its
            // temporary name (the next run removes it): that one may open, and must be complete.
            for (const fs::path& f : filesUnder(out, {complete})) {
                if (opensAsDatabase(f)) {
                    EXPECT_EQ(readFile(f.string()), reference) << k << ": " << f << " opens but is not whole";
                }
            }
            expectNoHalfShard(k);
            interrupted += leftTemporaries();  // a figure: how many kills landed mid-write (timing-dependent)
        }
        std::cout << "[ sweep    ] " << args[0] << ": " << interrupted << " of " << kKills
                  << " kills left temporaries behind\n";
        const RunResult r = runHlod(args);
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    }
    int interrupted = 0;
    // A shard folder is whole or absent: block records outside a temporary only beside shard.json
    // (a killed shard build leaves its staging folder, never a half-written shard).
    void expectNoHalfShard(int k) const {
        for (const auto& e : fs::recursive_directory_iterator(out)) {
            if (e.path().extension() != ".nodes") continue;
            bool temporary = false;  // inside a build's temporary folder or a staging folder
            for (const fs::path& part : fs::relative(e.path(), out)) {
                const std::string name = part.string();
                temporary = temporary || name.rfind("hlod-build-", 0) == 0 || name.find(".tmp-") != std::string::npos;
            }
            const fs::path folder = e.path().parent_path();
            if (!temporary) {
                EXPECT_TRUE(fs::exists(folder / "shard.json")) << k << ": half-written shard " << folder;
            }
        }
    }
    // Whether out/ holds a build folder or a database temporary of a killed run.
    bool leftTemporaries() const {
        for (const auto& e : fs::recursive_directory_iterator(out)) {
            const std::string name = e.path().filename().string();
            if (name.rfind("hlod-build-", 0) == 0 || name.find(".tmp-") != std::string::npos) return true;
        }
        return false;
    }
    void expectOnly(const std::vector<fs::path>& keep) {
        for (const fs::path& f : filesUnder(out, keep)) ADD_FAILURE() << "left behind: " << f;
        for (const auto& e : fs::directory_iterator(out))
            EXPECT_FALSE(e.path().filename().string().rfind("hlod-build-", 0) == 0) << "left behind: " << e.path();
    }
};

TEST_F(KillSweep, BuildKilledAnywhereLeavesNoDatabaseAndRerunIsIdentical) {
    const fs::path db = out / "t.hlod";
    sweep(build(db.string()), db, 15, duration);
    EXPECT_EQ(readFile(db.string()), reference);
    expectOnly({db, out / "t.hlod.build.json"});
}

TEST_F(KillSweep, ShardBuildAndMergeKilledAnywhere) {
    const fs::path a = out / "shardA", b = out / "shardB", db = out / "m.hlod";
    sweep(build(a.string(), {"--shard", "--blocks", "0:1"}), a / "none", 16, duration);
    ASSERT_EQ(runHlod(build(b.string(), {"--shard", "--blocks", "1:100"})).exitCode, 0);
    const std::vector<fs::path> shardFiles = filesUnder(out, {});
    const std::vector<std::string> merge = {"merge", a.string(), b.string(), "-o", db.string()};
    const auto start = std::chrono::steady_clock::now();  // a merge is much shorter than a build
    ASSERT_EQ(runHlod({"merge", a.string(), b.string(), "-o", (dir.path / "m.hlod").string()}).exitCode, 0);
    sweep(merge, db, 17, std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start));
    EXPECT_EQ(readFile(db.string()), reference);
    std::vector<fs::path> keep = shardFiles;
    keep.push_back(db);
    expectOnly(keep);
}

// SIGINT, SIGTERM and SIGHUP (Ctrl-C, kill, a closed terminal) at seeded points over a build and a
// shard build: the run ends by that signal (or has finished: status 0), leaves no temporary (each
// left its own until stop 45: formats/interrupt.h), and the earlier database stays whole.
TEST_F(KillSweep, InterruptedAnywhereLeavesNoTemporaries) {
    const fs::path db = out / "t.hlod";
    fs::copy_file(dir.path / "ref.hlod", db);  // an earlier output: kept, or replaced by the same bytes
    std::mt19937 random(45);
    std::uniform_int_distribution<int64_t> at(duration.count() / 4, duration.count() * 6 / 5);
    const int signals[] = {SIGINT, SIGTERM, SIGHUP};
    const int runs = 12;
    int ended = 0;
    for (int k = 0; k < runs; ++k) {
        const int signal = signals[k % 3];
        const auto args = k % 2 ? build(db.string()) : build((out / "shard").string(), {"--shard"});
        int status = 0;
        ASSERT_TRUE(test::runHlodAndKill(args, std::chrono::microseconds(at(random)), signal, &status));
        EXPECT_TRUE((WIFSIGNALED(status) && WTERMSIG(status) == signal) || (WIFEXITED(status) && WEXITSTATUS(status) == 0))
            << k << ": wait status " << status;
        ended += WIFSIGNALED(status);
        EXPECT_FALSE(leftTemporaries()) << k << ": signal " << signal;
        EXPECT_EQ(readFile(db.string()), reference) << k;
        expectNoHalfShard(k);
    }
    std::cout << "[ sweep    ] " << ended << " of " << runs << " runs ended by their signal\n";
    EXPECT_GT(ended, 0);
}

// A signal the parent ignores stays ignored (`nohup hlod build`, a background job's SIGINT): hlod
// blocked it to wait for it, a blocked signal is queued even when ignored, and the run ended by
// it (until stop 49). Here SIGHUP, ignored by the shell that starts the build, arrives mid-build.
TEST_F(KillSweep, ASignalTheParentIgnoresStaysIgnored) {
    const fs::path db = out / "ignored.hlod";
    std::string command = "trap '' HUP; '" HLOD_BINARY "'";
    for (const std::string& a : build(db.string())) command += " '" + a + "'";
    const std::string delay = std::to_string(duration.count() / 2 / 1e6);
    const RunResult r = runProcess({"bash", "-c", command + " >/dev/null & sleep " + delay + "; kill -HUP $!; wait $!"});
    EXPECT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_EQ(readFile(db.string()), reference);
}

// A full disk (a tmpfs of half the database's size, mounted when running as root): the build
// fails with one line and status 1, leaving no database and no temporaries.
TEST_F(KillSweep, FullDiskFailsWithOneLineAndLeavesNothing) {
    if (geteuid() != 0) GTEST_SKIP() << "mounting a tmpfs needs root";
    const fs::path disk = dir.path / "disk";
    fs::create_directories(disk);
    const std::string size = "size=" + std::to_string(reference.size() / 2);
    if (runProcess({"mount", "-t", "tmpfs", "-o", size, "tmpfs", disk.string()}).exitCode != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here";
    const fs::path db = disk / "t.hlod";
    const RunResult r = runHlod(build(db.string()));
    std::vector<std::string> left;
    for (const auto& e : fs::recursive_directory_iterator(disk)) left.push_back(e.path().string());
    runProcess({"umount", disk.string()});
    EXPECT_EQ(r.exitCode, 1) << r.outAndErr();
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("hlod build: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
    EXPECT_EQ(left, std::vector<std::string>{}) << r.err;
}

}  // namespace
}  // namespace hlod::test
