// BlobSpill (pipeline/blob_spill.h): a bottom-up block's finished nodes park their encoded blobs in
// an unnamed temporary file until the block is emitted breadth-first: the parked bytes leave memory
// and come back byte for byte, from any number of threads at once; the file leaves no name behind.
#include "pipeline/blob_spill.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <random>
#include <thread>

namespace hlod::test {
namespace {

std::vector<EncodedBlob> randomBlobs(std::mt19937& rng, const std::vector<size_t>& sizes) {
    std::vector<EncodedBlob> blobs;
    for (size_t size : sizes) {
        EncodedBlob b;
        b.textureSlot = static_cast<uint32_t>(blobs.size());
        for (size_t i = 0; i < size; ++i) b.bytes.push_back(static_cast<uint8_t>(rng()));
        blobs.push_back(std::move(b));
    }
    return blobs;
}

TEST(BlobSpill, ParkedBlobsLeaveMemoryAndComeBackByteForByte) {
    const TempDir dir;
    BlobSpill spill(dir.path.string());
    std::mt19937 rng(7);
    std::vector<std::vector<EncodedBlob>> originals, records;
    std::vector<std::vector<std::pair<uint64_t, uint64_t>>> parked(3);
    for (const std::vector<size_t>& sizes : std::vector<std::vector<size_t>>{{0, 1, 70'000}, {}, {3'000'000, 5}}) {
        originals.push_back(randomBlobs(rng, sizes));
        records.push_back(originals.back());
    }
    for (size_t r = 0; r < records.size(); ++r) {
        spill.park(records[r], parked[r]);
        for (const EncodedBlob& b : records[r]) EXPECT_EQ(b.bytes.capacity(), 0u) << "record " << r << ": still in memory";
    }
    for (const size_t r : {size_t{2}, size_t{0}, size_t{1}}) {  // any order, as breadth-first emission reads them
        spill.restore(records[r], parked[r]);
        ASSERT_EQ(records[r].size(), originals[r].size());
        for (size_t b = 0; b < records[r].size(); ++b) {
            EXPECT_TRUE(records[r][b].bytes == originals[r][b].bytes) << "record " << r << " blob " << b;
            EXPECT_EQ(records[r][b].textureSlot, originals[r][b].textureSlot);
        }
    }
    for (const auto& entry : std::filesystem::directory_iterator(dir.path))
        ADD_FAILURE() << "the spill left a name behind: " << entry.path();
}

TEST(BlobSpill, ThreadsParkingAtOnceGetTheirOwnBytesBack) {
    const TempDir dir;
    BlobSpill spill(dir.path.string());
    constexpr int kThreads = 6, kRecords = 40;
    std::vector<std::vector<std::vector<EncodedBlob>>> originals(kThreads), records(kThreads);
    std::vector<std::vector<std::vector<std::pair<uint64_t, uint64_t>>>> parked(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            std::mt19937 rng(100 + t);
            for (int r = 0; r < kRecords; ++r) {
                originals[t].push_back(randomBlobs(rng, {rng() % 20'000, rng() % 300}));
                records[t].push_back(originals[t].back());
                parked[t].emplace_back();
                spill.park(records[t].back(), parked[t].back());
            }
        });
    for (std::thread& t : threads) t.join();
    for (int t = 0; t < kThreads; ++t)
        for (int r = 0; r < kRecords; ++r) {
            spill.restore(records[t][r], parked[t][r]);
            for (size_t b = 0; b < 2; ++b)
                ASSERT_TRUE(records[t][r][b].bytes == originals[t][r][b].bytes) << "thread " << t << " record " << r << " blob " << b;
        }
}

TEST(BlobSpill, AFolderThatCannotHoldItIsAnErrorNamingIt) {
    const TempDir dir;
    const std::string missing = (dir.path / "no-such-folder").string();
    try {
        BlobSpill spill(missing);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

// A write the file system refuses (here the process's file-size limit, as a full disk would):
// one line naming the folder and the option that moves it.
TEST(BlobSpill, AFailedWriteIsAnErrorNamingTheFolder) {
    const TempDir dir;
    BlobSpill spill(dir.path.string());
    std::mt19937 rng(3);
    std::vector<EncodedBlob> blobs = randomBlobs(rng, {4096});
    std::vector<std::pair<uint64_t, uint64_t>> parked;
    rlimit old{};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
    const auto oldSignal = std::signal(SIGXFSZ, SIG_IGN);  // a write past the limit then fails with EFBIG
    rlimit small = old;
    small.rlim_cur = 1024;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string what;
    try {
        spill.park(blobs, parked);
    } catch (const std::runtime_error& e) {
        what = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldSignal);
    EXPECT_EQ(what.rfind(dir.path.string() + ": ", 0), 0u) << what;
    EXPECT_NE(what.find("write failed"), std::string::npos) << what;
    EXPECT_NE(what.find("--temp-dir"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

}  // namespace
}  // namespace hlod::test
