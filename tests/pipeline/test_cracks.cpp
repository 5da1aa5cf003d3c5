// No cracks in the stored database (test_simplify.cpp checks them before encoding): a 3 x 3-block terrain is built end to end, every node
// decoded from its Draco blobs, and for fronts mixing levels (hlod0 of a block beside leaves
// of its neighbour, siblings at different levels, all hlod0, all leaves) every open border of
// every node must lie on the border of another node of the front, except the model's outline.
// Tolerance: 0 (exact). The cuts make shared borders identical floats and the position lattice
// (formats/codec_draco.cpp) decodes an identical float identically in every blob. The same
// checks run on a --mode bottom-up build (StoredCracksBottomUp: the same tree, each node
// simplified from its children's simplified triangles).
#include "helpers.h"

#include "formats/codec.h"
#include "formats/db.h"
#include "tests/support/run_hlod.h"

#include <array>
#include <map>
#include <sstream>

namespace hlod::test {
namespace {

using Point = std::array<float, 3>;
using Edge = std::pair<Point, Point>;

struct NodeBorder {
    std::vector<Edge> edges;  // edges of one triangle only (positions welded over its blobs)
};

NodeBorder border(const Database& db, const Node& n) {
    std::map<Point, uint32_t> ids;
    std::vector<Point> points;
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (uint32_t b = n.firstBlob; b < n.firstBlob + n.blobCount; ++b) {
        if (db.skeleton().blobs[b].kind != BlobKind::Geometry) continue;
        const MeshData m = decodeGeometry(db.readBlob(b), "blob " + std::to_string(b));
        std::vector<uint32_t> welded(m.vertexCount());
        for (size_t v = 0; v < m.vertexCount(); ++v) {
            const Point p{m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
            welded[v] = ids.emplace(p, static_cast<uint32_t>(points.size())).first->second;
            if (welded[v] == points.size()) points.push_back(p);
        }
        for (size_t t = 0; t < m.triangleCount(); ++t)
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = welded[m.indices[3 * t + k]], c = welded[m.indices[3 * t + (k + 1) % 3]];
                ++uses[{std::min(a, c), std::max(a, c)}];
            }
    }
    NodeBorder out;
    for (const auto& [edge, count] : uses)
        if (count == 1) out.edges.push_back({points[edge.first], points[edge.second]});
    return out;
}

double distance(const Point& p, const Edge& e) {
    double d[3], v[3], len = 0, along = 0;
    for (int c = 0; c < 3; ++c) d[c] = double(e.second[c]) - e.first[c], v[c] = double(p[c]) - e.first[c];
    for (int c = 0; c < 3; ++c) len += d[c] * d[c], along += d[c] * v[c];
    const double t = len > 0 ? std::clamp(along / len, 0.0, 1.0) : 0.0;
    double sum = 0;
    for (int c = 0; c < 3; ++c) sum += (v[c] - t * d[c]) * (v[c] - t * d[c]);
    return std::sqrt(sum);
}

class StoredCracks : public ::testing::Test {
protected:
    static void SetUpTestSuite() { setUp(BuildMode::TopDown); }
    static void setUp(BuildMode mode) {
        dir_ = new std::filesystem::path(std::filesystem::temp_directory_path() /
                                         ("hlod-pipeline-stored-cracks-" + std::to_string(getpid())));
        std::filesystem::create_directories(*dir_);
        writePly(file("terrain.ply"), terrain(96).mesh, true);  // 18,432 triangles over 100 x 100
        BuildOptions o;
        o.constants.desiredTris = 150;
        o.blockTriangles = 2100;  // 3 x 3 blocks of 3 levels: hlod0, 4 children, 16 leaves
        o.jobs = 1;
        o.mode = mode;
        std::ostringstream log;
        Progress progress(log, false);
        BuildRequest request;
        request.input = file("terrain.ply"), request.output = file("t.hlod"), request.options = o;
        runBuild(request, progress);
        db_ = new Database(Database::open(file("t.hlod")));
        for (const Node& n : db_->skeleton().nodes) borders_.push_back(border(*db_, n));
    }
    static void TearDownTestSuite() {
        delete db_;
        std::filesystem::remove_all(*dir_);
        delete dir_;
        borders_.clear();
    }
    static std::string file(const std::string& name) { return (*dir_ / name).string(); }

