// `hlod stats` output: a text report (thesis §3.2 figures first, then per level, the hlod0
// resident set, build time per stage, and the thesis's figures beside ours for the thesis-scale
// city) and the same facts as JSON (--json).
#include "pipeline/stats/stats.h"

#include "formats/constants.h"

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>

namespace hlod::stats {

namespace {

std::string count(uint64_t v) {
    char buf[32];
    if (v >= 1'000'000) std::snprintf(buf, sizeof buf, "%.2f M", v / 1e6);
    else std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(v));
    return buf;
}

std::string mib(uint64_t b) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f MiB", b / 1048576.0);
    return buf;
}

template <class... A>
std::string fmt(const char* f, A... a) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, a...);
    return buf;
}

double meanTriangles(const Stats& s) {
    return s.summary.nodes ? double(s.totalTriangles) / double(s.summary.nodes) : 0;
}

uint64_t levelTriangles(const LevelSummary& L) { return L.texturedTriangles + L.untexturedTriangles; }

const LevelSummary* hlod0(const Stats& s) { return s.summary.levels.empty() ? nullptr : &s.summary.levels[0]; }

// The two readings of §3.2 beside the thesis's 114 / 2,296 / 5 (pipeline/TREE.md).
void printArithmetic(std::ostream& os, const Stats& s) {
    const ThesisFigures t;
    const TreeArithmetic a = thesisArithmetic(Constants{});
    const uint64_t k = static_cast<uint64_t>(a.levelFactor);
    os << fmt("thesis §3.2 tree arithmetic (Table 6.1: c_desiredTris %.0f, c_levelFactor %llu; pipeline/TREE.md):\n",
              a.desiredTris, (unsigned long long)k);
    os << fmt("  mean block %s / %llu = %.0f triangles, hlod0 factor %.1f\n", count(t.triangles).c_str(),
              (unsigned long long)t.hlod0Nodes, a.meanBlockTriangles, a.hlod0Factor);
    for (const auto& [name, shape] : {std::pair{"below-one  (divide while the factor is > 1)", a.belowOne},
                                      std::pair{"stop-before (no level whose factor is < 1)", a.stopBefore}})
        os << fmt("  %-44s depth %u, %llu nodes per block, x %llu = %llu nodes\n", name, shape.levels,
                  (unsigned long long)shape.nodes, (unsigned long long)t.hlod0Nodes,
                  (unsigned long long)(shape.nodes * t.hlod0Nodes));
    os << fmt("  thesis: %llu nodes, depth %u (%.1f nodes per block); %llu x %.0f = %s triangles, not %s\n",
              (unsigned long long)t.nodes, t.depth, double(t.nodes) / double(t.hlod0Nodes), (unsigned long long)t.nodes,
              a.desiredTris, count(uint64_t(double(t.nodes) * a.desiredTris)).c_str(), count(t.triangles).c_str());
    os << fmt("  a full %llu-ary tree has 1 + %llu m nodes, so %llu of them have %llu (mod %llu) in all; the thesis's %llu "
              "is %llu (mod %llu)%s\n", (unsigned long long)k, (unsigned long long)k, (unsigned long long)t.hlod0Nodes,
              (unsigned long long)(t.hlod0Nodes % k), (unsigned long long)k, (unsigned long long)t.nodes,
              (unsigned long long)(t.nodes % k), (unsigned long long)k,
              t.hlod0Nodes % k != t.nodes % k ? ": some divisions gave fewer pieces (even planes leave empty ones)" : "");
    os << fmt("  ours (--leaf-rule %s --planes %s): %llu nodes, depth %u\n", s.leafRule.empty() ? "below-one" : s.leafRule.c_str(),
              s.planes.empty() ? "balanced" : s.planes.c_str(), (unsigned long long)s.summary.nodes, s.summary.depth);
}

}  // namespace

