// Per-frame CSV (columns in player/stats.h, documented in player/STATS.md) and the summary:
// mean, sd, p99 of the frame time and of its error to target (§6.4), of the estimate errors
// with and without feedback (§6.3), toggles per frame, per unit of distance and per 400-frame
// window (§6.5), time the hlod0 share spends at its bounds (§4.2 second loop), peak memory (§6.1).
#include "player/stats.h"

#include "formats/errors.h"
#include "formats/json_text.h"
#include "player/feedback.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <ostream>

namespace hlod {

std::vector<std::string> statsHeader(uint32_t levels) {
    std::vector<std::string> h(std::begin(kStatsColumns), std::end(kStatsColumns));
    for (uint32_t l = 0; l < levels; ++l) h.push_back("nodes_l" + std::to_string(l));
    for (uint32_t l = 0; l < levels; ++l) h.push_back("tris_l" + std::to_string(l));
    h.insert(h.end(), std::begin(kPolicyColumns), std::end(kPolicyColumns));
    h.insert(h.end(), std::begin(kLoaderColumns), std::end(kLoaderColumns));
    return h;
}

void writeStatsPreamble(std::ostream& os, const Constants& c,
                        std::span<const std::pair<std::string, std::string>> extra, uint32_t levels) {
    os << "# ";
    printConstants(os, c, kUsedByPlayer);
    for (const auto& [k, v] : extra) os << "# " << printableLine(k) << ": " << printableLine(v) << "\n";
    auto header = statsHeader(levels);
    for (size_t i = 0; i < header.size(); ++i) os << (i ? "," : "") << header[i];
    os << "\n";
}

void writeStatsRow(std::ostream& os, const FrameStats& s, uint32_t levels) {
    char buf[512];
    uint32_t nodes = 0;
    uint64_t tris = 0;
    for (uint32_t n : s.nodesPerLevel) nodes += n;
    for (uint64_t t : s.trianglesPerLevel) tris += t;
    std::snprintf(buf, sizeof buf, "%llu,%.6f,%.4f,%.3f,%.4f,%.4f,%.4f,%.6g,%.4f,%u,%llu,%u,%u,%u,%u,%llu,%.0f,%.3f,%u,%u,%u,%u,%u,%.4f,%.4f",
                  (unsigned long long)s.frame, s.timeSeconds, s.distance, s.targetMs, s.estimateNoFeedbackMs, s.estimateMs,
                  s.actualMs, s.vTime, s.hlod0ShareMs, nodes, (unsigned long long)tris, s.upToggles, s.downToggles,
                  s.reversals, s.residentNodes, (unsigned long long)s.residentBytes, s.memoryEstimateBytes, s.memoryEstimatePct, s.loads, s.evictions,
                  s.failedLoads, s.misses, s.refused, s.stallMs, s.selectionMs);
    os << buf;
    for (uint32_t l = 0; l < levels; ++l) os << ',' << (l < s.nodesPerLevel.size() ? s.nodesPerLevel[l] : 0);
    for (uint32_t l = 0; l < levels; ++l) os << ',' << (l < s.trianglesPerLevel.size() ? s.trianglesPerLevel[l] : 0);
    std::snprintf(buf, sizeof buf, ",%s,%.6g,%.4f,%u,%llu,%.4f,%llu,%llu,%llu,%u,%.4f\n", s.policy, s.benefit,
                  s.optimisationMs, s.iterations, (unsigned long long)s.visibleTriangles, s.leftoverMs,
                  (unsigned long long)s.demandBytes, (unsigned long long)s.prefetchBytes,
                  (unsigned long long)s.frontBytes, s.wantedMissing, s.waitMs);
    os << buf;
}

Distribution distributionOf(std::vector<double> v) {
    Distribution d;
    if (v.empty()) return d;
    double sum = 0;
    for (double x : v) sum += x;
    d.mean = sum / v.size();
    double sq = 0;
    for (double x : v) sq += (x - d.mean) * (x - d.mean);
    d.sd = v.size() > 1 ? std::sqrt(sq / (v.size() - 1)) : 0;
    std::sort(v.begin(), v.end());
    d.p99 = v[std::min(v.size() - 1, size_t(std::ceil(0.99 * v.size())) - 1)];  // nearest rank
    d.max = v.back();
    return d;
}

namespace {

nlohmann::json toJson(const Distribution& d) { return {{"mean", d.mean}, {"sd", d.sd}, {"p99", d.p99}, {"max", d.max}}; }

}  // namespace

std::string figureOr(const char* missing, bool defined, const char* format, double a, double b) {
    if (!defined) return missing;
    char buf[96];
    std::snprintf(buf, sizeof buf, format, a, b);
    return buf;
}

StatsSummary summarize(std::span<const FrameStats> frames, uint64_t warmupFrames) {
    StatsSummary s;
    s.frames = frames.size();
    s.warmupFrames = std::min<uint64_t>(warmupFrames, frames.size() / 2);  // short runs keep half
    std::vector<double> ms, err, est, estNoFb, windows;
    uint64_t atMin = 0, atMax = 0, inWindow = 0, windowToggles = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
        const FrameStats& f = frames[i];
        s.peakResidentBytes = std::max(s.peakResidentBytes, f.residentBytes);
        s.peakMemoryEstimateBytes = std::max(s.peakMemoryEstimateBytes, f.memoryEstimateBytes);
        s.loads += f.loads;
        s.evictions += f.evictions;
        s.failedLoads += f.failedLoads;
        s.misses += f.misses;
        s.longestStallMs = std::max(s.longestStallMs, f.stallMs);
        if (i < s.warmupFrames) continue;
        s.upToggles += f.upToggles;
        s.downToggles += f.downToggles;
        s.reversals += f.reversals;
        windowToggles += f.upToggles + f.downToggles;
        if (++inWindow == kToggleWindow) {
            windows.push_back(double(windowToggles));
            inWindow = windowToggles = 0;
        }
        atMin += f.hlod0ShareMs <= kMinShare * f.targetMs * (1 + 1e-9);
        atMax += f.hlod0ShareMs >= kMaxShare * f.targetMs * (1 - 1e-9);
        ms.push_back(f.actualMs);
        err.push_back(f.actualMs - f.targetMs);
        if (f.estimateMs > 0) est.push_back(100 * (f.actualMs - f.estimateMs) / f.estimateMs);  // §6.3 footnote 2
        if (f.estimateNoFeedbackMs > 0) estNoFb.push_back(100 * (f.actualMs - f.estimateNoFeedbackMs) / f.estimateNoFeedbackMs);
    }
    s.frameMs = distributionOf(ms);
    s.errorMs = distributionOf(err);
    s.estimateErrorPct = distributionOf(est);
    s.estimateNoFbErrorPct = distributionOf(estNoFb);
    s.estimatedFrames = est.size(), s.estimatedNoFbFrames = estNoFb.size();
    size_t counted = frames.size() - s.warmupFrames;
    const double toggles = double(s.upToggles + s.downToggles);
    s.togglesPerFrame = counted ? toggles / counted : 0;
    if (counted) s.distance = frames.back().distance - frames[s.warmupFrames].distance;
    s.togglesPerDistance = s.distance > 0 ? toggles / s.distance : std::nan("");  // a turn or a still camera: no rate
    s.toggleWindows = windows.size();
    if (!windows.empty()) {
        Distribution w = distributionOf(windows);
        s.windowTogglesMean = w.mean;
        s.windowTogglesMin = *std::min_element(windows.begin(), windows.end());
        s.windowTogglesMax = w.max;
    }
    s.shareAtMinPct = counted ? 100.0 * atMin / counted : 0;
    s.shareAtMaxPct = counted ? 100.0 * atMax / counted : 0;
    return s;
}