    // The front reached from the roots, refining a node when `refine` says so (leaves stay).
    static std::vector<uint32_t> front(const std::function<bool(const Node&)>& refine) {
        const Skeleton& s = db_->skeleton();
        std::vector<uint32_t> out, stack = s.roots();
        while (!stack.empty()) {
            const Node& n = s.nodes[stack.back()];
            stack.pop_back();
            if (n.firstChild != kNone && refine(n)) {
                for (uint32_t c : s.children(n.id)) stack.push_back(c);
            } else {
                out.push_back(n.id);
            }
        }
        return out;
    }

    // Largest distance from an endpoint of a front node's border edge (not on the model's
    // outline) to the border of another node of the front, and where it is.
    struct Gap {
        double largest = 0;
        size_t endpoints = 0;  // endpoints measured
        std::string where;
    };
    static Gap largestGap(const std::vector<uint32_t>& nodes) {
        const Skeleton& s = db_->skeleton();
        Box3f model = s.nodes[s.roots()[0]].bounds;
        for (uint32_t r : s.roots()) {
            const Box3f& b = s.nodes[r].bounds;
            model.min = {std::min(model.min.x, b.min.x), std::min(model.min.y, b.min.y), model.min.z};
            model.max = {std::max(model.max.x, b.max.x), std::max(model.max.y, b.max.y), model.max.z};
        }
        const double eps = 1e-4 * std::max(model.max.x - model.min.x, model.max.y - model.min.y);
        const auto outline = [&](const Point& p, int side) {
            const float value[4] = {model.min.x, model.max.x, model.min.y, model.max.y};
            return std::abs(double(p[side / 2]) - value[side]) <= eps;
        };
        std::map<Point, std::vector<uint32_t>> owners;  // border vertex -> front nodes having it
        for (uint32_t id : nodes)
            for (const Edge& e : borders_[id].edges)
                for (const Point& p : {e.first, e.second}) owners[p].push_back(id);
        Gap gap;
        for (uint32_t id : nodes)
            for (const Edge& e : borders_[id].edges) {
                bool onOutline = false;
                for (int side = 0; side < 4; ++side) onOutline = onOutline || (outline(e.first, side) && outline(e.second, side));
                if (onOutline) continue;
                for (const Point& p : {e.first, e.second}) {
                    ++gap.endpoints;
                    const std::vector<uint32_t>& has = owners[p];
                    if (std::any_of(has.begin(), has.end(), [&](uint32_t o) { return o != id; })) continue;
                    double nearest = INFINITY;
                    for (uint32_t other : nodes)
                        if (other != id)
                            for (const Edge& f : borders_[other].edges) nearest = std::min(nearest, distance(p, f));
                    if (nearest > gap.largest) {
                        gap.largest = nearest;
                        gap.where = "node " + std::to_string(id) + " (level " + std::to_string(s.nodes[id].level) + ", block " +
                                   std::to_string(s.nodes[id].block) + ") at (" + std::to_string(p[0]) + ", " +
                                   std::to_string(p[1]) + ")";
                    }
                }
            }
        return gap;
    }

