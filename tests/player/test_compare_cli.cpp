// `hlod compare` as a user runs it: the table as text, CSV and JSON with one row per policy, the
// per-frame CSV, no invalid cut on a fixture database for any policy, and usage errors (an
// unknown policy or setting) as exit 2 with one line; `hlod play --policy`; the cost model's rates.
#include "formats/constants.h"
#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

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

namespace {

std::vector<std::string> splitLines(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

class CompareCli : public ::testing::Test {
protected:
    fs::path dir;
    std::string db, path;

    void SetUp() override {
        dir = fs::temp_directory_path() / ("hlod_cli_compare_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir);
        db = (dir / "terrain.hlod").string();
        SyntheticOptions o;
        o.levels = 3;
        writeSyntheticDatabase(db, o);
        path = (dir / "zigzag.path").string();
        RunResult r = runHlod({"path", db, "--kind", "zigzag", "--duration", "6", "-o", path});
        ASSERT_EQ(r.exitCode, 0) << r.err;
    }
    void TearDown() override { fs::remove_all(dir); }
};

}  // namespace

TEST_F(CompareCli, WritesOneRowPerPolicyInEveryForm) {
    const std::string policies = "thesis,thesis-rh,none,static,feedback,sse,sse-budget";
    std::string prefix = (dir / "cmp").string();
    std::ofstream(prefix + "-gap.png") << "an earlier run's plot";  // this run has no oracle: it goes (stale before stop 44)
    RunResult r = runHlod({"compare", db, "--path", path, "--policies", policies, "--step-ms", "30", "--preload",
                           "--warmup", "10", "--policy-set", "static.pixels=64", "--teleport-speed", "250", "-o", prefix});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("invalid cut"), std::string::npos) << r.err;  // every frame of every policy a valid cut
    // --teleport-speed, which compare's teleport warning names, is compare's too (play's alone until stop 50)
    EXPECT_NE(r.out.find("teleports above 250 m/s"), std::string::npos) << r.out;
    std::vector<std::string> names = {"thesis", "thesis-rh", "none", "static", "feedback", "sse", "sse-budget"};

    std::vector<std::string> csv = splitLines(readText(prefix + ".csv"));
    ASSERT_EQ(csv.size(), names.size() + 1);
    EXPECT_EQ(csv[0].rfind("policy,frames,counted_frames,frame_ms_mean,frame_ms_max,frame_ms_sd,frame_ms_p99,rel_error_p99,"
                           "rel_error_mean,benefit_mean,gap_mean,toggles_per_frame,toggles_per_metre,reversals,selection_ms_mean",
                           0),
              0u);
    for (size_t i = 0; i < names.size(); ++i) {
        EXPECT_EQ(csv[i + 1].rfind(names[i] + ",", 0), 0u) << csv[i + 1];
        EXPECT_TRUE(csv[i + 1].ends_with(",0")) << csv[i + 1];  // invalid_cuts
    }

    nlohmann::json j = nlohmann::json::parse(readText(prefix + ".json"));
    ASSERT_EQ(j["policies"].size(), names.size());
    for (size_t i = 0; i < names.size(); ++i) {
        const auto& row = j["policies"][i];
        EXPECT_EQ(row["policy"], names[i]);
        EXPECT_EQ(row["frames"], 201);  // 6 s at 30 ms, both ends
        EXPECT_GT(row["frame_ms"]["mean"].get<double>(), 0);
        EXPECT_GT(row["benefit_mean"].get<double>(), 0);
        EXPECT_TRUE(row["gap_mean"].is_null());  // no oracle among the policies
    }
    EXPECT_EQ(j["setup"]["preload"], "yes");
    // `none` draws the most: with everything resident it is full detail.
    double noneTris = j["policies"][2]["tris_mean"], thesisTris = j["policies"][0]["tris_mean"];
    EXPECT_GE(noneTris, thesisTris);

    std::string text = readText(prefix + ".txt");
    for (const std::string& n : names) EXPECT_NE(text.find("\n" + n + " "), std::string::npos) << n;
    std::vector<std::string> frames = splitLines(readText(prefix + "-frames.csv"));
    EXPECT_EQ(frames.size(), 1 + names.size() * 201);
    EXPECT_TRUE(fs::exists(prefix + "-frame-time.png"));
    EXPECT_GT(fs::file_size(prefix + "-frame-time.png"), 1000u);
    EXPECT_GT(fs::file_size(prefix + "-triangles.png"), 1000u);
    EXPECT_FALSE(fs::exists(prefix + "-gap.png"));
}

TEST_F(CompareCli, UnknownPolicyOrSettingIsAUsageError) {
    RunResult r = runHlod({"compare", db, "--path", path, "--policies", "thesis,nonsense"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("unknown policy 'nonsense'"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    r = runHlod({"compare", db, "--path", path, "--policies", "thesis", "--policy-set", "sse.tolerance=2"});
    EXPECT_EQ(r.exitCode, 2) << r.err;  // a setting of a policy not chosen
    r = runHlod({"compare", db, "--path", path, "--policies", "sse", "--policy-set", "sse.tolerance"});
    EXPECT_EQ(r.exitCode, 2) << r.err;
    r = runHlod({"compare", db, "--path", path, "--policies", "thesis,"});
    EXPECT_EQ(r.exitCode, 2) << r.err;
    r = runHlod({"compare", db, "--path", path, "--policies", "thesis,sse,thesis"});  // two rows named alike before stop 44
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err, "hlod compare: --policies: 'thesis' is given twice in 'thesis,sse,thesis'\n");
    r = runHlod({"compare", (dir / "missing.hlod").string(), "--path", path, "--policies", "thesis"});
    EXPECT_EQ(r.exitCode, 2) << r.err;
    r = runHlod({"play", db, "--path", path, "--policy", "nonsense"});
    EXPECT_EQ(r.exitCode, 2) << r.err;
}

TEST_F(CompareCli, PlayWritesThePolicyColumns) {
    std::string csv = (dir / "sse.csv").string();
    RunResult r = runHlod({"play", db, "--path", path, "--sync-loader", "--policy", "sse", "--policy-set",
                           "sse.tolerance=4", "--stats", csv});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::vector<std::string> lines = splitLines(readText(csv));
    auto header = std::find_if(lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("frame,", 0) == 0; });
    ASSERT_NE(header, lines.end());
    EXPECT_NE(header->find(",policy,benefit,optimisation_ms,iterations,visible_tris,leftover_ms,"), std::string::npos) << *header;
    ASSERT_NE(header + 1, lines.end());
    EXPECT_NE((header + 1)->find(",sse,"), std::string::npos) << *(header + 1);
    EXPECT_NE(readText(csv).find("# policy: sse"), std::string::npos);
}

TEST_F(CompareCli, FlatTriangleRateIsTheGivenOneOrConsistentWithCTextured) {
    std::string prefix = (dir / "flat").string();
    RunResult r = runHlod({"compare", db, "--path", path, "--policies", "none", "--step-ms", "30", "--no-plots",
                           "--model-ms-per-tri", "0.004", "--model-ms-per-flat-tri", "0.5", "-o", prefix});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(readText(prefix + ".json"));
    EXPECT_NEAR(std::stod(j["setup"]["model_ms_per_flat_tri"].get<std::string>()), 0.5, 1e-9);
    r = runHlod({"compare", db, "--path", path, "--policies", "none", "--step-ms", "30", "--no-plots",
                 "--model-ms-per-tri", "0.004", "-o", prefix});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(readText(prefix + ".json"));
    const double c = hlod::Constants{}.textured;  // the fixture's c_textured: eq. 3.1's weights
    EXPECT_NEAR(std::stod(j["setup"]["model_ms_per_flat_tri"].get<std::string>()), 0.004 * (1 - c) / c, 1e-5);
    EXPECT_EQ(j["setup"]["c_textured"], hlod::formatConstant(c));
    EXPECT_NE(r.out.find("c_textured: " + hlod::formatConstant(c)), std::string::npos) << r.out;
}
