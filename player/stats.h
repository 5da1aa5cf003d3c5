// Per-frame statistics (thesis Chapter 6: every figure 6.1-6.6 is redrawn from these columns)
// and the end-of-run summary. The column names are defined here, in one place, and documented
// in player/STATS.md; scripts/plot* read them by name.
#pragma once

#include "formats/constants.h"
#include "player/player.h"

#include <iosfwd>
#include <span>
#include <string>
#include <vector>

namespace hlod {

// The fixed columns, in order. Per-level columns follow: nodes_l0..nodes_l{L-1}, then
// tris_l0..tris_l{L-1}, where L is the database's level count; then kPolicyColumns, kLoaderColumns.
inline constexpr const char* kStatsColumns[] = {
    "frame", "time_s", "distance", "target_ms", "est_nofb_ms", "est_ms", "actual_ms", "v_time", "hlod0_share_ms",
    "nodes_drawn", "tris_drawn", "up_toggles", "down_toggles", "reversals", "resident_nodes", "resident_bytes",
    "memory_estimate_bytes", "memory_estimate_pct", "loads", "evictions", "failed_loads", "misses", "refused", "stall_ms", "selection_ms"};

// The columns every selection policy shares (player/POLICIES.md), after the per-level ones, so that
// the columns before them keep their positions.
inline constexpr const char* kPolicyColumns[] = {"policy", "benefit", "optimisation_ms", "iterations", "visible_tris",
                                                 "leftover_ms"};

// The loader columns (player/LOADERS.md), after the policy ones.
inline constexpr const char* kLoaderColumns[] = {"demand_bytes", "prefetch_bytes", "front_bytes", "wanted_missing",
                                                 "wait_ms"};

std::vector<std::string> statsHeader(uint32_t levels);

// Writes "# constants: ..." and "# key: value" comment lines, then the header line.
void writeStatsPreamble(std::ostream& os, const Constants& c,
                        std::span<const std::pair<std::string, std::string>> extra, uint32_t levels);
void writeStatsRow(std::ostream& os, const FrameStats& s, uint32_t levels);

struct Distribution {
    double mean = 0, sd = 0, p99 = 0, max = 0;
};
// Mean, sample sd, nearest-rank p99 and max (all 0 when empty).
Distribution distributionOf(std::vector<double> values);

// Toggles counted over consecutive windows of kToggleWindow frames after the warm-up (the thesis
// shows 400 frames of its walk-through with 3 toggles, §6.5 Fig. 6.6a).
inline constexpr uint64_t kToggleWindow = 400;

struct StatsSummary {
    uint64_t frames = 0;
    uint64_t warmupFrames = 0;          // frames excluded from the distributions below
    Distribution frameMs;               // actual_ms
    Distribution errorMs;               // actual_ms - target_ms
    // Thesis §6.3 convention: 100 * (actual_ms - est_ms) / est_ms; negative = a conservative
    // estimate (the frame took less than estimated), footnote 2 of §6.3.
    Distribution estimateErrorPct;      // with feedback (Fig. 6.4b)
    Distribution estimateNoFbErrorPct;  // without feedback (Fig. 6.4a)
    // Counted frames whose estimate is above 0 (the others have no percentage: nothing drawn and
    // no overhead); none: the two distributions are undefined ("n/a", JSON null).
    uint64_t estimatedFrames = 0, estimatedNoFbFrames = 0;
    double togglesPerFrame = 0;         // (up + down) / frames (§6.5)
    double distance = 0;                // camera path length over the counted frames (database units)
    double togglesPerDistance = 0;      // (up + down) / distance; NaN when the camera did not move ("n/a", JSON null)
    uint64_t toggleWindows = 0;         // complete kToggleWindow-frame windows counted
    double windowTogglesMean = 0, windowTogglesMin = 0, windowTogglesMax = 0;  // toggles per window
    uint64_t upToggles = 0, downToggles = 0, reversals = 0;
    double shareAtMinPct = 0, shareAtMaxPct = 0;  // % of counted frames with the hlod0 share at a bound
    uint64_t peakResidentBytes = 0;
    double peakMemoryEstimateBytes = 0;
    uint64_t loads = 0, evictions = 0, failedLoads = 0, misses = 0;
    double longestStallMs = 0;
};

// Summary over frames[warmup, end), warmup at most half of the frames.
StatsSummary summarize(std::span<const FrameStats> frames, uint64_t warmupFrames);
void printSummary(std::ostream& os, const StatsSummary& s);
std::string summaryJson(const StatsSummary& s, const Constants& c);
// `missing` for a figure that is undefined (a rate without a denominator), else the figures as
// printf's `format` writes them; shared by the summary ("n/a") and compare's tables ("-", "").
std::string figureOr(const char* missing, bool defined, const char* format, double a, double b = 0);

}  // namespace hlod
