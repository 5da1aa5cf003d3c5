// `hlod stats` output: a text report (thesis §3.2 figures first, then per level, the hlod0
// resident set, build time per stage, and the thesis's figures beside ours for the thesis-scale
// city) and the same facts as JSON (--json).
#include "pipeline/stats/stats.h"

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
    };
    if (s.build) {
        nlohmann::json stages = nlohmann::json::array();
        for (const BuildStage& st : s.build->stages)
            stages.push_back({{"name", st.name}, {"seconds", st.seconds}, {"items", st.items}});
        j["build"] = {{"sidecar", buildReportPath(s.summary.path)}, {"stages", stages}, {"wall_seconds", s.build->wallSeconds},
                      {"cpu_seconds", s.build->cpuSeconds}, {"peak_rss_bytes", s.build->peakRssBytes}};
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
    os << fmt("%5s %7s %12s %12s %14s %14s %10s\n", "level", "nodes", "triangles", "texels", "geometry", "textures",
              "tris/node");
    for (const LevelSummary& L : s.summary.levels) {
        os << fmt("%5u %7llu %12llu %12llu %14s %14s %10.0f\n", L.level, (unsigned long long)L.nodes,
                  (unsigned long long)levelTriangles(L), (unsigned long long)L.texels, mib(L.geometryBytes).c_str(),
                  mib(L.textureBytes).c_str(), L.nodes ? double(levelTriangles(L)) / double(L.nodes) : 0.0);
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
}

}  // namespace hlod::stats
