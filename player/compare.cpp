// The `hlod compare` table (player/compare.h): reduction of each policy's frames and the three
// output forms (aligned text, CSV, JSON). NaN (no oracle) is written as an empty CSV field, "-"
// in the text table and null in JSON.
#include "player/compare.h"

#include "formats/json_text.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <ostream>

namespace hlod {

std::vector<double> benefitGaps(const PolicyRun& run, const PolicyRun& oracle) {
    std::vector<double> gaps(run.frames.size(), NAN);
    for (size_t i = 0; i < run.frames.size() && i < oracle.frames.size(); ++i) {
        double best = oracle.frames[i].benefit;
        if (best > 0) gaps[i] = (best - run.frames[i].benefit) / best;
    }
    return gaps;
}

PolicyRun policyRun(std::string policy, std::span<const FrameStats> frames, uint64_t warmup) {
    PolicyRun run;
    run.policy = std::move(policy);
    run.summary = summarize(frames, warmup);
    run.frames.reserve(frames.size());
    for (const FrameStats& f : frames) {
        uint64_t triangles = 0;
        for (uint64_t t : f.trianglesPerLevel) triangles += t;
        run.frames.push_back({f.frame, f.timeSeconds, f.targetMs, f.actualMs, f.benefit, f.selectionMs, f.optimisationMs,
                              triangles, f.visibleTriangles});
    }
    return run;
}

std::vector<CompareRow> compareRows(std::span<const PolicyRun> runs, const PolicyRun* oracle) {
    std::vector<CompareRow> rows;
    for (const PolicyRun& run : runs) {
        CompareRow r;
        r.policy = run.policy;
        r.frames = run.frames.size();
        r.invalidCuts = run.invalidCuts;
        const StatsSummary& s = run.summary;
        r.counted = s.frames - s.warmupFrames;
        r.frameMs = s.frameMs;
        r.togglesPerFrame = s.togglesPerFrame;
        r.togglesPerMetre = s.togglesPerDistance;
        r.reversals = s.reversals;
        std::vector<double> relError, selection;
        double benefit = 0, optimisation = 0, triangles = 0, gap = 0;
        uint64_t gaps = 0;
        std::vector<double> frameGaps = oracle ? benefitGaps(run, *oracle) : std::vector<double>();
        for (size_t i = s.warmupFrames; i < run.frames.size(); ++i) {
            const CompareFrame& f = run.frames[i];
            relError.push_back(std::abs(f.actualMs - f.targetMs) / f.targetMs);
            selection.push_back(f.selectionMs);
            benefit += f.benefit;
            optimisation += f.optimisationMs;
            triangles += double(f.triangles);
            if (oracle && !std::isnan(frameGaps[i])) gap += frameGaps[i], ++gaps;
        }
        Distribution rel = distributionOf(relError);
        r.relErrorP99 = rel.p99;
        r.relErrorMean = rel.mean;
        r.selectionMs = distributionOf(selection);
        if (r.counted) {
            r.benefitMean = benefit / r.counted;
            r.optimisationMsMean = optimisation / r.counted;
            r.trianglesMean = triangles / r.counted;
        }
        if (gaps) r.gapMean = gap / gaps;
        rows.push_back(r);
    }
    return rows;
}

void writeCompareText(std::ostream& os, std::span<const CompareRow> rows) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "%-14s %7s %8s %8s %8s %8s %8s %8s %11s %8s %9s %9s %6s %8s %8s %8s %6s\n", "policy",
                  "frames", "mean_ms", "max_ms", "sd_ms", "p99_ms", "relerr99", "relerr", "benefit", "gap", "tog/frame",
                  "tog/m", "revers", "sel_ms", "selmax", "tris", "badcut");
    os << buf;
    for (const CompareRow& r : rows) {
        std::snprintf(buf, sizeof buf, "%-14s %7llu %8.3f %8.3f %8.3f %8.3f %8.4f %8.4f %11.5g %8s %9.4f %9s %6llu %8.4f %8.4f %8.0f %6llu\n",
                      r.policy.c_str(), (unsigned long long)r.counted, r.frameMs.mean, r.frameMs.max, r.frameMs.sd,
                      r.frameMs.p99, r.relErrorP99, r.relErrorMean, r.benefitMean, figureOr("-", !std::isnan(r.gapMean), "%.4f", r.gapMean).c_str(),
                      r.togglesPerFrame, figureOr("-", !std::isnan(r.togglesPerMetre), "%.4f", r.togglesPerMetre).c_str(), (unsigned long long)r.reversals, r.selectionMs.mean,
                      r.selectionMs.max, r.trianglesMean, (unsigned long long)r.invalidCuts);
        os << buf;
    }
}

