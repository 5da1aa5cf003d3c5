// `hlod play` (and `hlod path` writing its paths) as a user runs them: outputs (CSV with the documented header,
// JSON summary, path file) and, for each class of bad input, one line naming the file,
// a non-zero status and no half-written output; a corrupt node below hlod0 is a warning.
#include "formats/constants.h"
#include "formats/db.h"
#include "player/stats.h"
#include "tests/player/cli_fixture.h"
#include "tests/support/fix_checksums.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace hlod;
using hlod::test::RunResult;
using hlod::test::readText;
using hlod::test::runHlod;
using hlod::test::runProcess;

TEST_F(Cli, PlayWritesCsvAndJsonSummary) {
    std::string path = walk();
    std::string csv = (dir / "walk.csv").string(), json = (dir / "walk.json").string();
    RunResult r = runHlod({"play", db, "--path", path, "--stats", csv, "--json", json, "--frames", "100", "--sync-loader", "--set", "c_targetTime=20"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("constants: "), std::string::npos);
    EXPECT_NE(r.out.find("c_targetTime=20"), std::string::npos);
    EXPECT_NE(r.out.find("c_textured: " + hlod::formatConstant(hlod::Constants{}.textured) + " (the database's"),
              std::string::npos) << r.out;  // the database's constant the run uses
    std::istringstream in(readText(csv));
    std::string line, header;
    int rows = 0;
    while (std::getline(in, line)) {
        if (line.starts_with("#")) continue;
        if (header.empty())
            header = line;
        else
            ++rows;
    }
    std::string expected;
    for (const std::string& h : statsHeader(3)) expected += (expected.empty() ? "" : ",") + h;
    EXPECT_EQ(header, expected);
    EXPECT_EQ(rows, 100);
    auto j = nlohmann::json::parse(readText(json));
    EXPECT_EQ(j["frames"], 100);
    EXPECT_EQ(j["constants"]["c_targetTime"], "20");

    // --json -: stdout is the JSON alone, the text on stderr (both on stdout until stop 45)
    r = runHlod({"play", db, "--path", path, "--json", "-", "--frames", "100", "--sync-loader", "--set", "c_targetTime=20"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["frames"], 100) << r.out;
    EXPECT_NE(r.err.find("c_targetTime=20"), std::string::npos) << r.err;
}

// A database named with a newline: the CSV's `# database:` line broke in two, its second half
// read as the column header (until stop 45); control characters are shown as '?'.
TEST_F(Cli, CsvCommentLinesStayOneLineWhateverTheNames) {
    const std::string named = (dir / "a\nb\x1b.hlod").string(), csv = (dir / "n.csv").string();
    fs::copy_file(db, named);
    const RunResult r = runHlod({"play", named, "--path", walk(), "--stats", csv, "--frames", "5", "--sync-loader"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::istringstream in(readText(csv));
    std::string line;
    while (std::getline(in, line) && line.starts_with("#")) EXPECT_EQ(line.find('\x1b'), std::string::npos) << line;
    EXPECT_EQ(line.rfind("frame,", 0), 0u) << line;  // the first line that is not a comment is the header
    EXPECT_NE(readText(csv).find("# database: " + (dir / "a?b?.hlod").string() + "\n"), std::string::npos);
}

// A memory budget below the hlod0 set loaded nothing, exit 0 (§4.3: hlod0 stays resident);
// --preload with a budget below the database ran; options that need another one were ignored;
// `merge ''` read ./shard.json (all until stop 45).
TEST_F(Cli, MemoryBelowHlod0AndOptionsWithoutTheirPartnerAreUsageErrors) {
    const std::string path = walk();
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"play", db, "--path", path, "--sync-loader", "--memory", "1"}, "hlod play: --memory 1 is below the "},
        // a size takes its unit, as build's --memory-limit (refused as no number until stop 48)
        {{"play", db, "--path", path, "--sync-loader", "--memory", "1K"}, "hlod play: --memory 1024 is below the "},
        // a target frame of more than 10 s, as every other frame time (accepted until stop 48)
        {{"play", db, "--path", path, "--set", "c_targetTime=1e9"}, "hlod play: c_targetTime = 1e+09: must be > 0 and at most 10000"},
        {{"compare", db, "--path", path, "--policies", "thesis", "--preload", "--memory", "1", "--no-plots", "-o",
          (dir / "c").string()},
         "hlod compare: --preload needs every node in memory: "},
        {{"play", db, "--path", path, "--sync-loads", "5"}, "hlod play: --sync-loads requires --sync-loader"},
        {{"play", db, "--path", path, "--sync-loader", "--every", "3"}, "hlod play: --every requires --frames-dir"},
        {{"play", db, "--path", path, "--sync-loader", "--color-by-level"}, "hlod play: --color-by-level needs --renderer gl"},
        {{"play", db, "--path", path, "--sync-loader", "--frames-dir", (dir / "png").string()}, "hlod play: --frames-dir needs --renderer gl"},
        {{"merge", "", "-o", (dir / "m.hlod").string()}, "hlod merge: SHARDS: an empty path"},
        // the CSV was lost under the JSON until stop 47
        {{"play", db, "--path", path, "--sync-loader", "--stats", (dir / "s.out").string(), "--json", (dir / "./s.out").string()},
         "hlod play: --stats and --json name the same file ("},
        // accepted and ignored until stop 46
        {{"play", db, "--path", path, "--sync-loader", "--vm-delta", "50"}, "hlod play: --vm-delta needs --loader vm"},
        {{"compare", db, "--path", path, "--policies", "thesis", "--loader", "demand", "--vm-bins", "5", "--no-plots", "-o",
          (dir / "c").string()},
         "hlod compare: --vm-bins needs --loader vm"}};
    for (const auto& [args, message] : cases) {
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(r.err.rfind(message, 0), 0u) << r.err;
        EXPECT_EQ(lines(r.err), 1) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "c.csv"));
}