nlohmann::json toJson(const Stats& s) {
    nlohmann::json levels = nlohmann::json::array();
    for (const LevelSummary& L : s.summary.levels) {
        levels.push_back({{"level", L.level},
                          {"nodes", L.nodes},
                          {"triangles", levelTriangles(L)},
                          {"textured_triangles", L.texturedTriangles},
                          {"untextured_triangles", L.untexturedTriangles},
                          {"texels", L.texels},
                          {"geometry_bytes", L.geometryBytes},
                          {"texture_bytes", L.textureBytes},
                          {"mean_triangles_per_node", L.nodes ? double(levelTriangles(L)) / double(L.nodes) : 0.0}});
        const LevelCheck& c = s.checks.at(L.level);
        levels.back().update({{"max_triangles_per_node", c.maxTriangles},
                              {"simplified_nodes", c.simplifiedNodes},
                              {"nodes_missing_target", c.missing},
                              {"misses_target", c.missing > 0},
                              {"worst_target_ratio", c.worstRatio},
                              {"geometric_error_mean", c.meanError},
                              {"geometric_error_max", c.maxError}});
    }
    const LevelSummary* h0 = hlod0(s);
    nlohmann::json j = {
        {"database", s.summary.path},
        {"file_bytes", s.summary.fileSize},
        {"blocks", s.summary.blocks},
        {"hlod0_nodes", h0 ? h0->nodes : 0},
        {"nodes", s.summary.nodes},
        {"max_depth", s.summary.depth},
        {"input_triangles", inputTriangles(s)},
        {"leaf_nodes", s.leafNodes},
        {"leaf_triangles", s.leafTriangles},
        {"leaf_texels", s.leafTexels},
        {"levels", levels},
        {"hlod0_resident",
         {{"nodes", h0 ? h0->nodes : 0},
          {"triangles", h0 ? levelTriangles(*h0) : 0},
          {"texels", h0 ? h0->texels : 0},
          {"bytes", h0 ? h0->geometryBytes + h0->textureBytes : 0},
          {"decoded_texture_bytes", h0 ? h0->texels * 3 : 0}}},
        {"mean_triangles_per_node", meanTriangles(s)},
        {"c_desiredTris", s.desiredTris},
        {"c_levelFactor", s.levelFactor},
        {"target_slack", kTargetSlack},
        {"hlod0_triangles_per_node", {{"mean", h0 && h0->nodes ? double(levelTriangles(*h0)) / double(h0->nodes) : 0.0},
                                      {"max", s.checks.empty() ? 0 : s.checks[0].maxTriangles}}},
        {"leaf_rule", s.leafRule},
        {"planes", s.planes},
        {"error_cap", s.errorCap},
    };
    if (s.build) {
        nlohmann::json stages = nlohmann::json::array();
        for (const BuildStage& st : s.build->stages)
            stages.push_back({{"name", st.name}, {"seconds", st.seconds}, {"items", st.items}});
        j["build"] = {{"sidecar", buildReportPath(s.summary.path)}, {"stages", stages}, {"wall_seconds", s.build->wallSeconds},
                      {"cpu_seconds", s.build->cpuSeconds}, {"peak_rss_bytes", s.build->peakRssBytes}};
        nlohmann::json quality = nlohmann::json::array();
        for (const LevelQuality& q : levelQuality(s.build->nodes)) {
            quality.push_back({{"nodes", q.nodes}, {"error_mean", q.errorMean}, {"error_max", q.errorMax},
                               {"error_one_sided_max", q.oneSidedMax}, {"baked_nodes", q.baked}, {"bake_psnr_min_db", q.psnrMin},
                               {"bake_psnr_mean_db", q.psnrMean}, {"texels", q.texels}});
            if (q.fidelitySamples)
                quality.back()["texture_fidelity"] = {{"psnr_db", q.fidelityPsnr()}, {"texels_used", q.fidelityTexels},
                                                      {"texels_stored", q.fidelityStoredTexels}};
        }
        j["build"]["measured_per_level"] = quality;
    }
    if (s.city)
        j["synthetic_city"] = {{"manifest", s.city->path}, {"scale", s.city->scale}, {"seed", s.city->seed},
                               {"blocks", s.city->blocks}, {"triangles", s.city->triangles},
                               {"texels", s.city->texels}};
    if (s.thesis) {
        ThesisFigures t;
        j["thesis"] = {{"hlod0_nodes", t.hlod0Nodes}, {"nodes", t.nodes}, {"max_depth", t.depth},
                       {"triangles", t.triangles}, {"texels", t.texels},
                       {"uncompressed_texture_mib", t.uncompressedTextureMiB}};
        const TreeArithmetic a = thesisArithmetic(Constants{});
        const uint64_t k = static_cast<uint64_t>(a.levelFactor);
        j["thesis"]["arithmetic"] = {
            {"c_desiredTris", a.desiredTris}, {"c_levelFactor", a.levelFactor},
            {"mean_block_triangles", a.meanBlockTriangles}, {"hlod0_factor", a.hlod0Factor},
            {"below_one", {{"levels", a.belowOne.levels}, {"nodes_per_block", a.belowOne.nodes},
                           {"nodes", a.belowOne.nodes * t.hlod0Nodes}}},
            {"stop_before", {{"levels", a.stopBefore.levels}, {"nodes_per_block", a.stopBefore.nodes},
                             {"nodes", a.stopBefore.nodes * t.hlod0Nodes}}},
            {"full_forest_nodes_mod_c_levelFactor", t.hlod0Nodes % k},
            {"thesis_nodes_mod_c_levelFactor", t.nodes % k}};
    }
    return j;
}

