// The preprocessing statistics of thesis §3.2 from a database: the per-level summary of
// formats/inspect.h (so stats and inspect always agree), plus the leaves (the finest detail,
// which is the input model), the triangles over all nodes for the mean per node against
// c_desiredTris, each level against its targets (LevelCheck), and the build sidecar and city
// manifest when they exist.
#include "pipeline/stats/stats.h"

#include "formats/constants.h"
#include "formats/errors.h"
#include "formats/metrics.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace hlod::stats {
namespace {

// A recorded constant as the build checked it (validate says the same): 1e300 printed 300-digit
// targets and c_levelFactor -1 negative ones until stop 49.
double constantMeta(const Database& db, const char* name) {
    Constants c;
    if (const std::string* v = db.skeleton().findMeta(name)) {
        try {
            setConstant(c, name, *v);
            validateConstants(c, kUsedByBuild);
        } catch (const std::invalid_argument& e) {
            throw FormatError(db.path() + ": metadata " + e.what());
        }
    }
    return std::string(name) == "c_desiredTris" ? c.desiredTris : c.levelFactor;
}

std::vector<LevelCheck> checkLevels(const Skeleton& sk, double desiredTris, double levelFactor, size_t levels) {
    std::vector<uint32_t> order = sk.roots();  // breadth-first: parents before children
    for (size_t i = 0; i < order.size(); ++i)
        for (uint32_t c : sk.children(order[i])) order.push_back(c);
    std::vector<double> leaves(sk.nodes.size()), rootLeaves(sk.nodes.size());
    for (size_t i = order.size(); i-- > 0;) {
        const Node& n = sk.nodes[order[i]];
        if (n.firstChild == kNone) leaves[n.id] = n.triangles();
        if (n.parent != kNone) leaves[n.parent] += leaves[n.id];
    }
    std::vector<LevelCheck> checks(levels);
    std::vector<uint64_t> nodes(levels);
    for (uint32_t id : order) {
        const Node& n = sk.nodes[id];
        rootLeaves[id] = n.parent == kNone ? leaves[id] : rootLeaves[n.parent];
        LevelCheck& L = checks.at(n.level);
        ++nodes[n.level];
        L.maxTriangles = std::max<uint64_t>(L.maxTriangles, n.triangles());
        L.meanError += n.geometricError, L.maxError = std::max(L.maxError, double(n.geometricError));
        if (n.firstChild == kNone || rootLeaves[id] <= 0) continue;
        const double target = desiredTris * std::pow(levelFactor, n.level) * leaves[id] / rootLeaves[id];
        const double ratio = n.triangles() / target;
        ++L.simplifiedNodes;
        L.simplifiedTriangles += n.triangles(), L.targetTriangles += target;
        L.worstRatio = std::max(L.worstRatio, ratio);
        if (ratio > kTargetSlack) ++L.missing;
    }
    for (size_t l = 0; l < levels; ++l) checks[l].meanError /= std::max<uint64_t>(1, nodes[l]);
    return checks;
}

}  // namespace

TreeArithmetic thesisArithmetic(const Constants& c) {
    const ThesisFigures t;
    TreeArithmetic a;
    a.desiredTris = c.desiredTris, a.levelFactor = c.levelFactor;
    a.meanBlockTriangles = double(t.triangles) / double(t.hlod0Nodes);
    a.hlod0Factor = a.meanBlockTriangles / c.desiredTris;
    a.belowOne = fullTree(a.meanBlockTriangles, c.desiredTris, c.levelFactor, LeafRule::BelowOne);
    a.stopBefore = fullTree(a.meanBlockTriangles, c.desiredTris, c.levelFactor, LeafRule::StopBefore);
    return a;
}

LevelCheck hlod0Check(const Database& db) {
    uint32_t levels = 0;
    for (const Node& n : db.skeleton().nodes) levels = std::max(levels, n.level + 1);
    if (levels == 0) return {};
    return checkLevels(db.skeleton(), constantMeta(db, "c_desiredTris"), constantMeta(db, "c_levelFactor"), levels).at(0);
}

Stats computeStats(const Database& db, bool forceThesis) {
    Stats s;
    s.summary = summarize(db);
    const Skeleton& sk = db.skeleton();
    for (const Node& n : sk.nodes) {
        s.totalTriangles += n.triangles();
        if (n.firstChild != kNone) continue;
        ++s.leafNodes;
        s.leafTriangles += n.triangles();
        s.leafTexels += n.texelCount;
    }
    s.desiredTris = constantMeta(db, "c_desiredTris");
    s.levelFactor = constantMeta(db, "c_levelFactor");
    s.checks = checkLevels(sk, s.desiredTris, s.levelFactor, s.summary.levels.size());
    if (const std::string* v = sk.findMeta("tree.leafRule")) s.leafRule = *v;
    if (const std::string* v = sk.findMeta("tree.planes")) s.planes = *v;
    if (const std::string* v = sk.findMeta("tree.error")) s.treeError = *v;
    if (const std::string* v = sk.findMeta("tree.errorCap")) s.errorCap = *v;
    s.build = readBuildReport(buildReportPath(db.path()));
    // A report beside a database it does not describe (two builds racing to one -o; a merge over an
    // earlier build, which writes no report) is left out with a warning: its figures were printed
    // for the database without a word until stop 47.
    std::error_code ec;
    const uint64_t bytes = std::filesystem::file_size(db.path(), ec);
    if (s.build && !ec && s.build->outputBytes != bytes) {
        s.staleReport = buildReportPath(db.path()) + ": the report of another build (of " + std::to_string(s.build->outputBytes) +
                        " bytes; the database has " + std::to_string(bytes) + "), left out";
        s.build.reset();
    }
    s.city = findCityManifest(db.path(), sk);
    s.thesis = forceThesis || isThesisScale(s.city);
    return s;
}

uint64_t inputTriangles(const Stats& s) {
    return s.build && s.build->inputTriangles ? s.build->inputTriangles : s.leafTriangles;
}

double LevelQuality::fidelityPsnr() const { return psnrDb(fidelitySquaredError, fidelitySamples); }

std::vector<LevelQuality> levelQuality(const std::vector<NodeQuality>& nodes) {
    std::vector<LevelQuality> levels;
    for (const NodeQuality& n : nodes) {
        if (levels.size() <= n.level) levels.resize(n.level + 1);
        LevelQuality& q = levels[n.level];
        ++q.nodes;
        q.texels += n.texels;
        q.errorMean += n.errorMean;  // summed here, divided below
        q.errorMax = std::max(q.errorMax, n.errorMax);
        q.oneSidedMax = std::max(q.oneSidedMax, n.errorOneSided);
        if (n.fidelitySamples) {
            q.fidelityTexels += n.fidelityTexels, q.fidelitySamples += n.fidelitySamples;
            q.fidelityStoredTexels += n.texels, q.fidelitySquaredError += n.fidelitySquaredError;
        }
        if (!n.baked) continue;
        q.psnrMin = q.baked ? std::min(q.psnrMin, n.bakePsnrDb) : n.bakePsnrDb;
        q.psnrMean += n.bakePsnrDb;
        ++q.baked;
    }
    for (LevelQuality& q : levels) {
        if (q.nodes) q.errorMean /= double(q.nodes);
        if (q.baked) q.psnrMean /= double(q.baked);
    }
    return levels;
}

}  // namespace hlod::stats
