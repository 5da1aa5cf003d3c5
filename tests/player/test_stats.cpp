// Statistics: the CSV header is the documented one, rows have one field per column, and the
// summary computes mean, sd, p99, toggles per frame, per distance and per 400-frame window, the
// estimate error in the thesis's sign and the share's time at its bounds as defined in player/STATS.md.
#include "player/stats.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

using namespace hlod;

TEST(Stats, HeaderAndRowsAgree) {
    std::ostringstream os;
    Constants c;
    std::vector<std::pair<std::string, std::string>> extra{{"database", "x.hlod"}};
    writeStatsPreamble(os, c, extra, 3);
    FrameStats f;
    f.nodesPerLevel = {1, 2, 3};
    f.trianglesPerLevel = {10, 20, 30};
    f.actualMs = 12.5;
    f.policy = "thesis";
    f.benefit = 1234.5;
    f.iterations = 7;
    f.visibleTriangles = 99;
    f.demandBytes = 4096;
    f.prefetchBytes = 8192;
    f.frontBytes = 65536;
    f.wantedMissing = 5;
    f.waitMs = 1.25;
    writeStatsRow(os, f, 3);
    std::istringstream in(os.str());
    std::string constants, db, header, row;
    std::getline(in, constants);
    std::getline(in, db);
    std::getline(in, header);
    std::getline(in, row);
    EXPECT_EQ(constants.rfind("# constants: c_vis=", 0), 0u);  // the constants the player uses
    EXPECT_EQ(db, "# database: x.hlod");
    EXPECT_EQ(header.rfind("frame,time_s,distance,target_ms,est_nofb_ms,est_ms,actual_ms,v_time,hlod0_share_ms,nodes_drawn", 0), 0u);
    EXPECT_NE(header.find(",nodes_l0,nodes_l1,nodes_l2,tris_l0,tris_l1,tris_l2"), std::string::npos);
    auto count = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
    EXPECT_EQ(count(header), count(row));
    EXPECT_NE(row.find(",6,60,"), std::string::npos);  // nodes_drawn, tris_drawn
    EXPECT_NE(row.find(",1,2,3,10,20,30,thesis,1234.5,"), std::string::npos) << row;  // per-level, then policy columns
    EXPECT_NE(header.find(",tris_l2,policy,benefit,optimisation_ms,iterations,visible_tris,leftover_ms,"), std::string::npos)
        << header;
    EXPECT_NE(row.find(",7,99,"), std::string::npos) << row;
    // The loader columns, last (player/LOADERS.md).
    EXPECT_TRUE(header.ends_with(",leftover_ms,demand_bytes,prefetch_bytes,front_bytes,wanted_missing,wait_ms")) << header;
    EXPECT_TRUE(row.ends_with(",4096,8192,65536,5,1.2500")) << row;
}

TEST(Stats, SummaryMeanSdP99AndToggles) {
    std::vector<FrameStats> frames(200);
    for (size_t i = 0; i < frames.size(); ++i) {
        frames[i].targetMs = 30;
        frames[i].actualMs = i < 100 ? 100 : (i % 2 ? 28 : 32);  // first 100: warm-up
        frames[i].estimateMs = frames[i].actualMs;
        frames[i].upToggles = i == 150;
        frames[i].residentBytes = i;
    }
    frames[199].actualMs = 50;
    StatsSummary s = summarize(frames, 100);
    EXPECT_EQ(s.frames, 200u);
    EXPECT_NEAR(s.frameMs.mean, (49 * 28 + 50 * 32 + 50) / 100.0, 1e-9);
    EXPECT_EQ(s.frameMs.p99, 32);  // nearest rank: 99th of 100 sorted values
    EXPECT_EQ(s.frameMs.max, 50);
    EXPECT_NEAR(s.errorMs.mean, s.frameMs.mean - 30, 1e-9);
    EXPECT_DOUBLE_EQ(s.togglesPerFrame, 0.01);
    EXPECT_EQ(s.peakResidentBytes, 199u);
    auto j = nlohmann::json::parse(summaryJson(s, Constants{}));
    EXPECT_EQ(j["constants"]["c_targetTime"], "30");
    EXPECT_DOUBLE_EQ(j["toggles_per_frame"].get<double>(), 0.01);
}