TEST_F(Cli, MissingDatabaseIsOneLine) {
    std::string path = walk();
    RunResult r = runHlod({"play", (dir / "absent.hlod").string(), "--path", path});
    EXPECT_NE(r.exitCode, 0);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("absent.hlod"), std::string::npos) << r.err;
}

TEST_F(Cli, TruncatedDatabaseIsOneLineStatus2AndNoCsv) {  // cannot be opened as a database
    std::string path = walk();
    std::string cut = (dir / "cut.hlod").string();
    fs::copy_file(db, cut);
    fs::resize_file(cut, fs::file_size(cut) / 2);
    std::string csv = (dir / "cut.csv").string();
    RunResult r = runHlod({"play", cut, "--path", path, "--stats", csv});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("cut.hlod"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(csv));
}

// An output that cannot be replaced (here a folder in its place; a full disk and a missing folder
// take the same way): status 1, one line naming it and why, and nothing left beside it: no
// temporary, no half-written file, the folder untouched (formats/temp_files.h TextFileWriter).
TEST_F(Cli, TextOutputsThatCannotBeWrittenLeaveNothingBehind) {
    const std::string path = walk();
    const fs::path taken = dir / "taken";
    for (const char* name : {"stats.csv", "summary.json", "out.path", "cmp.txt", "cmp.csv"}) fs::create_directories(taken / name);
    const std::string in = (taken / "").string();
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"play", db, "--path", path, "--sync-loader", "--stats", in + "stats.csv"}, in + "stats.csv: cannot write statistics (exists and is not a regular file)"},
        {{"play", db, "--path", path, "--sync-loader", "--json", in + "summary.json"}, in + "summary.json: cannot write summary (exists and is not a regular file)"},
        {{"path", db, "-o", in + "out.path"}, in + "out.path: cannot write camera path (exists and is not a regular file)"},
        {{"compare", db, "--path", path, "--policies", "thesis", "--no-plots", "-o", in + "cmp"}, in + "cmp.txt: cannot write the table (exists and is not a regular file)"},
        {{"path", db, "-o", (dir / "absent" / "x.path").string()}, (dir / "absent" / "x.path").string() + ": cannot write camera path ("}};
    for (const auto& [args, message] : cases) {
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 1) << args[0] << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1) << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    }
    size_t entries = 0;
    for (const auto& e : fs::directory_iterator(taken)) {
        EXPECT_TRUE(e.is_directory() && fs::is_empty(e.path())) << e.path();
        ++entries;
    }
    EXPECT_EQ(entries, 5u);  // the five folders, nothing else
}