void printStats(std::ostream& os, const Stats& s) {
    const LevelSummary* h0 = hlod0(s);
    os << s.summary.path << ": HLOD database " << s.summary.major << "." << s.summary.minor << ", "
       << mib(s.summary.fileSize) << "\n";
    os << fmt("%-34s %llu\n", "blocks (= hlod0 nodes)", (unsigned long long)(h0 ? h0->nodes : 0));
    os << fmt("%-34s %llu\n", "total nodes", (unsigned long long)s.summary.nodes);
    os << fmt("%-34s %u\n", "maximum depth (levels on a path)", s.summary.depth);
    os << fmt("%-34s %s%s\n", "input triangles", count(inputTriangles(s)).c_str(),
              s.build ? " (build sidecar)" : " (leaves)");
    os << fmt("%-34s %s in %llu leaves\n", "finest texels", count(s.leafTexels).c_str(), (unsigned long long)s.leafNodes);
    os << fmt("%-34s %.0f (c_desiredTris = %.0f, ratio %.2f)\n", "mean triangles per node", meanTriangles(s),
              s.desiredTris, s.desiredTris > 0 ? meanTriangles(s) / s.desiredTris : 0.0);
    if (h0 && !s.checks.empty()) {
        const uint64_t most = s.checks[0].maxTriangles, limit = uint64_t(kTargetSlack * s.desiredTris);
        os << fmt("%-34s mean %.0f, max %llu (target c_desiredTris, at most %.2f x = %llu): %s\n", "hlod0 triangles per node",
                  h0->nodes ? double(levelTriangles(*h0)) / double(h0->nodes) : 0.0, (unsigned long long)most,
                  kTargetSlack, (unsigned long long)limit, s.checks[0].missing ? "MISSED" : "ok");
    }
    if (!s.leafRule.empty())
        os << fmt("%-34s --leaf-rule %s --planes %s%s\n", "tree", s.leafRule.c_str(), s.planes.c_str(),
                  s.errorCap.empty() ? "" : (" --error-cap " + s.errorCap).c_str());
    os << fmt("%5s %7s %12s %12s %14s %14s %9s %9s %8s %9s %9s\n", "level", "nodes", "triangles", "texels", "geometry",
              "textures", "tris/node", "max/node", "missed", "err mean", "err max");
    for (const LevelSummary& L : s.summary.levels) {
        const LevelCheck& c = s.checks.at(L.level);
        os << fmt("%5u %7llu %12llu %12llu %14s %14s %9.0f %9llu %8llu %9.3f %9.3f\n", L.level, (unsigned long long)L.nodes,
                  (unsigned long long)levelTriangles(L), (unsigned long long)L.texels, mib(L.geometryBytes).c_str(),
                  mib(L.textureBytes).c_str(), L.nodes ? double(levelTriangles(L)) / double(L.nodes) : 0.0,
                  (unsigned long long)c.maxTriangles, (unsigned long long)c.missing, c.meanError, c.maxError);
    }
    for (size_t l = 0; l < s.checks.size(); ++l) {  // every simplified level against its target
        const LevelCheck& c = s.checks[l];
        if (!c.simplifiedNodes) continue;
        const double perNode = c.simplifiedTriangles / double(c.simplifiedNodes), target = c.targetTriangles / double(c.simplifiedNodes);
        const std::string versus = fmt("%.0f tris/node vs target %.0f (%.2f x)", perNode, target, perNode / target);
        if (c.missing)
            os << fmt("level %zu MISSES its target: %llu of %llu simplified nodes above %.2f x numTriangles / factor "
                      "(worst %.2f x); %s\n", l, (unsigned long long)c.missing, (unsigned long long)c.simplifiedNodes,
                      kTargetSlack, c.worstRatio, versus.c_str());
        else
            os << fmt("level %zu: %s, ok\n", l, versus.c_str());
    }
    if (s.build && !s.build->nodes.empty()) {  // what the build measured (two-sided error, baking)
        os << "measured by the build (" << buildReportPath(s.summary.path) << "): "
           << (s.treeError == "bound" ? "upper bound of the error against the original surface (distance to the children's "
                                        "surface + their largest error, --mode bottom-up; input units)\n"
               : s.treeError == "simplifier"
                   ? "the simplifier's estimate, no distance measured (the children's largest + meshoptimizer's quadric error, "
                     "--bottom-up-error simplifier; not a bound; input units)\n"
                   : "error against the original surface (input units)\n");
        const std::vector<LevelQuality> quality = levelQuality(s.build->nodes);
        for (size_t l = 0; l < quality.size(); ++l) {
            const LevelQuality& q = quality[l];
            if (s.treeError == "simplifier") os << fmt("  level %zu: estimate mean %.3g max %.3g", l, q.errorMean, q.errorMax);
            else os << fmt("  level %zu: two-sided mean %.3g max %.3g (one-sided max %.3g)", l, q.errorMean, q.errorMax, q.oneSidedMax);
            if (q.baked) os << fmt(", %llu of %llu nodes baked, PSNR min %.1f mean %.1f dB", (unsigned long long)q.baked,
                                   (unsigned long long)q.nodes, q.psnrMin, q.psnrMean);
            if (q.fidelitySamples)
                os << fmt(", stored textures vs source PSNR %.2f dB over the %s texels triangles use (%.1f %% of %s stored)",
                          q.fidelityPsnr(), count(q.fidelityTexels).c_str(),
                          100.0 * double(q.fidelityTexels) / double(std::max<uint64_t>(1, q.fidelityStoredTexels)),
                          count(q.fidelityStoredTexels).c_str());
            os << "\n";
        }
    }
    if (h0)
        os << "hlod0 resident set (always in memory): " << h0->nodes << " nodes, " << levelTriangles(*h0)
           << " triangles, " << h0->texels << " texels, " << mib(h0->geometryBytes + h0->textureBytes)
           << " on disk, " << mib(h0->texels * 3) << " decoded RGB\n";
    if (s.build) {
        os << "build time per stage (" << buildReportPath(s.summary.path) << "):\n";
        for (const BuildStage& st : s.build->stages)
            os << fmt("  %-20s %10.2f s %12llu items\n", st.name.c_str(), st.seconds, (unsigned long long)st.items);
        os << fmt("  wall %.2f s, cpu %.2f s, peak RSS %s\n", s.build->wallSeconds, s.build->cpuSeconds,
                  mib(s.build->peakRssBytes).c_str());
    } else {
        os << "build time per stage: no " << buildReportPath(s.summary.path) << "\n";
    }
    if (s.city)
        os << "input: synthetic city " << s.city->path << " (scale " << s.city->scale << ", seed " << s.city->seed
           << ", " << s.city->blocks << " blocks, " << count(s.city->triangles) << " triangles, "
           << count(s.city->texels) << " texels)\n";
    if (!s.thesis) return;
    ThesisFigures t;
    os << fmt("%-22s %14s %14s\n", "thesis vs ours", "thesis (§3.2)", "ours");
    os << fmt("%-22s %14llu %14llu\n", "hlod0 nodes", (unsigned long long)t.hlod0Nodes,
              (unsigned long long)(h0 ? h0->nodes : 0));
    os << fmt("%-22s %14llu %14llu\n", "total nodes", (unsigned long long)t.nodes, (unsigned long long)s.summary.nodes);
    os << fmt("%-22s %14u %14u\n", "maximum depth", t.depth, s.summary.depth);
    os << fmt("%-22s %14s %14s\n", "triangles", count(t.triangles).c_str(), count(inputTriangles(s)).c_str());
    uint64_t texels = s.city ? s.city->texels : s.leafTexels;
    os << fmt("%-22s %14s %14s\n", "texels", count(t.texels).c_str(), count(texels).c_str());
    os << fmt("%-22s %14llu %14.0f\n", "uncompressed MiB", (unsigned long long)t.uncompressedTextureMiB,
              double(texels) * 3 / 1048576.0);
    printArithmetic(os, s);
}

}  // namespace hlod::stats
