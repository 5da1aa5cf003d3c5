// `hlod stats` (pipeline/stats): figures computed independently from the skeleton, agreement
// with `hlod inspect --json`, the build sidecar (present, absent, corrupt), the rule for showing
// the thesis's figures (synthetic city manifest at scale 1), and bad input on the command line.
#include "pipeline/stats/stats.h"

#include "formats/codec.h"

#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace hlod;
using hlod::test::RunResult;
using hlod::test::runHlod;

namespace {

struct Fixture {
    fs::path dir, db;
    explicit Fixture(const std::string& name) {
        dir = fs::temp_directory_path() / ("hlod_test_stats_" + name + "_" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
        db = dir / "tiny.hlod";
        SyntheticOptions o;  // 2 x 2 blocks, 3 levels, factor 4
        writeSyntheticDatabase(db.string(), o);
    }
    ~Fixture() { fs::remove_all(dir); }
};

void writeSidecar(const fs::path& db, const std::string& text) { std::ofstream(db.string() + ".build.json") << text; }

}  // namespace

TEST(Stats, FiguresMatchAnIndependentCountOfTheSkeleton) {
    Fixture f("count");
    Database db = Database::open(f.db.string());
    stats::Stats s = stats::computeStats(db, false);
    const Skeleton& sk = db.skeleton();
    std::vector<uint64_t> nodes(3), tris(3), texels(3);
    uint64_t leaves = 0, total = 0;
    for (const Node& n : sk.nodes) {
        ASSERT_LT(n.level, 3u);
        ++nodes[n.level];
        tris[n.level] += n.triangles();
        texels[n.level] += n.texelCount;
        total += n.triangles();
        leaves += n.firstChild == kNone;
    }
    EXPECT_EQ(s.summary.levels.at(0).nodes, 4u);  // blocks = hlod0 nodes
    EXPECT_EQ(s.summary.nodes, 4u * (1 + 4 + 16));
    EXPECT_EQ(s.summary.depth, 3u);
    ASSERT_EQ(s.summary.levels.size(), 3u);
    for (uint32_t L = 0; L < 3; ++L) {
        EXPECT_EQ(s.summary.levels[L].nodes, nodes[L]);
        EXPECT_EQ(s.summary.levels[L].texturedTriangles + s.summary.levels[L].untexturedTriangles, tris[L]);
        EXPECT_EQ(s.summary.levels[L].texels, texels[L]);
    }
    EXPECT_EQ(s.leafNodes, leaves);
    EXPECT_EQ(s.leafNodes, 64u);
    EXPECT_EQ(s.totalTriangles, total);
    EXPECT_EQ(stats::inputTriangles(s), tris[2]);  // no sidecar: the leaves
    EXPECT_DOUBLE_EQ(s.desiredTris, SyntheticOptions{}.trianglesPerNode);  // its c_desiredTris meta
    EXPECT_FALSE(s.build.has_value());
    EXPECT_FALSE(s.thesis);
    EXPECT_TRUE(stats::computeStats(db, true).thesis);
}

TEST(Stats, AgreesWithInspect) {
    Fixture f("inspect");
    RunResult st = runHlod({"stats", "--json", f.db.string()});
    RunResult in = runHlod({"inspect", "--json", f.db.string()});
    ASSERT_EQ(st.exitCode, 0) << st.err;
    ASSERT_EQ(in.exitCode, 0) << in.err;
    auto a = nlohmann::json::parse(st.out), b = nlohmann::json::parse(in.out);
    EXPECT_EQ(a["nodes"], b["nodes"]);
    EXPECT_EQ(a["blocks"], b["blocks"]);
    EXPECT_EQ(a["max_depth"], b["depth"]);
    ASSERT_EQ(a["levels"].size(), b["per_level"].size());
    for (size_t L = 0; L < a["levels"].size(); ++L) {
        const auto &x = a["levels"][L], &y = b["per_level"][L];
        EXPECT_EQ(x["nodes"], y["nodes"]);
        EXPECT_EQ(x["triangles"].get<uint64_t>(),
                  y["textured_triangles"].get<uint64_t>() + y["untextured_triangles"].get<uint64_t>());
        EXPECT_EQ(x["texels"], y["texels"]);
        EXPECT_EQ(x["geometry_bytes"], y["geometry_bytes"]);
        EXPECT_EQ(x["texture_bytes"], y["texture_bytes"]);
    }
    EXPECT_EQ(a["hlod0_nodes"], b["per_level"][0]["nodes"]);
}

TEST(Stats, ReadsTheBuildSidecar) {
    Fixture f("sidecar");
    writeSidecar(f.db, R"({"stages":[{"name":"read","seconds":1.5,"items":7},{"name":"simplify","seconds":2,"items":84}],
        "peak_rss_bytes":1048576,"input_triangles":12345,"wall_seconds":4,"cpu_seconds":6,"output_bytes":)" +
                           std::to_string(fs::file_size(f.db)) + "}");
    stats::Stats s = stats::computeStats(Database::open(f.db.string()), false);
    ASSERT_TRUE(s.build.has_value());
    ASSERT_EQ(s.build->stages.size(), 2u);
    EXPECT_EQ(s.build->stages[1].name, "simplify");
    EXPECT_EQ(s.build->stages[1].items, 84u);
    EXPECT_DOUBLE_EQ(s.build->stages[0].seconds, 1.5);
    EXPECT_EQ(stats::inputTriangles(s), 12345u);
    std::ostringstream text;
    stats::printStats(text, s);
    EXPECT_NE(text.str().find("simplify"), std::string::npos);
    EXPECT_EQ(text.str().find("thesis vs ours"), std::string::npos);
}