// A full disk: the writes fail part-way (here a file-size limit of 1 KiB with SIGXFSZ ignored,
// so write() returns EFBIG as it returns ENOSPC on a full disk; no root or mount needed): one
// line, exit 1, neither the output nor its temporary left behind.
TEST_F(Cli, TextOutputOnAFullDiskFailsWithOneLineAndLeavesNothing) {
    const std::string path = walk();
    const fs::path out = dir / "full";
    fs::create_directories(out);
    const std::string csv = (out / "stats.csv").string();
    const RunResult r = runProcess({"sh", "-c", "ulimit -f 2; trap '' XFSZ; exec \"$0\" \"$@\"", HLOD_BINARY, "play", db,
                                    "--path", path, "--sync-loader", "--frames", "200", "--stats", csv});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("hlod play: " + csv + ": cannot write statistics (write failed"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_empty(out)) << "left behind: " << fs::directory_iterator(out)->path();
    // An export says why too (until stop 44 only "FILE: cannot write").
    const RunResult tiles = runProcess({"sh", "-c", "ulimit -f 2; trap '' XFSZ; exec \"$0\" \"$@\"", HLOD_BINARY, "export", "tiles", db,
                                        "-o", (out / "tiles").string()});
    EXPECT_EQ(tiles.exitCode, 1) << tiles.err;
    EXPECT_EQ(lines(tiles.err), 1) << tiles.err;
    EXPECT_NE(tiles.err.find(": cannot write (File too large)"), std::string::npos) << tiles.err;
    EXPECT_TRUE(fs::is_empty(out)) << "left behind: " << fs::directory_iterator(out)->path();
}

// An output never replaces what is not a regular file (a FIFO here; as root `-o /dev/null`
// replaced /dev/null before stop 36): status 1, the FIFO left as it was. An output that is one of
// the run's inputs (the same file, through a symbolic link too) is a usage error, status 2, the
// input untouched (before stop 36 `play --stats PATHFILE` replaced the camera path).
TEST_F(Cli, OutputsNeverReplaceADeviceOrAnInput) {
    const std::string path = walk();
    const std::string fifo = (dir / "fifo").string(), link = (dir / "link.hlod").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    fs::create_symlink(db, link);
    const std::string cmpPath = (dir / "cmp.csv").string();
    fs::copy_file(path, cmpPath);
    const std::string dbBytes = readText(db), pathBytes = readText(path);
    RunResult r = runHlod({"path", db, "-o", fifo});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.err, "hlod path: " + fifo + ": cannot write camera path (exists and is not a regular file)\n");
    EXPECT_TRUE(fs::is_fifo(fifo));
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"play", db, "--path", path, "--sync-loader", "--stats", path}, "hlod play: " + path + ": is also an input (" + path + ")"},
        {{"play", db, "--path", path, "--sync-loader", "--json", link}, "hlod play: " + link + ": is also an input (" + db + ")"},
        {{"path", db, "-o", db}, "hlod path: " + db + ": is also an input (" + db + ")"},
        {{"compare", db, "--path", cmpPath, "--policies", "thesis", "--no-plots", "-o", (dir / "cmp").string()},
         "hlod compare: " + cmpPath + ": is also an input (" + cmpPath + ")"},  // -o cmp writes cmp.csv
        {{"export", "tiles", db, "--3tz", "-o", link}, "hlod export tiles: " + link + ": is also an input (" + db + ")"}};
    for (const auto& [args, message] : cases) {
        r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << args[0] << ": " << r.err;
        EXPECT_EQ(r.err, message + "; write the output elsewhere\n");
    }
    // A file output named with a trailing '/' (build failed at the end with "cannot create a
    // temporary folder (Not a directory)" until stop 45): refused before any work.
    const std::string slash = (dir / "f.out/").string();
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"path", db, "-o", slash}, {"play", db, "--path", path, "--sync-loader", "--stats", slash}, {"build", path, "-o", slash}}) {
        r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << args[0] << ": " << r.err;
        EXPECT_NE(r.err.find(slash + ": names a folder (ends in '/')"), std::string::npos) << r.err;
    }
    EXPECT_EQ(readText(db), dbBytes);
    EXPECT_EQ(readText(path), pathBytes);
    EXPECT_TRUE(fs::is_symlink(link));
}

// META c_textured that is not a number in (0, 1] (here 1e309, beyond double) is one line and
// status 1 for play and compare alike (compare printed "stod" before stop 36).
TEST_F(Cli, DatabaseCTexturedOutOfRangeIsOneLine) {
    const std::string path = walk();
    std::string bytes = readText(db);
    const size_t at = bytes.find("c_textured");
    ASSERT_NE(at, std::string::npos);
    const size_t value = bytes.find("0.127", at);
    ASSERT_LT(value - at, 20u);
    bytes.replace(value, 5, "1e309");
    std::vector<uint8_t> file(bytes.begin(), bytes.end());
    test::fixChecksums(file);
    std::ofstream(db, std::ios::binary).write(reinterpret_cast<const char*>(file.data()), std::streamsize(file.size()));
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"play", db, "--path", path, "--frames", "5"}, {"compare", db, "--path", path, "--policies", "thesis", "--frames", "5"}}) {
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 1) << r.err;
        EXPECT_EQ(r.err, "hlod " + args[0] + ": " + db + ": metadata c_textured is not in (0, 1]\n");
    }
}

