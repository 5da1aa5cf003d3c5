// Makefile.datasets and samples/: the verify targets accept good data and detect a corrupted
// file, copies of the shared real scans verify, an unreachable download fails with a clear
// message, and the committed sample city is exactly what the generator writes from its manifest.
#include "pipeline/synth/synth.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

const fs::path kSource = HLOD_SOURCE_DIR;
const fs::path kShared = fs::path(HLOD_SHARED_DIR) / "datasets";

struct CmdResult {
    int status;
    std::string output;
};

// Runs make on Makefile.datasets from the source root with DATASETS in a temporary directory.
CmdResult make(const fs::path& datasets, const std::string& args) {
    std::string cmd = "cd " + kSource.string() + " && make -f Makefile.datasets HLOD=" + HLOD_BINARY +
                      " DATASETS=" + datasets.string() + " SHARED=" + kShared.string() + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    int status = pclose(p);
    return {WEXITSTATUS(status), out};
}

fs::path tempDir(const std::string& name) {
    fs::path p = fs::temp_directory_path() / ("hlod_test_datasets_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    return p;
}

void flipByte(const fs::path& file, uint64_t offset) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(std::streamoff(offset));
    char c;
    f.get(c);
    f.seekp(std::streamoff(offset));
    f.put(char(c ^ 0x20));
}

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST(Datasets, GeneratedCityVerifiesAndACorruptedFileIsDetected) {
    fs::path d = tempDir("city");
    CmdResult gen = make(d, "city-small");
    ASSERT_EQ(gen.status, 0) << gen.output;
    EXPECT_NE(gen.output.find("city-small: sha256 OK"), std::string::npos) << gen.output;
    CmdResult again = make(d, "city-small");  // already there: verified, not regenerated
    EXPECT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("already verified"), std::string::npos) << again.output;
    flipByte(d / "city-small" / "block_003.obj", 200);
    CmdResult bad = make(d, "verify-city-small");
    EXPECT_NE(bad.status, 0) << bad.output;
    EXPECT_NE(bad.output.find("block_003.obj"), std::string::npos) << bad.output;
    EXPECT_NE(bad.output.find("checksum mismatch"), std::string::npos) << bad.output;
    fs::remove_all(d);
}

TEST(Datasets, SharedScanCopiesVerifyAndCorruptionIsDetected) {
    if (!fs::exists(kShared / "SHA256SUMS")) GTEST_SKIP() << "no " << kShared;
    fs::path d = tempDir("scan");
    CmdResult copy = make(d, "bunny");
    ASSERT_EQ(copy.status, 0) << copy.output;
    EXPECT_NE(copy.output.find("bunny: sha256 OK"), std::string::npos) << copy.output;
    flipByte(d / "A1_stanford_bunny" / "bun_zipper.ply", 5000);
    CmdResult bad = make(d, "verify-scan-bunny");
    EXPECT_NE(bad.status, 0) << bad.output;
    EXPECT_NE(bad.output.find("bun_zipper.ply"), std::string::npos) << bad.output;
    fs::remove_all(d);
}

TEST(Datasets, CommittedShareScanChecksumsMatchTheSharedList) {
    if (!fs::exists(kShared / "SHA256SUMS")) GTEST_SKIP() << "no " << kShared;
    EXPECT_EQ(readAll(kSource / "samples/checksums/shared-scans.sha256"), readAll(kShared / "SHA256SUMS"));
}

TEST(Datasets, UnreachableDownloadFailsWithAClearMessage) {
    fs::path d = tempDir("download");
    CmdResult r = make(d, "download-stanford-bunny URL_stanford-bunny=http://127.0.0.1:9/bunny.tar.gz");
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("error: cannot download http://127.0.0.1:9/bunny.tar.gz"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "downloads" / "bunny.tar.gz.part"));
    fs::remove_all(d);
}

TEST(Datasets, SampleCityIsExactlyTheGeneratorsOutput) {
    fs::path sample = kSource / "samples/city";
    nlohmann::json m = nlohmann::json::parse(readAll(sample / "city.json"));
    hlod::synth::CityOptions o;
    o.scale = m["scale"];
    o.seed = m["seed"];
    o.jpegQuality = m["jpeg_quality"];
    o.cityBlocks = m["city_blocks"];
    fs::path d = tempDir("sample");
    hlod::synth::generateCity(o, d.string());
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(d)) {
        ++files;
        EXPECT_TRUE(readAll(e.path()) == readAll(sample / e.path().filename())) << e.path().filename() << " differs";
    }
    EXPECT_EQ(files, 3 * m["block_count"].get<size_t>() + 1);
    fs::remove_all(d);
}

// The thesis reproduction chain of Makefile.datasets, end to end on the small city: generate and
// verify, build, validate, stats (text and JSON), walk/drive/fly paths and replays, the plots
// (6.5 walk vs fly, 6.6 walk vs drive, in one folder).
TEST(Datasets, ThesisChainRunsEndToEndOnTheSmallCity) {
    fs::path d = tempDir("thesis"), out = d / "out";
    CmdResult r = make(d, "thesis CITY=small OUT=" + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("city-small: sha256 OK"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(": valid ("), std::string::npos) << r.output;
    for (const char* f : {"city.hlod", "stats.txt", "stats.json", "walk.csv", "drive.csv", "fly.csv", "walk.json",
                          "plots/fig6_1.png", "plots/fig6_6.png", "plots/hlod0_share.png"})
        EXPECT_GT(fs::exists(out / f) ? fs::file_size(out / f) : 0, 0u) << f;
    EXPECT_NE(readAll(out / "walk.csv").find("# memory_budget_bytes: 1073741824"), std::string::npos);  // PLAY_FLAGS
    EXPECT_GT(nlohmann::json::parse(readAll(out / "walk.json"))["frames"].get<int>(), 100);
    fs::remove_all(d);
}
