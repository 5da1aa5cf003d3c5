// End to end through the `hlod` tool on a small synthetic database: `play --renderer gl`
// writes PNG frames shaded by level and a statistics log, scripts/plot_figures.sh turns the
// log into Figures 6.1-6.6; `calibrate` and `view` fail with one line on bad input.
// Skips the GL parts when no EGL context exists.
#include "player/gl/gl_renderer.h"
#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace hlod {
namespace {

using test::RunResult;
using test::runHlod;
using test::runProcess;

namespace fs = std::filesystem;

bool haveEgl() {
    try {
        makeGlRenderer({64, 64, false, false});
        return true;
    } catch (const NoGlContext&) {
        return false;
    }
}

class HlodTool : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("hlod_gl_cli_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(HlodTool, PlayWithGlWritesLevelShadedFramesAndTheLogPlots) {
    if (!haveEgl()) GTEST_SKIP() << "no EGL OpenGL context";
    const fs::path db = dir_ / "terrain.hlod";
    SyntheticOptions synthetic;
    synthetic.levels = 3;
    synthetic.trianglesPerNode = 256;
    synthetic.textureSize = 0;  // textured drawing is covered by test_gl_renderer.cpp
    writeSyntheticDatabase(db.string(), synthetic);
    const fs::path path = dir_ / "fly.path", log = dir_ / "run.csv", frames = dir_ / "frames";
    RunResult r = runHlod({"path", db.string(), "--kind", "fly", "--duration", "4", "-o", path.string()});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    r = runHlod({"play", db.string(), "--path", path.string(), "--renderer", "gl", "--width", "320", "--height", "180", "--sync-loader", "--stats", log.string(), "--frames-dir", frames.string(), "--every", "20", "--color-by-level"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    size_t pngs = 0;
    for (const auto& entry : fs::directory_iterator(frames)) pngs += entry.path().extension() == ".png";
    EXPECT_GT(pngs, 1u);
    // A later run into the folder replaces the earlier run's frames (they stayed until stop 47), and
    // refuses, before any is removed, a frame name that is one of its inputs (overwritten until then).
    fs::copy_file(path, frames / "frame_000020.png", fs::copy_options::overwrite_existing);
    r = runHlod({"play", db.string(), "--path", (frames / "frame_000020.png").string(), "--renderer", "gl", "--width", "32", "--height", "18",
                 "--sync-loader", "--frames-dir", frames.string()});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_EQ(r.err.rfind("hlod play: " + (frames / "frame_000020.png").string() + ": is also an input", 0), 0u) << r.err;
    r = runHlod({"play", db.string(), "--path", path.string(), "--renderer", "gl", "--width", "32", "--height", "18", "--sync-loader",
                 "--frames-dir", frames.string(), "--every", "100000"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    pngs = 0;
    for (const auto& entry : fs::directory_iterator(frames)) pngs += entry.path().extension() == ".png";
    EXPECT_EQ(pngs, 1u);  // frame 0 alone
    // a folder that cannot be made (a file in the way): the convention's one line, before any frame
    const std::string blocked = (dir_ / "fly.path" / "png").string();
    r = runHlod({"play", db.string(), "--path", path.string(), "--renderer", "gl", "--width", "32", "--height", "18", "--sync-loader", "--frames-dir", blocked});
    EXPECT_EQ(r.exitCode, 1) << r.outAndErr();
    EXPECT_EQ(r.err, "hlod play: " + blocked + ": cannot create the folder for PNG frames (Not a directory)\n");
    if (runProcess({"sh", "-c", "command -v gnuplot"}).exitCode != 0) GTEST_SKIP() << "gnuplot is not installed";
    r = runProcess({"bash", std::string(HLOD_SOURCE_DIR) + "/scripts/plot_figures.sh", log.string(), (dir_ / "figs").string()});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    for (int n = 1; n <= 6; ++n) EXPECT_GT(fs::file_size(dir_ / "figs" / ("fig6_" + std::to_string(n) + ".png")), 10000u);
}

TEST_F(HlodTool, CalibrateWritesACalibrationFileThatBuildAndPlayRead) {
    if (!haveEgl()) GTEST_SKIP() << "no EGL OpenGL context";
    const fs::path out = dir_ / "calibration.conf";
    const RunResult r = runHlod({"calibrate", "--width", "320", "--height", "180", "--frames", "3", "--triangles", "1000", "80000", "-o", out.string()});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    std::ifstream in(out);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\nc_textured = 0."), std::string::npos) << text;
    EXPECT_NE(text.find("\nms_per_cost = "), std::string::npos) << text;
    const Calibration c = readCalibration(out.string());
    EXPECT_GT(c.msPerCost, 0);
    EXPECT_GT(c.cTextured, 0);
}

TEST_F(HlodTool, CalibrateToAnUnwritablePathFailsBeforeMeasuring) {
    const std::string out = (dir_ / "missing-dir" / "c.conf").string();
    const RunResult r = runHlod({"calibrate", "-o", out});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.outAndErr(), "hlod calibrate: " + out + ": cannot write calibration (No such file or directory)\n");
}

TEST_F(HlodTool, ViewOfAMissingDatabaseFailsWithOneLine) {
    const std::string db = (dir_ / "missing.hlod").string();
    const RunResult r = runHlod({"view", db});
    EXPECT_EQ(r.exitCode, 2);
    const std::string output = r.err;
    EXPECT_NE(output.find(db), std::string::npos) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
}

TEST_F(HlodTool, ViewWithoutADisplayFailsWithOneLine) {
    const fs::path db = dir_ / "terrain.hlod";
    SyntheticOptions synthetic;
    synthetic.levels = 2;
    writeSyntheticDatabase(db.string(), synthetic);
    const RunResult r = runHlod({"view", db.string()}, {.unsetEnv = {"DISPLAY", "WAYLAND_DISPLAY"}});
    EXPECT_EQ(r.exitCode, 1);
    const std::string output = r.err;
    EXPECT_NE(output.find("hlod view: GLFW"), std::string::npos) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
}

// The flight is written at exit: an output it could not be written to is refused before the window
// opens (until stop 44 `--record DB` replaced the database with the camera path).
TEST_F(HlodTool, ViewRefusesARecordFileItCouldNotWriteBeforeTheFlight) {
    const fs::path db = dir_ / "record.hlod";
    writeSyntheticDatabase(db.string(), SyntheticOptions{});
    const auto size = fs::file_size(db);
    RunResult r = runHlod({"view", db.string(), "--record", db.string()});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod view: " + db.string() + ": is also an input (" + db.string() + "); write the output elsewhere\n");
    EXPECT_EQ(fs::file_size(db), size);
    const std::string missing = (dir_ / "missing-dir" / "f.path").string();
    r = runHlod({"view", db.string(), "--record", missing});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err, "hlod view: " + missing + ": cannot write camera path (No such file or directory)\n");
    r = runHlod({"view", db.string(), "--record", dir_.string()});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("(exists and is not a regular file)"), std::string::npos) << r.err;
}

TEST_F(HlodTool, ViewOfACorruptDatabaseFailsWithOneLine) {
    const fs::path db = dir_ / "corrupt.hlod";
    std::ofstream(db) << std::string(4096, 'x');
    const RunResult r = runHlod({"view", db.string()});
    EXPECT_EQ(r.exitCode, 2);
    const std::string output = r.err;
    EXPECT_NE(output.find(db.string()), std::string::npos) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
}

}  // namespace
}  // namespace hlod