TEST_F(Cli, BadPathFileIsOneLineWithLineNumber) {
    std::string bad = (dir / "bad.path").string();
    std::ofstream(bad) << "hlod-camera-path 1\n0 0 0 1.7 0 0 0 1 60\n1 0 0 1.7 0 0 0 1\n";
    RunResult r = runHlod({"play", db, "--path", bad});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("bad.path:3:"), std::string::npos) << r.err;
}

TEST_F(Cli, FramesDirNeedsGlAndBadConstantIsRejected) {
    std::string path = walk();
    RunResult r = runHlod({"play", db, "--path", path, "--frames-dir", (dir / "png").string()});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    r = runHlod({"play", db, "--path", path, "--set", "c_vis=abc"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
}

// The vm loader's bins are rebuilt whenever the view moves: an absurd count is a usage error
// (before: 10^6 bins ran for minutes and 1.6 GB, 10^10 ended in a C++ library's message).
TEST_F(Cli, AbsurdVmBinCountsAreUsageErrors) {
    const std::string path = walk();
    for (const char* option : {"--vm-bins", "--vm-delta"})
        for (const char* value : {"1e6", "1e10", "101"}) {
            RunResult r = runHlod({"play", db, "--path", path, "--sync-loader", "--loader", "vm", option, value});
            EXPECT_EQ(r.exitCode, 2) << option << " " << value;
            EXPECT_EQ(lines(r.err), 1) << r.err;
            EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
            EXPECT_NE(r.err.find("expected a finite number in (0, 100]"), std::string::npos) << r.err;  // one range, as --help
        }
    RunResult r = runHlod({"play", db, "--path", path, "--sync-loader", "--loader", "vm", "--vm-bins", "100", "--vm-delta", "100"});
    EXPECT_EQ(r.exitCode, 0) << r.err;
}

// Blocks of one node (an input smaller than c_desiredTris): the vm loader's prefetch pops a
// resident hlod0 with nothing around it (before stop 44 it then read an empty queue: SIGSEGV).
TEST_F(Cli, VmLoaderPlaysBlocksOfOneNode) {
    SyntheticOptions o;
    o.levels = 1;
    const std::string flat = (dir / "flat.hlod").string();
    writeSyntheticDatabase(flat, o);
    const std::string path = (dir / "flat.path").string();
    ASSERT_EQ(runHlod({"path", flat, "--kind", "fly", "--duration", "5", "-o", path}).exitCode, 0);
    for (const char* sync : {"--sync-loader", "--uploads=4"}) {
        RunResult r = runHlod({"play", flat, "--path", path, "--loader", "vm", sync});
        EXPECT_EQ(r.exitCode, 0) << sync << ": " << r.err;
    }
}

TEST_F(Cli, CalibrationFileSetsInitialVTimeAndOverhead) {
    std::string path = walk();
    std::string cal = (dir / "cal.conf").string();
    std::ofstream(cal) << "# formats/calibration.h\nrenderer = test\nc_textured = 0.5\nms_per_cost = 0.0123\nfixed_overhead_ms = 4.5\n";
    std::string csv = (dir / "cal.csv").string();
    RunResult r = runHlod({"play", db, "--path", path, "--sync-loader", "--frames", "5", "--calibration", cal, "--stats", csv});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::string text = readText(csv);
    EXPECT_NE(text.find("# overhead_ms: 4.500000"), std::string::npos) << text.substr(0, 600);
    EXPECT_NE(text.find("# initial_v_time: 0.012300"), std::string::npos) << text.substr(0, 600);

    std::string notCal = (dir / "notcal.conf").string();
    std::ofstream(notCal) << "c_textured = 0.5\n";
    r = runHlod({"play", db, "--path", path, "--calibration", notCal});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("notcal.conf: not a calibration file"), std::string::npos) << r.err;

    std::ofstream(notCal) << "c_textured = 0.5\nms_per_cost = -1\nfixed_overhead_ms = 4.5\n";
    r = runHlod({"play", db, "--path", path, "--calibration", notCal});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("notcal.conf:2: ms_per_cost '-1' is not a finite non-negative number"), std::string::npos) << r.err;

    // finite but absurd: a frame of 1e300 ms (before stop 38 accepted and printed in 300 digits)
    std::ofstream(notCal) << "c_textured = 0.5\nms_per_cost = 0.01\nfixed_overhead_ms = 1e300\n";
    r = runHlod({"play", db, "--path", path, "--calibration", notCal});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("notcal.conf: fixed_overhead_ms = 1e+300 is absurd (a frame of more than 10 s)"), std::string::npos) << r.err;
}