// §6.5 per distance and per 400-frame window; the share's time at its bounds.
TEST(Stats, TogglesPerDistanceAndPerWindowAndShareAtBounds) {
    std::vector<FrameStats> frames(1000);
    for (size_t i = 0; i < frames.size(); ++i) {
        frames[i].targetMs = 30;
        frames[i].actualMs = 30;
        frames[i].distance = 0.05 * i;                  // 1.5 m/s at 30 ms a frame
        frames[i].upToggles = i >= 100 && i % 100 == 0;  // 9 counted: frames 100, 200, ... 900
        frames[i].downToggles = i == 150;
        frames[i].hlod0ShareMs = i < 300 ? kMinShare * 30 : i < 400 ? kMaxShare * 30 : 60;
    }
    StatsSummary s = summarize(frames, 100);
    EXPECT_NEAR(s.distance, 0.05 * 899, 1e-9);
    EXPECT_NEAR(s.togglesPerDistance, 10 / (0.05 * 899), 1e-12);
    EXPECT_EQ(s.toggleWindows, 2u);  // frames 100-499 and 500-899; the last 100 are no full window
    EXPECT_DOUBLE_EQ(s.windowTogglesMin, 4);  // 500, 600, 700, 800
    EXPECT_DOUBLE_EQ(s.windowTogglesMax, 5);  // 100, 150 (down), 200, 300, 400
    EXPECT_DOUBLE_EQ(s.windowTogglesMean, 4.5);
    EXPECT_NEAR(s.shareAtMinPct, 100 * 200 / 900.0, 1e-9);
    EXPECT_NEAR(s.shareAtMaxPct, 100 * 100 / 900.0, 1e-9);
    auto j = nlohmann::json::parse(summaryJson(s, Constants{}));
    EXPECT_EQ(j["toggles_per_400_frames"]["windows"].get<int>(), 2);
}

// §6.3 footnote 2: a negative difference is a conservative estimate (the frame took less).
TEST(Stats, EstimateErrorIsNegativeForAConservativeEstimate) {
    std::vector<FrameStats> frames(10);
    for (FrameStats& f : frames) {
        f.targetMs = 30;
        f.actualMs = 24;
        f.estimateMs = 25;            // over-estimated: conservative
        f.estimateNoFeedbackMs = 20;  // under-estimated
    }
    StatsSummary s = summarize(frames, 0);
    EXPECT_NEAR(s.estimateErrorPct.mean, -4, 1e-9);   // 100 (24 - 25) / 25
    EXPECT_NEAR(s.estimateNoFbErrorPct.mean, 20, 1e-9);  // 100 (24 - 20) / 20
}

// A rate with nothing to divide by is no rate: a camera that only turns has no toggles per metre,
// frames with an estimate of 0 no estimate error (both printed as 0, "no flicker" and "a perfect
// estimate", until stop 50).
TEST(Stats, RatesWithoutADenominatorAreNotApplicable) {
    std::vector<FrameStats> frames(10);
    for (FrameStats& f : frames) {
        f.targetMs = 30;
        f.actualMs = 2;
        f.upToggles = 1;  // toggling while the camera turns in place
    }
    StatsSummary s = summarize(frames, 0);
    EXPECT_TRUE(std::isnan(s.togglesPerDistance));
    EXPECT_EQ(s.estimatedFrames, 0u);
    std::ostringstream text;
    printSummary(text, s);
    EXPECT_NE(text.str().find("with feedback n/a; without n/a\n"), std::string::npos) << text.str();
    EXPECT_NE(text.str().find("toggles per unit of distance n/a over 0.0;"), std::string::npos) << text.str();
    auto j = nlohmann::json::parse(summaryJson(s, Constants{}));
    EXPECT_TRUE(j["toggles_per_distance"].is_null());
    EXPECT_TRUE(j["estimate_error_pct"].is_null());
    EXPECT_TRUE(j["estimate_nofb_error_pct"].is_null());
    // One frame with an estimate is enough for a figure.
    frames[4].estimateMs = frames[4].estimateNoFeedbackMs = 1;
    s = summarize(frames, 0);
    EXPECT_EQ(s.estimatedFrames, 1u);
    EXPECT_NEAR(s.estimateErrorPct.mean, 100, 1e-9);
    EXPECT_FALSE(nlohmann::json::parse(summaryJson(s, Constants{}))["estimate_error_pct"].is_null());
}