    // Bottom-up (capped, the default since stop 43), hlod0 reaches c_desiredTris (150). Top-down
    // with --error-cap on (the default), a root keeps the accuracy of the same block with free
    // borders and pays for its locked grid-line borders in triangles (pipeline/TREE.md): still far
    // coarser than its children.
    static void checkShape(BuildMode mode) {
        const Skeleton& s = db_->skeleton();
        ASSERT_EQ(s.blockCount, 9u);
        for (const Node& n : s.nodes) EXPECT_LE(n.level, 2u);
        EXPECT_EQ(front([](const Node&) { return true; }).size(), 9u * 16);
        for (uint32_t root : s.roots()) {
            const Node& n = s.nodes[root];
            if (mode == BuildMode::BottomUp) {
                EXPECT_LE(n.triangles(), kTargetSlack * 150) << "hlod0 of block " << n.block;
            } else {
                uint64_t children = 0;
                for (uint32_t c : s.children(root)) children += s.nodes[c].triangles();
                EXPECT_LT(2 * n.triangles(), children) << "hlod0 of block " << n.block;
            }
            EXPECT_GT(n.geometricError, 0.0f) << "hlod0 of block " << n.block;
        }
    }
    static void checkNoGap() {
        const Skeleton& s = db_->skeleton();
        struct Case {
            std::string name;
            std::function<bool(const Node&)> refine;
        };
        std::vector<Case> cases = {{"all hlod0", [](const Node&) { return false; }},
                                   {"all leaves", [](const Node&) { return true; }}};
        for (uint32_t seed = 1; seed <= 4; ++seed)
            cases.push_back({"mixed " + std::to_string(seed), [seed](const Node& n) {
                                 const uint32_t hash = (n.id + 1) * 2654435761u ^ seed * 40503u;
                                 return ((hash >> 16) & 1) != 0;
                             }});
        for (const Case& c : cases) {
            const std::vector<uint32_t> nodes = front(c.refine);
            if (c.name.starts_with("mixed")) {
                std::vector<bool> levels(3);
                for (uint32_t id : nodes) levels[s.nodes[id].level] = true;
                EXPECT_TRUE(levels[0] && levels[1] && levels[2]) << c.name << " does not mix all three levels";
            }
            const Gap gap = largestGap(nodes);
            EXPECT_GT(gap.endpoints, 1000u) << c.name;  // 9 blocks: 4 inner block borders of about 96 edges
            EXPECT_EQ(gap.largest, 0.0) << c.name << ": largest border gap " << gap.largest << " at " << gap.where;
    }
    }