void printSummary(std::ostream& os, const StatsSummary& s) {
    char buf[1536];
    std::snprintf(buf, sizeof buf,
                  "frames %llu (first %llu excluded as warm-up)\n"
                  "frame time ms: mean %.3f sd %.3f p99 %.3f max %.3f\n"
                  "error to target ms: mean %.3f sd %.3f p99 %.3f\n"
                  "estimate error %% (actual - estimate, negative = conservative): with feedback %s; without %s\n"
                  "toggles per frame %.4f (up %llu, down %llu; reversals within 35 frames %llu)\n"
                  "toggles per unit of distance %s over %.1f; per %llu frames: mean %.2f min %.0f max %.0f (%llu windows)\n"
                  "hlod0 share at its lower bound %.1f %% of frames, at its upper bound %.1f %%\n"
                  "peak resident bytes %llu, peak c_memory estimate %.0f\n"
                  "loads %llu, evictions %llu, failed loads %llu, misses %llu, longest render-thread stall %.3f ms\n",
                  (unsigned long long)s.frames, (unsigned long long)s.warmupFrames, s.frameMs.mean, s.frameMs.sd,
                  s.frameMs.p99, s.frameMs.max, s.errorMs.mean, s.errorMs.sd, s.errorMs.p99,
                  figureOr("n/a", s.estimatedFrames > 0, "mean %.2f sd %.2f", s.estimateErrorPct.mean, s.estimateErrorPct.sd).c_str(),
                  figureOr("n/a", s.estimatedNoFbFrames > 0, "mean %.2f sd %.2f", s.estimateNoFbErrorPct.mean, s.estimateNoFbErrorPct.sd).c_str(),
                  s.togglesPerFrame,
                  (unsigned long long)s.upToggles, (unsigned long long)s.downToggles, (unsigned long long)s.reversals,
                  figureOr("n/a", !std::isnan(s.togglesPerDistance), "%.4f", s.togglesPerDistance).c_str(), s.distance, (unsigned long long)kToggleWindow, s.windowTogglesMean,
                  s.windowTogglesMin, s.windowTogglesMax, (unsigned long long)s.toggleWindows, s.shareAtMinPct,
                  s.shareAtMaxPct, (unsigned long long)s.peakResidentBytes, s.peakMemoryEstimateBytes,
                  (unsigned long long)s.loads, (unsigned long long)s.evictions, (unsigned long long)s.failedLoads,
                  (unsigned long long)s.misses,
                  s.longestStallMs);
    os << buf;
}

