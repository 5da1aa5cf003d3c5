// `hlod path` as a user runs it: the paths it writes are ones `hlod play` reads (eye height,
// coordinates), every kind on a database, the ground it follows, a bad database.
#include "formats/db.h"
#include "formats/layout.h"
#include "tests/player/cli_fixture.h"

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace hlod;
using hlod::test::RunResult;
using hlod::test::readText;
using hlod::test::runHlod;

// `hlod path` refuses an eye height its own reader would refuse (2e15: a path `hlod play` then
// rejected) or that meant "by scale" (a negative one was silently replaced by the default).
TEST_F(Cli, PathEyeHeightWithinWhatPathsHold) {
    for (const char* height : {"2e15", "-5"}) {
        RunResult r = runHlod({"path", db, "--kind", "walk", "--eye-height", height, "-o", (dir / "e.path").string()});
        EXPECT_EQ(r.exitCode, 2) << height;
        EXPECT_EQ(lines(r.err), 1) << r.err;
        EXPECT_NE(r.err.find("--eye-height"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "e.path"));
    }
    EXPECT_EQ(runHlod({"path", db, "--kind", "walk", "--eye-height", "0", "-o", (dir / "e.path").string()}).exitCode, 0);
}

// A fly path orbits 1.5 extents out: on a model 8e14 units across it passed the 1e15 its reader
// holds, and `hlod path` wrote (exit 0) a path `hlod play` refused (until stop 45).
TEST_F(Cli, PathRefusesCoordinatesItsReaderWouldRefuse) {
    const std::string obj = (dir / "big.obj").string(), big = (dir / "big.hlod").string();
    std::ofstream(obj) << "v 0 0 0\nv 8e14 0 0\nv 0 8e14 0\nf 1 2 3\n";
    ASSERT_EQ(runHlod({"build", obj, "-o", big}).exitCode, 0);
    RunResult r = runHlod({"path", big, "--kind", "fly", "-o", (dir / "big.path").string()});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(big + ": the fly path reaches a coordinate of "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("beyond the 1e15 a camera path holds"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "big.path"));
    r = runHlod({"path", big, "--kind", "walk", "--duration", "60", "-o", (dir / "big.path").string()});  // within
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_EQ(runHlod({"play", big, "--path", (dir / "big.path").string(), "--sync-loader", "--frames", "5"}).exitCode, 0);
}

TEST_F(Cli, PathKindsAndBadDatabase) {
    for (const char* kind : {"walk", "drive", "fly", "erratic"}) {
        std::string out = (dir / (std::string(kind) + ".path")).string();
        RunResult r = runHlod({"path", db, "--kind", kind, "-o", out});
        EXPECT_EQ(r.exitCode, 0) << kind << r.err;
        EXPECT_TRUE(readText(out).starts_with("hlod-camera-path 1\n"));
    }
    // The scale it chose and the duration are printed; --units must be a unit or a number of metres.
    RunResult units = runHlod({"path", db, "--units", "mm", "-o", (dir / "mm.path").string()});
    EXPECT_EQ(units.exitCode, 0) << units.err;
    EXPECT_NE(units.out.find("duration"), std::string::npos) << units.out;
    EXPECT_NE(units.out.find("1 unit = 0.001 m"), std::string::npos) << units.out;
    RunResult badUnits = runHlod({"path", db, "--units", "furlong", "-o", (dir / "u.path").string()});
    EXPECT_EQ(badUnits.exitCode, 2);
    EXPECT_EQ(lines(badUnits.err), 1) << badUnits.err;
    EXPECT_FALSE(fs::exists(dir / "u.path"));
    std::string junk = (dir / "junk.hlod").string();
    std::ofstream(junk) << "not a database at all";
    RunResult r = runHlod({"path", junk, "-o", (dir / "x.path").string()});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.path"));
}

// player/CAMERA_PATH.md "Eye height": `hlod path` decodes a cut of the database for the ground
// and says so; a geometry blob that does not read back is left out with one warning, and the
// path is still written (exit 0).
TEST_F(Cli, PathReadsTheGroundAndSurvivesACorruptBlob) {
    const std::string out = (dir / "p.path").string();
    RunResult r = runHlod({"path", db, "-o", out});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("ground: the lowest of "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("passes through the geometry between "), std::string::npos) << r.out;
    EXPECT_EQ(r.err, "");
    uint64_t offset = 0;
    {
        const Database d = Database::open(db);
        for (const BlobRef& b : d.skeleton().blobs)
            if (b.kind == BlobKind::Geometry && d.skeleton().nodes[b.node].firstChild == kNone) offset = b.offset + b.size / 2;
    }
    ASSERT_GT(offset, 0u);
    {
        std::fstream f(db, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(offset));
        const char byte = char(f.get() ^ 0x5A);
        f.seekp(std::streamoff(offset));
        f.put(byte);
    }
    r = runHlod({"path", db, "-o", out});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("hlod path: warning: 1 geometry blobs left out of the ground (first: "), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(out));
}

// A database in millimetres played in metres: every move of a 500 units/s path was a teleport (no
// distance, no velocity look-ahead) without a word until stop 48; `--units mm` says what a unit
// is, and a path faster than --teleport-speed over most of its time is warned of. A given fixed
// overhead at or above c_targetTime left no time to draw and the v_time loop refined everything:
// a usage error now, from the option or a calibration file.
TEST_F(Cli, PlayUnitsAndAnOverheadThatLeavesNoTimeToDraw) {
    const std::string path = (dir / "fast.path").string(), json = (dir / "fast.json").string();
    std::ofstream(path) << "hlod-camera-path 1\n0 0 0 50 0 0 0 1 60\n4 2000 0 50 0 0 0 1 60\n";
    RunResult r = runHlod({"play", db, "--path", path, "--sync-loader", "--json", json});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_NE(r.err.find("hlod play: warning: the camera moves faster than --teleport-speed 100 m/s over 100 % of the path's time: each such "
                        "move counts as a cut"),
              std::string::npos)
        << r.err;
    EXPECT_NE(readText(json).find("\"distance\": 0.0"), std::string::npos) << readText(json);
    r = runHlod({"play", db, "--path", path, "--sync-loader", "--json", json, "--units", "mm"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("units: mm (0.001 m a database unit)"), std::string::npos) << r.out;
    EXPECT_EQ(readText(json).find("\"distance\": 0.0"), std::string::npos) << readText(json);

    const std::string cal = (dir / "cal.conf").string();
    std::ofstream(cal) << "renderer = test\nc_textured = 0.5\nms_per_cost = 0.01\nfixed_overhead_ms = 30\n";
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"play", db, "--path", path, "--overhead-ms", "30"}, {"play", db, "--path", path, "--calibration", cal},
          {"compare", db, "--path", path, "--policies", "thesis", "--overhead-ms", "45", "--set", "c_targetTime=40"}}) {
        r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(lines(r.err), 1) << r.err;
        EXPECT_NE(r.err.find("is not below c_targetTime"), std::string::npos) << r.err;
    }
    EXPECT_NE(r.err.find("--overhead-ms 45 ms is not below c_targetTime 40 ms"), std::string::npos) << r.err;
    EXPECT_EQ(runHlod({"play", db, "--path", path, "--overhead-ms", "29", "--sync-loader", "--frames", "5"}).exitCode, 0);
}
