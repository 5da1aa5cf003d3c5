// `hlod inspect` and `hlod validate` run as the built binary: outputs, JSON that parses,
// exit codes, and one-line error messages naming the file.
#include "helpers.h"

#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace hlod::test {
namespace {

struct Cli : ::testing::Test {
    TempDir dir;
    std::string db = dir.file("s.hlod");
    void SetUp() override {
        SyntheticOptions o;
        o.levels = 2;
        writeSyntheticDatabase(db, o);
    }
};

TEST_F(Cli, InspectSummary) {
    RunResult r = runHlod({"inspect", db});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("nodes 20, blobs 40, blocks 4, levels 2, depth 2"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("c_levelFactor=4"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("tool: hlod writeSyntheticDatabase"), std::string::npos) << r.out;
}

TEST_F(Cli, InspectJsonViews) {
    RunResult r = runHlod({"inspect", "--json", db});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["nodes"], 20);
    EXPECT_EQ(j["per_level"].size(), 2u);
    EXPECT_EQ(j["per_level"][1]["nodes"], 16);
    EXPECT_EQ(j["constants"]["c_levelFactor"], "4");

    r = runHlod({"inspect", "--tree", "--depth", "1", "--json", db});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.size(), 4u);
    EXPECT_FALSE(j[0].contains("children")) << j[0];  // cut by --depth: not a leaf
    EXPECT_EQ(j[0]["children_not_shown"], 4);
    r = runHlod({"inspect", "--tree", "--depth", "2", "--json", db});
    j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j[0]["children"].size(), 4u);
    EXPECT_TRUE(j[0]["children"][0]["children"].empty()) << j[0];  // a leaf at the cut is still a leaf
    EXPECT_FALSE(j[0]["children"][0].contains("children_not_shown"));
    r = runHlod({"inspect", "--tree", "--json", db});
    EXPECT_EQ(nlohmann::json::parse(r.out)[0]["children"].size(), 4u);

    r = runHlod({"inspect", "--node", "1", "--json", db});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["id"], 1);
    EXPECT_EQ(j["parent"], 0);
    EXPECT_EQ(j["level"], 1);
    EXPECT_EQ(j["blobs"].size(), 2u);
    EXPECT_EQ(j["blobs"][1]["texture"], 2);
}

TEST_F(Cli, InspectTextTreeAndNode) {
    RunResult r = runHlod({"inspect", "--tree", db});
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_NE(r.out.find("  node 1  level 1  block 0"), std::string::npos) << r.out;
    r = runHlod({"inspect", "--node", "3", db});
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_NE(r.out.find("static_benefit"), std::string::npos) << r.out;
    r = runHlod({"inspect", "--node", "999", db});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod inspect: " + db + ": node 999 does not exist (the database has 20 nodes)\n");
    r = runHlod({"inspect", "--tree", "--depth", "1", db});
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_NE(r.out.find("  (4 children not shown)"), std::string::npos) << r.out;
}

TEST_F(Cli, ValidateExitCodes) {
    RunResult r = runHlod({"validate", db});
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("valid (20 nodes, 40 blobs, all blobs decoded)"), std::string::npos) << r.out;

    std::vector<uint8_t> file = readFile(db);
    patchRecord(file, layout::kTagNode, 1, kNodeCost, 5.0f);
    patchRecord(file, layout::kTagNode, 2, kNodeLevel, uint32_t(4));
    writeFile(db, file);
    r = runHlod({"validate", "--quick", db});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.out.find(db + ": node 1: cost 5 differs from eq. 3.1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(db + ": node 2: level 4 is not parent level 0 + 1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("2 violation(s)"), std::string::npos) << r.out;
    r = runHlod({"validate", "--json", db});
    EXPECT_EQ(r.exitCode, 1);
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["valid"].get<bool>());
    EXPECT_EQ(j["violations"].size(), 2u);
}

TEST_F(Cli, BadFilesGiveOneLineAndNonZeroExit) {
    const std::string empty = dir.file("empty.hlod");
    writeFile(empty, {});
    std::vector<uint8_t> file = readFile(db);
    file[20] ^= 1;
    const std::string flipped = dir.file("flipped.hlod");
    writeFile(flipped, file);
    for (const std::string cmd : {"validate", "inspect"}) {
        for (const auto& [path, text] : std::vector<std::pair<std::string, std::string>>{
                 {dir.file("missing.hlod"), "no such file"},
                 {dir.path.string(), "is a directory"},
                 {empty, "empty file"},
                 {flipped, "header checksum mismatch"}}) {
            RunResult r = runHlod({cmd, path});
            EXPECT_EQ(r.exitCode, 2) << cmd << " " << path;
            EXPECT_EQ(r.err, "hlod " + cmd + ": " + path + ": " + r.err.substr(cmd.size() + path.size() + 9));
            EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
            EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        }
    }
}

// A node tree with a cycle (node 1's first child is the root; before stop 36 `stats` and `play`
// hung and `export` crashed on one) is refused by every open with one line, exit 2; `validate`
// still lists it as a violation, exit 1.
TEST_F(Cli, ATreeWithACycleIsRefusedAtOpenAndListedByValidate) {
    std::vector<uint8_t> file = readFile(db);
    patchRecord(file, layout::kTagNode, 1, kNodeFirstChild, uint32_t(0));
    writeFile(db, file);
    const std::string line = db + ": node 0: is reached twice through the child/sibling links (a cycle or a shared node)";
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"inspect", db}, {"stats", db}, {"export", "tiles", db, "-o", dir.file("t")}, {"path", db, "-o", dir.file("p")}}) {
        RunResult r = runHlod(args);
        EXPECT_EQ(r.exitCode, 2) << args[0] << r.err;
        const std::string command = args[0] == "export" ? "export tiles" : args[0];
        EXPECT_EQ(r.err, "hlod " + command + ": " + line + " (`hlod validate` lists every violation)\n") << args[0];
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("t")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("p")));
    RunResult r = runHlod({"validate", "--quick", db});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.out.find(line), std::string::npos) << r.out;
}

// `hlod path` plans from the hlod0 bounds: a NaN there wrote a path of -inf extents with status 0
// before stop 36; now one line naming the database and node, status 1, no path written.
TEST_F(Cli, PathRefusesHlod0BoundsThatAreNotFinite) {
    std::vector<uint8_t> file = readFile(db);
    patchRecord(file, layout::kTagNode, 0, kNodeBoundsMinX, std::nanf(""));
    writeFile(db, file);
    const RunResult r = runHlod({"path", db, "-o", dir.file("p")});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.err, "hlod path: " + db + ": node 0: bounding box is not finite or has min > max (`hlod validate` lists every violation)\n");
    EXPECT_FALSE(std::filesystem::exists(dir.file("p")));
}

}  // namespace
}  // namespace hlod::test