// One flipped byte in one node's blob does not end a replay: one warning line naming the
// database, node and problem, exit 0, the statistics written with failed_loads 1. --strict
// makes it fatal: exit 1, one error line, no CSV.
TEST_F(Cli, CorruptNodeIsSkippedWithOneWarningUnlessStrict) {
    uint32_t node = 0, blob = 0;
    {
        const Database database = Database::open(db);
        node = database.skeleton().children(database.skeleton().roots()[0])[0];
        blob = database.skeleton().nodes[node].firstBlob;
        const BlobRef& ref = database.skeleton().blobs[blob];
        std::fstream f(db, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(ref.offset + ref.size / 2));
        char x = char(f.get() ^ 0xff);
        f.seekp(std::streamoff(ref.offset + ref.size / 2));
        f.put(x);
    }
    std::string path = (dir / "fly.path").string();
    ASSERT_EQ(runHlod({"path", db, "--kind", "fly", "--duration", "5", "-o", path}).exitCode, 0);
    std::string csv = (dir / "fly.csv").string(), json = (dir / "fly.json").string();
    // A 5 s lap flies faster than 100 units/s: --teleport-speed keeps it motion (its warning is not this test's).
    const std::vector<std::string> args = {"play", db, "--path", path, "--sync-loader", "--frames", "200",
                                           "--set", "c_targetTime=1000", "--stats", csv, "--teleport-speed", "1e4"};
    std::vector<std::string> withJson = args;
    withJson.insert(withJson.end(), {"--json", json});
    RunResult r = runHlod(withJson);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "hlod play: warning: " + db + ": node " + std::to_string(node) + ": blob " + std::to_string(blob) +
                         ": checksum mismatch (corrupt data)\n");
    EXPECT_NE(r.out.find("failed loads 1,"), std::string::npos) << r.out;
    EXPECT_EQ(nlohmann::json::parse(readText(json))["failed_loads"], 1);
    std::istringstream in(readText(csv));
    std::string line;
    std::vector<std::string> header;
    long column = -1, failed = 0, rows = 0;
    while (std::getline(in, line)) {
        if (line.starts_with("#")) continue;
        std::vector<std::string> fields;
        std::istringstream cells(line);
        for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
        if (header.empty()) {
            header = fields;
            column = std::find(header.begin(), header.end(), "failed_loads") - header.begin();
            ASSERT_LT(column, long(header.size()));
            continue;
        }
        failed += std::stol(fields.at(column));
        ++rows;
    }
    EXPECT_EQ(rows, 200);
    EXPECT_EQ(failed, 1);

    fs::remove(csv);
    std::vector<std::string> strict = args;
    strict.push_back("--strict");
    r = runHlod(strict);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("hlod play: " + db + " (node " + std::to_string(node) + ", blob " + std::to_string(blob) +
                              "): checksum mismatch",
                          0),
              0u)
        << r.err;
    EXPECT_FALSE(fs::exists(csv));

    // Loading every node at start (--loader incore, compare --preload) skips it the same way
    // (before stop 36 both stopped with status 1); --strict still stops.
    const std::string warning = "warning: " + db + ": node " + std::to_string(node) + ": blob " + std::to_string(blob) +
                                ": checksum mismatch (corrupt data)\n";
    std::vector<std::string> incore = args;
    incore.insert(incore.end(), {"--loader", "incore"});
    r = runHlod(incore);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "hlod play: " + warning);
    EXPECT_NE(r.out.find("failed loads 1,"), std::string::npos) << r.out;
    incore.push_back("--strict");
    EXPECT_EQ(runHlod(incore).exitCode, 1);
    r = runHlod({"compare", db, "--path", path, "--policies", "thesis,none", "--preload", "--frames", "50"});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find(warning), std::string::npos) << r.err;
}

