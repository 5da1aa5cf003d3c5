// `hlod compare`'s table (player/POLICIES.md "hlod compare"): the per-frame statistics of each
// policy's replay of one path reduced to one row per policy, beside the exact optimum when the
// `oracle` policy ran: frame time (Funkhouser & Séquin 1993 Table 1: mean, max, sd; plus p99),
// p99 and mean of |actual - target| / target (RH Table 2), mean common benefit and mean gap to the oracle, toggles per
// frame and per metre and reversals (thesis §6.5), selection time.
#pragma once

#include "player/player.h"
#include "player/stats.h"

#include <cmath>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

namespace hlod {

// One frame as the table, the frames CSV and the plots read it: 72 bytes, where a FrameStats holds
// ~0.45 KB with its per-level arrays (16 policies at the 1,000,000-frame cap took ~7 GB until stop 44).
struct CompareFrame {
    uint64_t frame = 0;
    double timeSeconds = 0, targetMs = 0, actualMs = 0, benefit = 0, selectionMs = 0, optimisationMs = 0;
    uint64_t triangles = 0;         // drawn, all levels
    uint64_t visibleTriangles = 0;  // FrameStats::visibleTriangles
};

struct PolicyRun {
    std::string policy;
    StatsSummary summary;           // summarize() of the full frames, before they were reduced
    std::vector<CompareFrame> frames;
    uint64_t invalidCuts = 0;       // frames whose front failed checkCut (player/front.h)
    std::string firstInvalid;       // the first such failure, in words
};

// `policy`'s run as `hlod compare` keeps it: the summary of `frames` counted from `warmup` on
// (summarize's rule: at most half the frames) and each frame reduced to a CompareFrame.
PolicyRun policyRun(std::string policy, std::span<const FrameStats> frames, uint64_t warmup);

struct CompareRow {
    std::string policy;
    uint64_t frames = 0, counted = 0;  // all frames, frames after the warm-up
    Distribution frameMs;
    double relErrorP99 = 0;            // p99 of |actual - target| / target
    double relErrorMean = 0;           // its mean: Robin Hood Table 2's "AvgErr"
    double benefitMean = 0;
    double gapMean = NAN;              // mean of (B_oracle - B) / B_oracle over aligned frames; NaN without oracle
    double togglesPerFrame = 0, togglesPerMetre = 0;  // per metre: NaN when the camera did not move (printed "-")
    uint64_t reversals = 0;
    Distribution selectionMs;
    double optimisationMsMean = 0;
    double trianglesMean = 0;
    uint64_t invalidCuts = 0;
};

// Per-frame gap of `run` to `oracle`: (B_oracle_i - B_i) / B_oracle_i for frame i of both (NaN
// where the oracle's benefit is 0 or the oracle has no frame i).
std::vector<double> benefitGaps(const PolicyRun& run, const PolicyRun& oracle);

// One row per run, counting the frames after its summary's warm-up. `oracle` (may be null) gives
// the gap column; frames must be aligned (fixed step) for it to mean anything, which the caller decides.
std::vector<CompareRow> compareRows(std::span<const PolicyRun> runs, const PolicyRun* oracle);

void writeCompareText(std::ostream& os, std::span<const CompareRow> rows);
void writeCompareCsv(std::ostream& os, std::span<const CompareRow> rows);
std::string compareJson(std::span<const CompareRow> rows, const std::vector<std::pair<std::string, std::string>>& setup);

}  // namespace hlod