void writeCompareCsv(std::ostream& os, std::span<const CompareRow> rows) {
    os << "policy,frames,counted_frames,frame_ms_mean,frame_ms_max,frame_ms_sd,frame_ms_p99,rel_error_p99,rel_error_mean,benefit_mean,"
          "gap_mean,toggles_per_frame,toggles_per_metre,reversals,selection_ms_mean,selection_ms_max,"
          "optimisation_ms_mean,tris_mean,invalid_cuts\n";
    char buf[512];
    for (const CompareRow& r : rows) {
        std::snprintf(buf, sizeof buf, "%s,%llu,%llu,%.4f,%.4f,%.4f,%.4f,%.5f,%.5f,%.6g,%s,%.5f,%s,%llu,%.5f,%.5f,%.5f,%.1f,%llu\n",
                      r.policy.c_str(), (unsigned long long)r.frames, (unsigned long long)r.counted, r.frameMs.mean,
                      r.frameMs.max, r.frameMs.sd, r.frameMs.p99, r.relErrorP99, r.relErrorMean, r.benefitMean,
                      figureOr("", !std::isnan(r.gapMean), "%.5f", r.gapMean).c_str(), r.togglesPerFrame, figureOr("", !std::isnan(r.togglesPerMetre), "%.5f", r.togglesPerMetre).c_str(),
                      (unsigned long long)r.reversals, r.selectionMs.mean, r.selectionMs.max, r.optimisationMsMean,
                      r.trianglesMean, (unsigned long long)r.invalidCuts);
        os << buf;
    }
}

std::string compareJson(std::span<const CompareRow> rows, const std::vector<std::pair<std::string, std::string>>& setup) {
    nlohmann::json j;
    for (const auto& [k, v] : setup) j["setup"][k] = v;
    j["policies"] = nlohmann::json::array();
    auto dist = [](const Distribution& d) {
        return nlohmann::json{{"mean", d.mean}, {"sd", d.sd}, {"p99", d.p99}, {"max", d.max}};
    };
    for (const CompareRow& r : rows)
        j["policies"].push_back({{"policy", r.policy},
                                 {"frames", r.frames},
                                 {"counted_frames", r.counted},
                                 {"frame_ms", dist(r.frameMs)},
                                 {"rel_error_p99", r.relErrorP99},
                                 {"rel_error_mean", r.relErrorMean},
                                 {"benefit_mean", r.benefitMean},
                                 {"gap_mean", std::isnan(r.gapMean) ? nlohmann::json(nullptr) : nlohmann::json(r.gapMean)},
                                 {"toggles_per_frame", r.togglesPerFrame},
                                 {"toggles_per_metre", std::isnan(r.togglesPerMetre) ? nlohmann::json(nullptr) : nlohmann::json(r.togglesPerMetre)},
                                 {"reversals", r.reversals},
                                 {"selection_ms", dist(r.selectionMs)},
                                 {"optimisation_ms_mean", r.optimisationMsMean},
                                 {"tris_mean", r.trianglesMean},
                                 {"invalid_cuts", r.invalidCuts}});
    return jsonText(j, 2);
}

}  // namespace hlod
