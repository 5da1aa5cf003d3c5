// Version compatibility (FORMAT.md §Versions): a newer minor version with bigger records and
// an unknown section is read; an unknown major version and shrunken records are refused.
#include "helpers.h"

#include "tests/support/synthetic.h"

namespace hlod::test {
namespace {

using namespace layout;

// Rebuilds the skeleton of `file` with `extra` bytes appended to every record of the
// known sections and, optionally, an unknown section; sets the minor version; fixes checksums.
std::vector<uint8_t> rewriteSkeleton(const std::vector<uint8_t>& file, int extra, bool unknownSection, uint16_t minor) {
    const uint64_t skOff = load<uint64_t>(file, kOffSkeletonOffset);
    std::span<const uint8_t> skel(file.data() + skOff, file.size() - skOff);
    const uint32_t count = load<uint32_t>(skel, 0), entrySize = load<uint32_t>(skel, 4);
    struct Sec {
        uint32_t tag, recordSize;
        uint64_t count;
        std::vector<uint8_t> bytes;
    };
    std::vector<Sec> secs;
    if (unknownSection) secs.push_back({tag("XTRA"), 4, 3, std::vector<uint8_t>(12, 0xAB)});
    for (uint32_t i = 0; i < count; ++i) {
        const size_t e = 8 + size_t(i) * entrySize;
        Sec s{load<uint32_t>(skel, e), load<uint32_t>(skel, e + 4), load<uint64_t>(skel, e + 24), {}};
        const uint64_t off = load<uint64_t>(skel, e + 8), size = load<uint64_t>(skel, e + 16);
        if (s.recordSize == 0) {
            s.bytes.assign(skel.begin() + off, skel.begin() + off + size);
        } else {
            for (uint64_t r = 0; r < s.count; ++r) {
                auto rec = skel.subspan(off + r * s.recordSize, s.recordSize);
                s.bytes.insert(s.bytes.end(), rec.begin(), rec.end());
                for (int k = 0; k < extra; ++k) s.bytes.push_back(uint8_t(0xC0 + k));
            }
            s.recordSize += extra;
        }
        secs.push_back(std::move(s));
    }
    std::vector<uint8_t> out(file.begin(), file.begin() + skOff);
    ByteWriter w{out};
    const uint32_t bigEntry = kSectionEntrySize + 8;  // newer entries may grow too
    w.put(uint32_t(secs.size()));
    w.put(bigEntry);
    uint64_t offset = 8 + secs.size() * bigEntry;
    for (const Sec& s : secs) {
        w.put(s.tag);
        w.put(s.recordSize);
        w.put(offset);
        w.put(uint64_t(s.bytes.size()));
        w.put(s.count);
        w.put(uint64_t(0x1122334455667788));
        offset += s.bytes.size();
    }
    for (const Sec& s : secs) w.bytes(s.bytes);
    std::span<uint8_t> all(out);
    store(all, kOffMinor, minor);
    store(all, kOffSkeletonSize, uint64_t(out.size() - skOff));
    store(all, kOffFileSize, uint64_t(out.size()));
    fixChecksums(all);
    return out;
}

struct Compat : ::testing::Test {
    TempDir dir;
    std::string path = dir.file("db.hlod");
    void SetUp() override {
        SyntheticOptions o;
        o.blocksX = 1;
        o.levels = 2;
        o.trianglesPerNode = 8;
        o.textureSize = 8;
        writeSyntheticDatabase(path, o);
    }
};

TEST_F(Compat, NewerMinorWithBiggerRecordsAndUnknownSectionIsRead) {
    Database original = Database::open(path);
    std::vector<uint8_t> file = readFile(path);
    const std::string newer = dir.file("newer.hlod");
    writeFile(newer, rewriteSkeleton(file, 8, true, kFormatMinor + 3));
    Database db = Database::open(newer);
    EXPECT_EQ(db.skeleton().minor, kFormatMinor + 3);
    const Skeleton &a = original.skeleton(), &b = db.skeleton();
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    ASSERT_EQ(a.blobs.size(), b.blobs.size());
    EXPECT_EQ(0, std::memcmp(encodeSkeleton(a).data() + 8 + 4 * kSectionEntrySize,
                             encodeSkeleton(b).data() + 8 + 4 * kSectionEntrySize,
                             encodeSkeleton(a).size() - 8 - 4 * kSectionEntrySize));
    EXPECT_EQ(a.meta, b.meta);
    for (uint32_t i = 0; i < b.blobs.size(); ++i) EXPECT_EQ(db.readBlob(i), original.readBlob(i));
}

TEST_F(Compat, UnknownMajorIsRefusedWithAClearMessage) {
    std::vector<uint8_t> file = readFile(path);
    store(std::span(file), kOffMajor, uint16_t(2));
    store(std::span(file), kOffMinor, uint16_t(3));
    fixChecksums(file);
    writeFile(path, file);
    try {
        Database::open(path);
        FAIL() << "opened a 2.3 file";
    } catch (const FormatError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": format version 2.3 is not supported by this hlod (reads 1.x)");
    }
}

TEST_F(Compat, SmallerRecordSizeIsAnError) {
    std::vector<uint8_t> file = readFile(path);
    std::vector<uint8_t> smaller = rewriteSkeleton(file, 0, false, kFormatMinor);
    // Shrink the NODE record size in its section entry (entries are 40 bytes after rewrite).
    const uint64_t skOff = load<uint64_t>(smaller, kOffSkeletonOffset);
    for (uint32_t i = 0; i < 4; ++i) {
        const size_t e = skOff + 8 + size_t(i) * (kSectionEntrySize + 8);
        if (load<uint32_t>(smaller, e) == kTagNode) store(std::span(smaller), e + 4, kNodeRecordSize - 8);
    }
    fixChecksums(smaller);
    writeFile(path, smaller);
    try {
        Database::open(path);
        FAIL() << "opened a file with shrunken NODE records";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("NODE record size 112 is smaller than 120"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace hlod::test
