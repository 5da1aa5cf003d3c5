// The command-line convention of formats/cli/command.h, checked on every subcommand through the
// built binary: a missing file, a file that is not a database, a corrupt blob and a bad option
// each give the documented exit status (0 ok, 1 invalid data, 2 usage or unreadable input) and
// one error line "hlod SUBCOMMAND: ..."; --set of a constant a subcommand does not use is a
// usage error that names the subcommands using it.
#include "helpers.h"

#include "formats/db.h"
#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <cctype>
#include <fstream>
#include <regex>
#include <sstream>

namespace hlod::test {
namespace {

struct Conventions : ::testing::Test {
    TempDir dir;
    std::string db = dir.file("s.hlod"), notDb = dir.file("garbage.hlod"), corrupt = dir.file("corrupt.hlod");
    std::string path = dir.file("walk.path");
    void SetUp() override {
        SyntheticOptions o;
        o.levels = 2;
        writeSyntheticDatabase(db, o);
        writeFile(notDb, std::vector<uint8_t>(4096, 0x5a));
        std::vector<uint8_t> bytes = readFile(db);
        const Database database = Database::open(db);
        const BlobRef& blob = database.skeleton().blobs.at(0);  // an hlod0 node's geometry
        bytes.at(blob.offset + blob.size / 2) ^= 0xff;
        writeFile(corrupt, bytes);
        ASSERT_EQ(runHlod({"path", db, "--kind", "walk", "-o", path, "--duration", "2"}).exitCode, 0);
    }
};

// One line on stderr, prefixed with the subcommand.
void expectOneErrorLine(const RunResult& r, const std::string& prefix) {
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << r.err;
}

// Each subcommand that reads a database, with the arguments that make it run.
std::vector<std::vector<std::string>> databaseCommands(const std::string& db, const std::string& path,
                                                       const std::string& out) {
    return {{"inspect", db},
            {"validate", db},
            {"stats", db},
            {"play", db, "--path", path, "--sync-loader", "--frames", "3"},
            {"path", db, "-o", out},
            {"view", db},
            {"export", "tiles", db, "-o", out + ".tiles"}};
}

// The name errors are prefixed with: the subcommand, and its sub-subcommand for `hlod export` and
// `hlod synth`.
std::string commandName(const std::vector<std::string>& args) {
    return args[0] == "export" || args[0] == "synth" ? args[0] + " " + args[1] : args[0];
}

TEST_F(Conventions, MissingOrUnreadableDatabaseIsStatusTwo) {
    for (const std::string& file : {dir.file("missing.hlod"), notDb}) {
        for (const auto& args : databaseCommands(file, path, dir.file("p.path"))) {
            const RunResult r = runHlod(args);
            EXPECT_EQ(r.exitCode, 2) << args[0] << " " << file << ": " << r.err;
            expectOneErrorLine(r, "hlod " + commandName(args) + ": " + file + ": ");
        }
    }
}

TEST_F(Conventions, CorruptBlobIsStatusOneWhereBlobsAreRead) {
    RunResult r = runHlod({"validate", corrupt});
    EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
    r = runHlod({"play", corrupt, "--path", path, "--sync-loader", "--frames", "3"});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    expectOneErrorLine(r, "hlod play: " + corrupt + " (node 0, blob 0): checksum mismatch");
    r = runHlod({"export", "tiles", corrupt, "-o", dir.file("corrupt-tiles")});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    expectOneErrorLine(r, "hlod export tiles: " + corrupt + ": blob 0 (node 0) checksum mismatch");
    for (const std::string cmd : {"inspect", "stats"}) {  // read the skeleton only
        r = runHlod({cmd, corrupt});
        EXPECT_EQ(r.exitCode, 0) << cmd << ": " << r.err;
    }
}

TEST_F(Conventions, BadOptionIsStatusTwoWithOneLine) {
    const std::vector<std::vector<std::string>> commands = {
        {"build", db, "-o", dir.file("x.hlod"), "--no-such-option"}, {"merge", db, "-o", dir.file("m.hlod"), "--bogus"},
        {"split", db, "-o", dir.file("w"), "--bogus"}, {"inspect", db, "--bogus"}, {"validate", db, "--bogus"}, {"stats", db, "--bogus"},
        {"play", db, "--path", path, "--bogus"}, {"path", db, "-o", dir.file("p"), "--kind", "swim"},
        {"view", db, "--up", "w"}, {"calibrate", "--frames", "0"}, {"synth", "city", "-o", dir.file("c"), "--bogus"},
        {"export", "tiles", db, "-o", dir.file("t"), "--bogus"}, {"export", "obj", db}, {"no-such-subcommand"}};
    for (const auto& args : commands) {
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << args[0] << ": " << r.err;
        // the subcommand it concerns (each was "hlod: " until stop 46), or the word that is none
        expectOneErrorLine(r, args[0] == "no-such-subcommand" ? "hlod: 'no-such-subcommand' is not a subcommand (see --help)"
                              : args[0] == "export" && args[1] == "obj" ? "hlod export: "
                                                                       : "hlod " + commandName(args) + ": ");
    }
}

TEST_F(Conventions, MissingInputsOfOtherSubcommandsAreStatusTwo) {
    const std::string missing = dir.file("missing.ply");
    const std::vector<std::vector<std::string>> commands = {
        {"build", missing, "-o", dir.file("x.hlod")},
        {"merge", dir.file("no-shard"), "-o", dir.file("m.hlod")},
        {"split", missing, "-o", dir.file("work")},
        {"play", db, "--path", dir.file("missing.path")},
        {"play", db, "--path", path, "--config", dir.file("missing.conf")},
        {"play", db, "--path", path, "--calibration", dir.file("missing.conf")},
        {"build", missing, "-o", dir.file("x.hlod"), "--calibration", dir.file("missing.conf")}};
    for (const auto& args : commands) {
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << args[0] << " " << args[1] << ": " << r.err;
        expectOneErrorLine(r, "hlod " + args[0] + ": ");
    }
}

// A FIFO (or a device) given as an input file is refused before it is opened: opening a FIFO
// for reading waits for a writer, so before stop 38 each of these runs hung.
TEST_F(Conventions, FifoInputsAreRefusedNotWaitedOn) {
    std::vector<std::string> fifos;
    for (const char* name : {"f.ply", "f.obj", "f.glb", "f.path", "f.conf", "f.cal"}) {
        fifos.push_back(dir.file(name));
        ASSERT_EQ(::mkfifo(fifos.back().c_str(), 0644), 0) << name;
    }
    const std::vector<std::vector<std::string>> commands = {
        {"build", fifos[0], "-o", dir.file("x.hlod")},
        {"build", fifos[1], "-o", dir.file("x.hlod")},
        {"build", fifos[2], "-o", dir.file("x.hlod")},
        {"split", fifos[0], "-o", dir.file("work")},
        {"play", db, "--path", fifos[3]},
        {"compare", db, "--path", fifos[3], "--policies", "thesis"},
        {"play", db, "--path", path, "--config", fifos[4]},
        {"build", fifos[1], "-o", dir.file("x.hlod"), "--config", fifos[4]},
        {"play", db, "--path", path, "--calibration", fifos[5]},
        {"build", fifos[1], "-o", dir.file("x.hlod"), "--calibration", fifos[5]}};
    for (const auto& args : commands) {
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << args[0] << " " << args[1] << ": " << r.err;
        expectOneErrorLine(r, "hlod " + args[0] + ": ");
        EXPECT_NE(r.err.find(": not a regular file\n"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.hlod")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("work")));
}

TEST_F(Conventions, ConstantsAreAcceptedOnlyWhereUsed) {
    RunResult r = runHlod({"build", dir.file("missing.ply"), "-o", dir.file("x.hlod"), "--set", "c_targetTime=20"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod build: --set c_targetTime: `hlod build` does not use c_targetTime (used by: play, view, compare)\n");
    r = runHlod({"play", db, "--path", path, "--set", "c_levelFactor=3"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod play: --set c_levelFactor: `hlod play` does not use c_levelFactor (used by: build)\n");
    r = runHlod({"view", db, "--set", "c_desiredTris=3"});
    EXPECT_EQ(r.exitCode, 2);
    for (const std::string cmd : {"inspect", "validate", "stats", "path"}) {  // take no constants at all
        r = runHlod({cmd, db, "--set", "c_vis=1"});
        EXPECT_EQ(r.exitCode, 2) << cmd;
    }

    // A constants file may hold every constant: the ones play does not use are noted, not applied.
    const std::string conf = dir.file("all.conf");
    std::ofstream(conf) << "c_desiredTris = 300\nc_targetTime = 20\n";
    r = runHlod({"play", db, "--path", path, "--sync-loader", "--frames", "3", "--config", conf});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("note: " + conf + ": not used by `hlod play`: c_desiredTris"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("constants: c_vis=1.275 c_fore=0.45 c_targetTime=20 "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("c_desiredTris="), std::string::npos) << r.out;  // prints only what it uses

    // A bad file's bytes quoted in the error line are shown printable (a terminal escape here).
    std::ofstream(conf) << "c_fo\x1b[2Jo = 3\n";
    r = runHlod({"play", db, "--path", path, "--config", conf});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err.rfind("hlod play: " + conf + ":1: unknown constant 'c_fo?[2Jo' (known: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count_if(r.err.begin(), r.err.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }), 1) << r.err;
}

// Absurd constants (README "Reliability") are a usage error of the subcommand that uses them:
// status 2, one line, before any work; from --set or a constants file alike.
TEST_F(Conventions, AbsurdConstantsAreStatusTwoWithOneLine) {
    RunResult r = runHlod({"play", db, "--path", path, "--sync-loader", "--set", "c_targetTime=-5"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod play: c_targetTime = -5: must be > 0 and at most 10000 (milliseconds: a frame of at most 10 s)\n");
    const std::string conf = dir.file("hyst.conf");
    std::ofstream(conf) << "c_hystSwitch = 5000\nc_hystLimit = 100\nc_levelFactor = 1\n";
    r = runHlod({"play", db, "--path", path, "--sync-loader", "--config", conf});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod play: c_hystSwitch = 5000: must be <= c_hystLimit = 100 (the counter could never reach it)\n");
    writeFile(dir.file("t.ply"), {});
    r = runHlod({"build", dir.file("t.ply"), "-o", dir.file("t.hlod"), "--set", "c_levelFactor=1"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod build: c_levelFactor = 1: must be a whole number in [2, 64] (children per node)\n");
    r = runHlod({"build", dir.file("t.ply"), "-o", dir.file("t.hlod"), "--config", conf});  // c_hyst* are play's
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod build: c_levelFactor = 1: must be a whole number in [2, 64] (children per node)\n");
    EXPECT_FALSE(std::filesystem::exists(dir.file("t.hlod")));
}

// Every number option of every subcommand, found in its --help: a floating-point one refuses
// nan and +-inf, a count (INT, UINT) refuses -1 and 10^23 (beyond its type: CLI11's "Could not
// convert" until stop 45), each with status 2 and one line naming the option, the value and
// (for a count) what it accepts (formats/cli/command.h), before any work.
TEST_F(Conventions, NumberOptionsRefuseNanInfinityAndNegativeCounts) {
    const std::string obj = dir.file("t.obj");
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::vector<std::vector<std::string>> commands = {
        {"build", obj, "-o", dir.file("n.hlod")}, {"split", obj, "-o", dir.file("nw")},
        {"merge", dir.file("shard"), "-o", dir.file("m.hlod")}, {"inspect", db}, {"validate", db}, {"stats", db},
        {"play", db, "--path", path, "--sync-loader"}, {"path", db, "-o", dir.file("n.path")}, {"view", db},
        {"calibrate"}, {"compare", db, "--path", path, "--policies", "thesis"},
        {"export", "tiles", db, "-o", dir.file("nt")}, {"synth", "city", "-o", dir.file("nc"), "--scale", "0.01"}};
    const std::regex option(R"(^\s+(?:-\w,)?(--[a-z][a-z-]*) (FLOAT|INT|UINT)\b.*?(?: x (\d+))?(?: |$))");
    size_t checked = 0;
    for (const auto& base : commands) {
        std::vector<std::string> help = base;
        help.push_back("--help");
        std::istringstream lines(runHlod(help).out);
        for (std::string line; std::getline(lines, line);) {
            std::smatch m;
            if (!std::regex_search(line, m, option)) continue;
            const int repeat = m[3].matched ? std::stoi(m[3]) : 1;
            const std::vector<std::string> values =
                m[2] == "FLOAT" ? std::vector<std::string>{"nan", "inf", "-inf"}
                                : std::vector<std::string>{"-1", "99999999999999999999999"};
            for (const std::string& value : values) {
                std::vector<std::string> args = base;
                args.push_back(m[1]);
                for (int i = 0; i < repeat; ++i) args.push_back(value);
                const RunResult r = runHlod(args);
                const std::string what = base[0] + " " + std::string(m[1]) + " " + value;
                EXPECT_EQ(r.exitCode, 2) << what << ": " << r.err;
                expectOneErrorLine(r, "hlod " + commandName(base) + ": ");
                EXPECT_NE(r.err.find(m[1]), std::string::npos) << what << ": " << r.err;
                EXPECT_NE(r.err.find(value), std::string::npos) << what << ": " << r.err;
                EXPECT_EQ(r.err.find("Could not convert"), std::string::npos) << what << ": " << r.err;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 180u);  // the sweep found the options (about 70 of them)
}

// Finite but absurd numbers that once crashed (-j 99999: TBB) or ran until memory ran out (a path
// of 1e300 s, or of a key every nanosecond, or a lap at 1e-300 m/s), and block ranges that were
// wrapped around or cut short: status 2, one line.
TEST_F(Conventions, AbsurdNumbersAreStatusTwoNotACrashOrAHang) {
    const std::string obj = dir.file("t.obj");
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::string out = dir.file("absurd.path");
    std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"build", obj, "-o", dir.file("j.hlod"), "-j", "99999"}, "hlod build: --jobs: Value 99999 not in range 0 to 1024"},
        {{"path", db, "-o", out, "--duration", "1e300"}, "hlod path: --duration: value '1e300': expected a finite number in [0, 86400]"},
        {{"path", db, "-o", out, "--key-interval", "1e-9"}, "hlod path: --key-interval: value '1e-9': expected a finite number in [0.001, 86400]"},
        {{"path", db, "-o", out, "--key-interval", "0.001", "--duration", "2000"}, "hlod path: a path of 2000 s with a key every 0.001 s has more than"},
        {{"path", db, "-o", out, "--speed", "1e-300"}, "hlod path: a path of "},
        {{"play", db, "--path", path, "--model-overhead-ms", "1e300"}, "hlod play: --model-overhead-ms: value '1e300': expected"},
        {{"play", db, "--path", path, "--overhead-ms", "1e300"}, "hlod play: --overhead-ms: value '1e300': expected"},
        {{"compare", db, "--path", path, "--v-time", "1e300"}, "hlod compare: --v-time: value '1e300': expected"},
        // the help said [0, 4] while the generator refused 0 after the parse (until stop 44)
        {{"synth", "city", "-o", dir.file("zc"), "--scale", "0"}, "hlod synth city: --scale: value '0': expected a finite number in (0, 4]"},
        // both batches are grids of 2 triangles: fitLine failed after the measurements (until stop 44)
        {{"calibrate", "-o", dir.file("k.conf"), "--triangles", "1", "2"},
         "hlod calibrate: --triangles: every batch is a grid of 2 triangles; fitting a line needs two sizes (give counts further apart)"}};
    // Every output option refuses "" (a filesystem error, status 1, before stop 36).
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"build", obj, "-o"}, {"split", obj, "-o"}, {"merge", dir.path.string(), "-o"}, {"path", db, "-o"},
             {"export", "tiles", db, "-o"}, {"calibrate", "-o"}, {"synth", "city", "-o"},
             {"compare", db, "--path", path, "--policies", "thesis", "-o"}, {"play", db, "--path", path, "--stats"},
             {"play", db, "--path", path, "--json"}, {"play", db, "--path", path, "--frames-dir"}, {"view", db, "--record"}}) {
        std::vector<std::string> empty = args;
        empty.push_back("");
        const std::string option = args.back() == "-o" ? "--output" : args.back();
        cases.push_back({empty, "hlod " + commandName(args) + ": " + option + ": an empty path (see --help)"});
    }
    for (const std::string blocks : {"-1:3", "0:1:2", "0:4294967297", " 0:1"})  // no wrap-around, no truncation
        cases.push_back({{"build", obj, "-o", dir.file("j.hlod"), "--shard", "--blocks", blocks},
                         "hlod build: --blocks '" + blocks + "': expected FIRST:LAST"});
    for (const auto& [args, message] : cases) {
        const RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << args[0] << ": " << r.err;
        expectOneErrorLine(r, message);
    }
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_FALSE(std::filesystem::exists(dir.file("j.hlod")));
}

TEST_F(Conventions, HelpAndVersionAreStatusZero) {
    EXPECT_EQ(runHlod({"--help"}).exitCode, 0);
    EXPECT_EQ(runHlod({"--version"}).exitCode, 0);
    const std::vector<std::string> withDb = {"inspect", "validate", "stats", "play", "path", "view", "export tiles"};
    for (const std::string cmd : {"build", "split", "merge", "inspect", "validate", "stats", "play", "path", "view", "calibrate",
                                  "export", "export tiles", "synth"}) {
        const size_t space = cmd.find(' ');  // "export tiles": a subcommand of a subcommand
        const RunResult r = runHlod(space == std::string::npos ? std::vector<std::string>{cmd, "--help"}
                                                               : std::vector<std::string>{cmd.substr(0, space),
                                                                                          cmd.substr(space + 1), "--help"});
        EXPECT_EQ(r.exitCode, 0) << cmd;
        ASSERT_FALSE(r.out.empty()) << cmd;
        EXPECT_TRUE(std::islower(static_cast<unsigned char>(r.out[0]))) << cmd << ": " << r.out;  // one help style
        // every option's text too (CLI11's "Print this help message and exit" until stop 46), and the
        // tool's name, not the binary's path, in the usage line
        EXPECT_NE(r.out.find("  -h,--help                   print this help and exit\n"), std::string::npos) << cmd;
        EXPECT_NE(r.out.find("Usage: hlod " + cmd + " "), std::string::npos) << cmd << ": " << r.out;
        if (std::find(withDb.begin(), withDb.end(), cmd) != withDb.end()) {
            EXPECT_NE(r.out.find("  DB TEXT REQUIRED            database file (.hlod)"), std::string::npos) << cmd;
        }
    }
}

// A std::filesystem failure no check foresaw (here the working folder deleted under the run, where
// a relative output cannot be made absolute) is one hlod line naming the path, not libstdc++'s
// "filesystem error: cannot make absolute path: ... [PATH]" (until stop 45).
TEST_F(Conventions, FilesystemFailuresAreOneLineNamingThePath) {
    const std::string obj = dir.file("t.obj");
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::string gone = dir.file("gone");
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"build", obj, "-o", "g.hlod"}, {"split", obj, "-o", "w"}, {"synth", "city", "-o", "c", "--scale", "0.01"}}) {
        std::vector<std::string> argv = {"sh", "-c", "mkdir \"$0\" && cd \"$0\" && rmdir \"$0\" && exec \"$@\"", gone, HLOD_BINARY};
        argv.insert(argv.end(), args.begin(), args.end());
        const RunResult r = runProcess(argv);
        EXPECT_EQ(r.exitCode, 1) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod " + (args[0] == "synth" ? "synth city" : args[0]) + ": " + args[3] +
                             ": cannot make absolute path (No such file or directory)\n");
    }
}

// Standard output that cannot be written (a full device; a file-size limit cutting a JSON) is a failed
// write, status 1 and one line, for every subcommand that prints to it (status 0 and a cut JSON
// until stop 46).
TEST_F(Conventions, UnwritableStandardOutputIsStatusOne) {
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"inspect", db, "--tree", "--json"}, {"validate", db}, {"stats", db, "--json"},
             {"play", db, "--path", path, "--sync-loader", "--frames", "3", "--json", "-"}}) {
        std::vector<std::string> argv = {"sh", "-c", "exec \"$@\" > /dev/full", "sh", HLOD_BINARY};
        argv.insert(argv.end(), args.begin(), args.end());
        const RunResult full = runProcess(argv);
        EXPECT_EQ(full.exitCode, 1) << args[0] << ": " << full.err;
        EXPECT_NE(full.err.find("hlod " + args[0] + ": standard output: write failed (No space left on device)"),
                  std::string::npos) << full.err;
    }
    std::vector<std::string> argv = {"sh", "-c", "trap '' XFSZ; ulimit -f 1; exec \"$@\" > \"$0\"", dir.file("cut.json"),
                                     HLOD_BINARY, "inspect", db, "--tree", "--json"};
    const RunResult cut = runProcess(argv);
    EXPECT_EQ(cut.exitCode, 1) << cut.err;
    expectOneErrorLine(cut, "hlod inspect: standard output: write failed (File too large)");
}

}  // namespace
}  // namespace hlod::test
