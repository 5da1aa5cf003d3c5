// scripts/plot_figures.sh turns a statistics log (player/stats.h columns) into the PNGs of
// thesis Figures 6.1-6.6, and refuses bad logs with one line and a non-zero exit.
// Skips when gnuplot is not installed.
#include "player/stats.h"
#include "tests/support/run_hlod.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace hlod {
namespace {

using test::RunResult;
using test::runProcess;

namespace fs = std::filesystem;

std::string script() { return std::string(HLOD_SOURCE_DIR) + "/scripts/plot_figures.sh"; }

class PlotFigures : public ::testing::Test {
protected:
    void SetUp() override {
        if (runProcess({"sh", "-c", "command -v gnuplot"}).exitCode != 0) GTEST_SKIP() << "gnuplot is not installed (gnuplot-nox)";
        dir_ = fs::temp_directory_path() / ("hlod_plot_test_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        if (!dir_.empty()) fs::remove_all(dir_);
    }

    // A plausible log: 3 levels, feedback converging, a toggle now and then, memory rising.
    fs::path writeLog(const std::string& name, int frames, int levels = 3) {
        const fs::path path = dir_ / name;
        std::ofstream out(path);
        out << "# constants: c_targetTime=30\n# memory_budget_bytes: 4000000\n";
        std::string header;
        for (const char* column : kStatsColumns) header += std::string(header.empty() ? "" : ",") + column;
        for (int l = 0; l < levels; ++l) header += ",nodes_l" + std::to_string(l);
        for (int l = 0; l < levels; ++l) header += ",tris_l" + std::to_string(l);
        out << header << "\n";
        for (int f = 0; f < frames; ++f) {
            const double actual = 25 + 4 * std::sin(f / 7.0);
            const int nodes[3] = {8, 4 + f % 5, f % 3};
            out << f << "," << f / 30.0 << "," << 0.05 * f << ",30," << actual * 1.2 << "," << actual * 0.98 << ","
                << actual << ",0.01,"
                << "20," << nodes[0] + nodes[1] + nodes[2] << "," << 900 * (nodes[0] + nodes[1] + nodes[2]) << ","
                << (f % 11 == 0) << "," << (f % 13 == 0) << ",0,40," << 1000000 + 5000 * f << "," << 900000 + 4000 * f
                << "," << (900000 + 4000 * f) / 40000.0 << ",1,0,0,0,0,0.1,0.4";
            for (int l = 0; l < levels; ++l) out << "," << nodes[l % 3];
            for (int l = 0; l < levels; ++l) out << "," << 900 * nodes[l % 3];
            out << "\n";
        }
        return path;
    }

    fs::path dir_;
};

// Width and height from the IHDR chunk of a PNG, or {0, 0} when the file is not a PNG.
std::pair<uint32_t, uint32_t> pngSize(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char head[24] = {};
    in.read(reinterpret_cast<char*>(head), sizeof head);
    const unsigned char magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (!in || !std::equal(magic, magic + 8, head) || std::string(head + 12, head + 16) != "IHDR") return {0, 0};
    auto be32 = [&](int at) { return uint32_t{head[at]} << 24 | uint32_t{head[at + 1]} << 16 | uint32_t{head[at + 2]} << 8 | head[at + 3]; };
    return {be32(16), be32(20)};
}

TEST_F(PlotFigures, WritesSixNonTrivialPngs) {
    const fs::path log = writeLog("run.csv", 120);
    const RunResult r = runProcess({"bash", script(), log.string(), (dir_ / "figs").string()});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    for (int n = 1; n <= 6; ++n) {
        const fs::path png = dir_ / "figs" / ("fig6_" + std::to_string(n) + ".png");
        ASSERT_TRUE(fs::exists(png)) << png;
        const auto [width, height] = pngSize(png);
        EXPECT_EQ(width, 1280u) << png;
        EXPECT_EQ(height, 800u) << png;
        EXPECT_GT(fs::file_size(png), 20000u) << png << " looks empty";
    }
}

TEST_F(PlotFigures, TakesFlyAndDriveRunsForTheTwoRunFigures) {
    const fs::path walk = writeLog("walk.csv", 60, 2), fly = writeLog("fly.csv", 90, 4), drive = writeLog("drive.csv", 70, 3);
    RunResult r = runProcess({"bash", script(), walk.string(), (dir_ / "figs").string(), fly.string()});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_NE(r.out.find("6.5: (a) walk-through, (b) fly-through"), std::string::npos) << r.out;
    for (int n = 1; n <= 6; ++n) EXPECT_GT(pngSize(dir_ / "figs" / ("fig6_" + std::to_string(n) + ".png")).first, 0u);
    EXPECT_GT(pngSize(dir_ / "figs" / "hlod0_share.png").first, 0u);
    r = runProcess({"bash", script(), walk.string(), (dir_ / "figs2").string(), fly.string(), drive.string()});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_NE(r.out.find("6.6: (a) walk-through, (b) drive-through"), std::string::npos) << r.out;
    r = runProcess({"bash", script(), walk.string(), (dir_ / "figs3").string()});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_NE(r.out.find("6.5: (a) walk-through only"), std::string::npos) << r.out;
}

void expectOneLineFailure(const RunResult& r, const std::string& mention) {
    const std::string output = r.outAndErr();
    EXPECT_EQ(r.exitCode, 2) << output;
    EXPECT_NE(output.find(mention), std::string::npos) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
}

TEST_F(PlotFigures, MissingLogFails) {
    const std::string missing = (dir_ / "missing.csv").string();
    expectOneLineFailure(runProcess({"bash", script(), missing, (dir_ / "figs").string()}), missing);
    EXPECT_FALSE(fs::exists(dir_ / "figs")) << "nothing written for a bad log";
}

TEST_F(PlotFigures, LogWithoutStatisticsColumnsFails) {
    const fs::path log = dir_ / "other.csv";
    std::ofstream(log) << "a,b,c\n1,2,3\n4,5,6\n";
    expectOneLineFailure(runProcess({"bash", script(), log.string(), (dir_ / "figs").string()}), "no column 'frame'");
    EXPECT_FALSE(fs::exists(dir_ / "figs"));
}

TEST_F(PlotFigures, TruncatedLogFails) {
    const fs::path log = writeLog("run.csv", 40);
    fs::resize_file(log, fs::file_size(log) - 7);  // last row loses its last fields
    expectOneLineFailure(runProcess({"bash", script(), log.string(), (dir_ / "figs").string()}), "fields");
}

TEST_F(PlotFigures, CorruptFieldFails) {
    const fs::path log = writeLog("run.csv", 10);
    std::ofstream(log, std::ios::app) << std::string(30, 'x') << std::string(200, ',') << "\n";
    const RunResult r = runProcess({"bash", script(), log.string(), (dir_ / "figs").string()});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_NE(r.outAndErr().find(log.string()), std::string::npos) << r.outAndErr();
}

TEST_F(PlotFigures, EmptyOrOneFrameLogFails) {
    const fs::path empty = dir_ / "empty.csv";
    std::ofstream(empty).flush();
    expectOneLineFailure(runProcess({"bash", script(), empty.string(), (dir_ / "figs").string()}), "empty");
    const fs::path one = writeLog("one.csv", 1);
    expectOneLineFailure(runProcess({"bash", script(), one.string(), (dir_ / "figs").string()}), "two frames");
}

TEST_F(PlotFigures, BadUsageFails) {
    const RunResult r = runProcess({"bash", script()});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.outAndErr().find("usage"), std::string::npos);
}

}  // namespace
}  // namespace hlod