    static std::filesystem::path* dir_;
    static Database* db_;
    static std::vector<NodeBorder> borders_;
};
std::filesystem::path* StoredCracks::dir_ = nullptr;
Database* StoredCracks::db_ = nullptr;
std::vector<NodeBorder> StoredCracks::borders_;

TEST_F(StoredCracks, DatabaseHasNineBlocksOfThreeLevels) { checkShape(BuildMode::TopDown); }
TEST_F(StoredCracks, NoGapBetweenNodesOfAnyFront) { checkNoGap(); }

class StoredCracksBottomUp : public StoredCracks {
protected:
    static void SetUpTestSuite() { setUp(BuildMode::BottomUp); }
};
TEST_F(StoredCracksBottomUp, DatabaseHasNineBlocksOfThreeLevels) { checkShape(BuildMode::BottomUp); }
TEST_F(StoredCracksBottomUp, NoGapBetweenNodesOfAnyFront) { checkNoGap(); }

// One lattice per block: a leaf spans a quarter of its block's longest side (the block cut in
// four strips, each strip in four), so it needs 2 bits fewer than hlod0.
TEST_F(StoredCracks, LeavesNeedFewerPositionBitsThanTheirRoot) {
    const Skeleton& s = db_->skeleton();
    size_t leafBlobs = 0;
    for (uint32_t root : s.roots()) {
        const uint8_t rootBits = s.blobs[s.nodes[root].firstBlob].positionBits;
        for (const Node& n : s.nodes) {
            if (n.block != s.nodes[root].block || n.firstChild != kNone) continue;
            for (uint32_t b = n.firstBlob; b < n.firstBlob + n.blobCount; ++b, ++leafBlobs)
                EXPECT_LE(s.blobs[b].positionBits + 2, rootBits) << "node " << n.id;
        }
    }
    EXPECT_GE(leafBlobs, 16u * s.roots().size());  // each block's sixteen leaves, at least
}

// gridPositionStep (one lattice for all blocks of a grid) comes from one cell: the 33.3 m cells
// above give 2^-9 (33.3 / 16383 = 0.0020), the step each of their block roots gives.
TEST(PositionLattice, GridStepComesFromOneCell) {
    const Box3f flat{{0, 0, -2}, {100, 100, 2}};
    const GridSpec grid = chooseGrid(flat, 18432, 2100, 0);
    ASSERT_EQ(grid.cellsU * grid.cellsV, 9u);
    EXPECT_EQ(gridPositionStep(flat, grid, 14), std::ldexp(1.0, -9));
    const Box3f tall{{0, 0, 0}, {100, 100, 80}};  // the third axis, longer than a cell, decides
    EXPECT_EQ(gridPositionStep(tall, chooseGrid(tall, 18432, 2100, 0), 14), std::ldexp(1.0, -8));
}

// A given --draco-position-step must leave a block at most 2^kMaxPositionBits steps across: finer
// ones are refused before any work (before, 1e-20 crashed in Draco and 1e-45 stored every position
// as one point, both through integer overflow); and at least 2^kMinPositionBits: coarser ones
// collapsed the model (a step of 1 on a 100-unit model kept 4 % of its triangles, with geometric
// error 0, exit 0, until stop 45).
TEST(PositionLattice, AStepTooFineOrTooCoarseForABlockIsAUsageErrorBeforeAnyWork) {
    const Box3f unit{{0, 0, 0}, {1, 0.5f, 0}};
    EXPECT_NO_THROW(checkPositionStep("m.obj", unit, std::ldexp(1.0, -kMaxPositionBits)));
    EXPECT_NO_THROW(checkPositionStep("m.obj", unit, std::ldexp(1.0, -kMinPositionBits)));
    EXPECT_NO_THROW(checkPositionStep("m.obj", unit, 0));  // automatic
    EXPECT_THROW(checkPositionStep("m.obj", unit, std::ldexp(1.0, -kMaxPositionBits - 1)), std::invalid_argument);
    EXPECT_THROW(checkPositionStep("m.obj", unit, std::ldexp(1.0, -kMinPositionBits + 1)), std::invalid_argument);
    TempDir dir;
    writeObj(dir.file("m.obj"), terrain(4), "");
    for (const char* step : {"1e-20", "1e-45", "1", "1000"}) {
        const RunResult r = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--draco-position-step", step});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        const std::string why = std::string(step).find('-') != std::string::npos ? " is too fine for " : " is too coarse for ";
        EXPECT_EQ(r.err.rfind("hlod build: --draco-position-step " + std::string(step) + why + dir.file("m.obj"), 0), 0u)
            << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(r.out.find("split"), std::string::npos) << r.out;
        EXPECT_FALSE(std::filesystem::exists(dir.file("m.hlod")));
    }
    // A step that fits (here 2^-16, the finest for this block) is recorded exactly: std::to_string's
    // 6 decimals wrote it as 0.000015, and 2^-30 as 0.000000, "automatic" when run again.
    const RunResult ok = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--draco-position-step", "1.52587890625e-05"});
    ASSERT_EQ(ok.exitCode, 0) << ok.outAndErr();
    const Database db = Database::open(dir.file("m.hlod"));
    EXPECT_EQ(*db.skeleton().findMeta("draco.positionStep"), "1.52587890625e-05");
    EXPECT_NE(db.skeleton().findMeta("command")->find("--draco-position-step 1.52587890625e-05"), std::string::npos);
    // The encoder itself refuses a lattice too fine for its positions instead of overflowing.
    Piece one = terrain(2);
    DracoOptions fine;
    fine.positionStep = 1e-40;
    EXPECT_THROW(encodeGeometry(one.mesh, fine), std::runtime_error);
}

}  // namespace
}  // namespace hlod::test