std::string summaryJson(const StatsSummary& s, const Constants& c) {
    nlohmann::json constants = nlohmann::json::object();
    for (const auto& [k, v] : constantsAsPairs(c, kUsedByPlayer)) constants[k] = v;
    nlohmann::json j = {{"frames", s.frames},
                        {"warmup_frames", s.warmupFrames},
                        {"frame_ms", toJson(s.frameMs)},
                        {"error_ms", toJson(s.errorMs)},
                        {"estimate_error_pct", s.estimatedFrames ? toJson(s.estimateErrorPct) : nlohmann::json(nullptr)},
                        {"estimate_nofb_error_pct", s.estimatedNoFbFrames ? toJson(s.estimateNoFbErrorPct) : nlohmann::json(nullptr)},
                        {"toggles_per_frame", s.togglesPerFrame},
                        {"distance", s.distance},
                        {"toggles_per_distance", std::isnan(s.togglesPerDistance) ? nlohmann::json(nullptr) : nlohmann::json(s.togglesPerDistance)},
                        {"toggles_per_400_frames",
                         {{"windows", s.toggleWindows},
                          {"mean", s.windowTogglesMean},
                          {"min", s.windowTogglesMin},
                          {"max", s.windowTogglesMax}}},
                        {"up_toggles", s.upToggles},
                        {"down_toggles", s.downToggles},
                        {"reversals", s.reversals},
                        {"hlod0_share_at_min_pct", s.shareAtMinPct},
                        {"hlod0_share_at_max_pct", s.shareAtMaxPct},
                        {"peak_resident_bytes", s.peakResidentBytes},
                        {"peak_memory_estimate_bytes", s.peakMemoryEstimateBytes},
                        {"loads", s.loads},
                        {"evictions", s.evictions},
                        {"failed_loads", s.failedLoads},
                        {"misses", s.misses},
                        {"longest_stall_ms", s.longestStallMs},
                        {"constants", constants}};
    return jsonText(j, 2);
}

}  // namespace hlod
