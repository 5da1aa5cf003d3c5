// `hlod build` / `hlod merge` as a user runs them: exit codes, the one-line error, the summary,
// the <db>.build.json sidecar, and a database `hlod validate` accepts.
#include "helpers.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>

namespace hlod::test {
namespace {

struct CliResult {
    int status = -1;
    std::string out;
};

CliResult run(const std::string& args) {
    CliResult r;
    const std::string command = std::string(PIPELINE_CLI) + " " + args + " 2>&1";
    FILE* p = popen(command.c_str(), "r");
    std::array<char, 4096> buffer{};
    while (size_t n = fread(buffer.data(), 1, buffer.size(), p)) r.out.append(buffer.data(), n);
    const int raw = pclose(p);
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return r;
}

TEST(Cli, BuildPrintsConstantsSummaryAndWritesSidecar) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(50).mesh, true);
    const CliResult r = run("build " + dir.file("t.ply") + " -o " + dir.file("t.hlod") + " -j 2 --set c_desiredTris=500");
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("c_desiredTris=500"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("nodes per level: hlod0=1 hlod1=4"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("B/input triangle"), std::string::npos) << r.out;
    std::ifstream sidecar(dir.file("t.hlod.build.json"));
    const nlohmann::json j = nlohmann::json::parse(sidecar);
    EXPECT_EQ(j.at("input_triangles"), 5000);
    EXPECT_GT(j.at("peak_rss_bytes").get<uint64_t>(), 0u);
    EXPECT_EQ(j.at("output_bytes").get<uint64_t>(), std::filesystem::file_size(dir.file("t.hlod")));
    EXPECT_GE(j.at("stages").size(), 3u);
    const CliResult v = run("validate " + dir.file("t.hlod"));
    EXPECT_EQ(v.status, 0) << v.out;
}

TEST(Cli, BadInputIsOneLineAndNonZero) {
    TempDir dir;
    std::ofstream(dir.file("bad.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\n";
    const CliResult r = run("build " + dir.file("bad.ply") + " -o " + dir.file("bad.hlod"));
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.out.find("hlod build: " + dir.file("bad.ply") + ": truncated PLY header"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hlod")));
    const CliResult m = run("build /nonexistent.obj -o " + dir.file("x.hlod"));
    EXPECT_EQ(m.status, 2);
    EXPECT_NE(m.out.find("/nonexistent.obj: no such file"), std::string::npos) << m.out;
}

TEST(Cli, ShardsAndMerge) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(40).mesh, true);
    const std::string common = " --block-triangles 800 --set c_desiredTris=300";
    ASSERT_EQ(run("build " + dir.file("t.ply") + " -o " + dir.file("one.hlod") + common).status, 0);
    ASSERT_EQ(run("build " + dir.file("t.ply") + " -o " + dir.file("s1") + " --shard --blocks 0:2" + common).status, 0);
    ASSERT_EQ(run("build " + dir.file("t.ply") + " -o " + dir.file("s2") + " --shard --blocks 2:99 -j 1" + common).status, 0);
    const CliResult m = run("merge " + dir.file("s1") + " " + dir.file("s2") + " -o " + dir.file("merged.hlod"));
    ASSERT_EQ(m.status, 0) << m.out;
    EXPECT_EQ(readBytes(dir.file("one.hlod")), readBytes(dir.file("merged.hlod")));
    const CliResult bad = run("merge " + dir.file("s1") + " -o " + dir.file("half.hlod"));
    EXPECT_EQ(bad.status, 1);
    EXPECT_NE(bad.out.find("is in none of the shards"), std::string::npos) << bad.out;
}

}  // namespace
}  // namespace hlod::test