// A report whose database size is not this database's is left out with a warning (two builds racing
// to one -o, or a merge over an earlier build, left a report whose figures stats printed until stop 47).
TEST(Stats, TheReportOfAnotherBuildIsLeftOutWithAWarning) {
    Fixture f("other");
    writeSidecar(f.db, R"({"stages":[{"name":"simplify","seconds":2,"items":84}],"peak_rss_bytes":1,"input_triangles":12345,)"
                       R"("wall_seconds":1,"cpu_seconds":1,"output_bytes":99})");
    const RunResult r = runHlod({"stats", f.db.string()});
    EXPECT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_EQ(r.err, "warning: " + f.db.string() + ".build.json: the report of another build (of 99 bytes; the database has " +
                         std::to_string(fs::file_size(f.db)) + "), left out\n");
    EXPECT_EQ(r.out.find("simplify"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("12345"), std::string::npos) << r.out;
}

TEST(Stats, CorruptSidecarIsOneLineNamingIt) {
    Fixture f("corrupt");
    for (const char* bad : {"{\"stages\": [", "[1,2]", R"({"stages":[]})", R"({"stages":[{"name":3}]})"}) {
        writeSidecar(f.db, bad);
        RunResult r = runHlod({"stats", f.db.string()});
        EXPECT_EQ(r.exitCode, 2) << bad;  // an input that cannot be read
        EXPECT_NE(r.err.find(f.db.string() + ".build.json"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    // A level the report's nodes cannot reach (-1 read as 2^32 - 1: SIGSEGV; 2^31 - 1: std::bad_alloc).
    const std::string head = R"({"stages":[],"peak_rss_bytes":1,"input_triangles":1,"wall_seconds":1,"cpu_seconds":1,"output_bytes":1,)";
    for (const std::string level : {"-1", "2147483647", "1"}) {
        writeSidecar(f.db, head + R"("nodes":[{"block":0,"node":0,"level":)" + level +
                               R"(,"triangles":1,"texels":0,"error_one_sided":0,"error_mean":0,"error_max":0,"baked":false,"bake_psnr_db":0}]})");
        RunResult r = runHlod({"stats", f.db.string()});
        EXPECT_EQ(r.exitCode, 2) << level << ": " << r.err;
        EXPECT_NE(r.err.find(level == "-1" ? ".build.json: \"level\" must be a whole number from 0 to 4294967295"
                                           : ".build.json: node 0 has level "),
                  std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    // A count that is negative, fractional or beyond its type (-1 printed as 2^64 - 1 until stop 46).
    const std::string counts = R"({"stages":[],"peak_rss_bytes":1,"wall_seconds":1,"cpu_seconds":1,"output_bytes":1,)";
    for (const std::string bad : {R"("input_triangles":-1})", R"("input_triangles":2.5})", R"("input_triangles":1e30})",
                                  R"("input_triangles":1,"nodes_per_level":[3,-1]})"}) {
        writeSidecar(f.db, counts + bad);
        RunResult r = runHlod({"stats", f.db.string()});
        EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.err;
        EXPECT_NE(r.err.find("\" must be a whole number from 0 to 18446744073709551615"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    // A negative time (a wall time of -1 printed as given until stop 50).
    const std::string times = R"({"peak_rss_bytes":1,"input_triangles":1,"output_bytes":1,)";
    for (const std::string bad : {R"("stages":[],"wall_seconds":-1,"cpu_seconds":1})", R"("stages":[],"wall_seconds":1,"cpu_seconds":-0.5})",
                                  R"("stages":[{"name":"read","seconds":-2,"items":1}],"wall_seconds":1,"cpu_seconds":1})"}) {
        writeSidecar(f.db, times + bad);
        RunResult r = runHlod({"stats", f.db.string()});
        EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.err;
        EXPECT_NE(r.err.find("seconds\" must be a number of seconds, 0 or more"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    // A FIFO (blocked the open for good) or a folder in the report's place.
    fs::remove(f.db.string() + ".build.json");
    ASSERT_EQ(mkfifo((f.db.string() + ".build.json").c_str(), 0600), 0);
    RunResult fifo = runHlod({"stats", f.db.string()});
    EXPECT_EQ(fifo.exitCode, 2);
    EXPECT_NE(fifo.err.find(".build.json: not a regular file"), std::string::npos) << fifo.err;
    fs::remove(f.db.string() + ".build.json");
    fs::create_directory(f.db.string() + ".build.json");
    RunResult folder = runHlod({"stats", f.db.string()});
    EXPECT_EQ(folder.exitCode, 2);
    EXPECT_NE(folder.err.find(".build.json: a folder, not a build report"), std::string::npos) << folder.err;
}

TEST(Stats, MissingOrTruncatedDatabaseFailsCleanly) {
    Fixture f("bad");
    RunResult missing = runHlod({"stats", (f.dir / "nope.hlod").string()});
    EXPECT_NE(missing.exitCode, 0);
    EXPECT_NE(missing.err.find("nope.hlod"), std::string::npos) << missing.err;
    EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
    fs::resize_file(f.db, fs::file_size(f.db) / 2);
    RunResult truncated = runHlod({"stats", f.db.string()});
    EXPECT_NE(truncated.exitCode, 0);
    EXPECT_NE(truncated.err.find("tiny.hlod"), std::string::npos) << truncated.err;
    EXPECT_TRUE(truncated.out.empty());
}

TEST(Stats, ThesisFiguresOnlyForTheScaleOneCity) {
    fs::path dir = fs::temp_directory_path() / ("hlod_test_stats_city_" + std::to_string(::getpid()));
    fs::create_directories(dir / "city");
    auto manifest = [&](double scale) {
        std::ofstream(dir / "city" / "city.json")
            << nlohmann::json{{"generator", "hlod synth city"}, {"scale", scale}, {"seed", 1}, {"block_count", 114},
                              {"triangles", 8950000}, {"texels", 937000000}}.dump();
    };
    Skeleton sk;
    for (uint32_t b = 0; b < 114; ++b) {  // the manifest's 114 blocks, one root each
        Node root;
        root.id = b, root.block = b;
        sk.nodes.push_back(root);
    }
    sk.meta = {{"input", "city"}};  // relative to the database's directory
    std::string db = (dir / "city.hlod").string();
    manifest(1.0);
    auto m = stats::findCityManifest(db, sk);
    ASSERT_TRUE(m.has_value());
    EXPECT_EQ(m->blocks, 114u);
    EXPECT_TRUE(stats::isThesisScale(m));
    manifest(0.01);
    EXPECT_FALSE(stats::isThesisScale(stats::findCityManifest(db, sk)));
    std::ofstream(dir / "city" / "block_000.obj") << "v 0 0 0\n";
    sk.meta = {{"input", (dir / "city" / "block_000.obj").string()}};  // a file of the city: beside it
    EXPECT_TRUE(stats::findCityManifest(db, sk).has_value());
    // A relative input that is not beside a city.json above the database is not that city (until
    // stop 44 a bunny built in a/b/c reported the city.json of a/).
    fs::create_directories(dir / "city" / "a" / "b");
    std::ofstream(dir / "city" / "a" / "b" / "bunny.ply") << "ply\n";
    sk.meta = {{"input", "bunny.ply"}};
    EXPECT_FALSE(stats::findCityManifest((dir / "city" / "a" / "b" / "bunny.hlod").string(), sk).has_value());
    sk.meta = {{"input", "city"}};  // relative to a folder above the database (built from the repo root)
    EXPECT_TRUE(stats::findCityManifest((dir / "out" / "thesis" / "city.hlod").string(), sk).has_value());
    sk.meta = {{"input", "elsewhere"}};
    EXPECT_FALSE(stats::findCityManifest(db, sk).has_value());
    // A database of other blocks than the manifest's (one block of the city built alone) is not
    // that city (until stop 45 it reported the whole city's counts and the thesis's table).
    Skeleton one = sk;
    one.nodes.resize(1);
    one.meta = {{"input", (dir / "city" / "block_000.obj").string()}};
    EXPECT_FALSE(stats::findCityManifest(db, one).has_value());
    // Counts that are not counts (-1 was printed as 2^64 - 1; 1e300 was undefined behaviour).
    sk.meta = {{"input", "city"}};
    for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
             {"triangles", -1}, {"texels", 1e300}, {"block_count", 2.5}, {"scale", -1}, {"seed", "1"}}) {
        nlohmann::json j{{"generator", "hlod synth city"}, {"scale", 1.0}, {"seed", 1}, {"block_count", 114},
                         {"triangles", 8950000}, {"texels", 937000000}};
        j[key] = value;
        std::ofstream(dir / "city" / "city.json") << j.dump();
        std::string what;
        try {
            stats::findCityManifest(db, sk);
        } catch (const InputError& e) {
            what = e.what();
        }
        EXPECT_EQ(what, (dir / "city" / "city.json").string() + ": \"" + key + "\" = " + value.dump() + " is not " +
                      (key == "scale" ? "a positive number" : "a count"))
            << key;
    }
    fs::remove_all(dir);
}

namespace {

// A strip of `triangles` triangles over [x, x + 1] x [0, 1].
MeshData strip(uint32_t triangles, float x) {
    MeshData m;
    const uint32_t columns = triangles / 2 + 1;
    for (uint32_t i = 0; i <= columns; ++i)
        for (float y : {0.0f, 1.0f}) m.positions.insert(m.positions.end(), {x + float(i) / columns, y, 0.0f});
    for (uint32_t t = 0; t < triangles; ++t)
        m.indices.insert(m.indices.end(), {t, t % 2 ? t + 2 : t + 1, t % 2 ? t + 1 : t + 2});
    return m;
}

// One block per entry of `hlod0`: an hlod0 node of that many triangles over four 600-triangle leaves;
// `meta` replaces recorded values.
void writeTree(const std::string& path, const std::vector<uint32_t>& hlod0, const std::map<std::string, std::string>& meta = {}) {
    Constants c;  // c_desiredTris 900
    Writer w(path, c.textured);
    for (const auto& [name, value] : constantsAsPairs(c)) w.setMeta(name, meta.contains(name) ? meta.at(name) : value);
    for (uint32_t b = 0; b < hlod0.size(); ++b) {
        auto node = [&](uint32_t parent, uint32_t level, uint32_t triangles, float x) {
            NodeInput in;
            in.parent = parent, in.level = level, in.block = b;
            in.bounds = {{x, 0, 0}, {x + 1, 1, 0}};
            in.staticBenefit = 1, in.geometricError = level == 0 ? 0.5f : 0.0f;
            in.blobs.push_back(encodeGeometry(strip(triangles, x), DracoOptions{}));
            return w.addNode(std::move(in));
        };
        const uint32_t root = node(kNone, 0, hlod0[b], 4.0f * b);
        for (uint32_t k = 0; k < 4; ++k) node(root, 1, 600, 4.0f * b + k / 4.0f);
    }
    w.finish();
}

}  // namespace

// hlod0's target is c_desiredTris (900): 1,100 triangles are within 1.25 x, 2,000 are not, and
// the level is flagged in the text and the JSON, with its triangles per node against the
// target; leaves keep originals and have no target.
TEST(Stats, FlagsALevelThatMissesItsTarget) {
    const fs::path dir = fs::temp_directory_path() / ("hlod_test_stats_miss_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string ok = (dir / "ok.hlod").string(), missed = (dir / "missed.hlod").string();
    writeTree(ok, {1000, 1100});
    writeTree(missed, {1000, 2000});
    stats::Stats s = stats::computeStats(Database::open(ok), false);
    ASSERT_EQ(s.checks.size(), 2u);
    EXPECT_EQ(s.checks[0].maxTriangles, 1100u);
    EXPECT_EQ(s.checks[0].missing, 0u);
    EXPECT_EQ(s.checks[1].simplifiedNodes, 0u);
    EXPECT_DOUBLE_EQ(s.checks[0].maxError, 0.5);
    s = stats::computeStats(Database::open(missed), false);
    EXPECT_EQ(s.checks[0].missing, 1u);
    EXPECT_NEAR(s.checks[0].worstRatio, 2000.0 / 900, 1e-9);
    RunResult text = runHlod({"stats", missed});
    EXPECT_NE(text.out.find("mean 1500, max 2000"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("level 0 MISSES its target: 1 of 2"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("1500 tris/node vs target 900 (1.67 x)"), std::string::npos) << text.out;
    const std::string okText = runHlod({"stats", ok}).out;
    EXPECT_EQ(okText.find("MISS"), std::string::npos);
    EXPECT_NE(okText.find("level 0: 1050 tris/node vs target 900 (1.17 x), ok"), std::string::npos) << okText;
    const nlohmann::json j = nlohmann::json::parse(runHlod({"stats", missed, "--json"}).out);
    EXPECT_TRUE(j["levels"][0]["misses_target"].get<bool>());
    EXPECT_FALSE(j["levels"][1]["misses_target"].get<bool>());
    EXPECT_EQ(j["hlod0_triangles_per_node"]["max"].get<uint64_t>(), 2000u);
    fs::remove_all(dir);
}

// A recorded c_desiredTris or c_levelFactor no build writes is invalid data (status 1, one line), as
// `hlod validate` says: stats printed 300-digit and negative targets from it until stop 49.
TEST(Stats, RecordedConstantsOutsideTheBuildsRangesAreInvalidData) {
    const fs::path dir = fs::temp_directory_path() / ("hlod_test_stats_meta_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string path = (dir / "m.hlod").string();
    for (const auto& [name, value, problem] : std::vector<std::array<std::string, 3>>{
             {"c_desiredTris", "1e300", "c_desiredTris = 1e+300: must be in [1, 4294967295] (triangles per node)"},
             {"c_levelFactor", "-1", "c_levelFactor = -1: must be a whole number in [2, 64] (children per node)"},
             {"c_desiredTris", "nan", "constant c_desiredTris: 'nan' is not a finite number"}}) {
        writeTree(path, {1000}, {{name, value}});
        const RunResult r = runHlod({"stats", path});
        EXPECT_EQ(r.exitCode, 1) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod stats: " + path + ": metadata " + problem + "\n");
        const RunResult v = runHlod({"validate", path});
        EXPECT_EQ(v.exitCode, 1) << v.outAndErr();
        EXPECT_NE(v.outAndErr().find("metadata " + problem), std::string::npos) << v.outAndErr();
    }
    fs::remove_all(dir);
}

// `hlod stats --thesis`: both readings of §3.2 beside 114 / 2,296 / 5 (pipeline/TREE.md).
TEST(Stats, ThesisArithmeticOfBothLeafRules) {
    const stats::TreeArithmetic a = stats::thesisArithmetic(Constants{});  // Table 6.1: 900, 4
    EXPECT_NEAR(a.meanBlockTriangles, 8'950'000.0 / 114, 1e-6);
    EXPECT_EQ(a.belowOne.levels, 5u);
    EXPECT_EQ(a.belowOne.nodes, 341u);
    EXPECT_EQ(a.stopBefore.levels, 4u);
    EXPECT_EQ(a.stopBefore.nodes, 85u);
    Fixture f("arithmetic");
    RunResult r = runHlod({"stats", f.db.string(), "--thesis"});
    EXPECT_NE(r.out.find("341 nodes per block, x 114 = 38874 nodes"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("85 nodes per block, x 114 = 9690 nodes"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("so 114 of them have 2 (mod 4) in all; the thesis's 2296 is 0 (mod 4)"), std::string::npos) << r.out;
}
