// The preprocessing statistics of thesis §3.2 from a database: the per-level summary of
// formats/inspect.h (so stats and inspect always agree), plus the leaves (the finest detail,
// which is the input model), the triangles over all nodes for the mean per node against
// c_desiredTris, and the build sidecar and city manifest when they exist.
#include "pipeline/stats/stats.h"

#include "formats/constants.h"

#include <stdexcept>
#include <string>

namespace hlod::stats {

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
    s.desiredTris = Constants{}.desiredTris;
    if (const std::string* v = sk.findMeta("c_desiredTris")) {
        Constants c;
        try {
            setConstant(c, "c_desiredTris", *v);
        } catch (const std::invalid_argument& e) {
            throw std::runtime_error(db.path() + ": metadata " + e.what());
        }
        s.desiredTris = c.desiredTris;
    }
    s.build = readBuildReport(buildReportPath(db.path()));
    s.city = findCityManifest(db.path(), sk);
    s.thesis = forceThesis || isThesisScale(s.city);
    return s;
}

uint64_t inputTriangles(const Stats& s) {
    return s.build && s.build->inputTriangles ? s.build->inputTriangles : s.leafTriangles;
}

}  // namespace hlod::stats
