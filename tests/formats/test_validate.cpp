// The validator (FORMAT.md §Invariants): each invariant violated on purpose is reported,
// through the Writer (which accepts arbitrary levels, bounds, costs and errors) or by patching
// skeleton bytes with the checksums fixed.
#include "helpers.h"

#include "formats/validate.h"

#include <cmath>
#include <functional>

namespace hlod::test {
namespace {

NodeInput node(uint32_t parent, uint32_t level, Box3f bounds, float error) {
    NodeInput in;
    in.parent = parent;
    in.level = level;
    in.bounds = bounds;
    in.geometricError = error;
    in.blobs.push_back(encodeTexture(gradientImage(8, 8, 3), Codec::Jpeg));
    in.blobs.push_back(encodeGeometry(gridMesh(2), {}));
    in.blobs.back().textureSlot = 0;
    return in;
}

struct Validate : ::testing::Test {
    TempDir dir;
    std::string path = dir.file("v.hlod");

    // Root + two children; `tweak` edits the inputs before writing.
    void write(const std::function<void(std::vector<NodeInput>&)>& tweak) {
        std::vector<NodeInput> in = {node(kNone, 0, {{0, 0, 0}, {2, 2, 1}}, 0.5f),
                                     node(0, 1, {{0, 0, 0}, {1, 2, 1}}, 0.25f),
                                     node(0, 1, {{1, 0, 0}, {2, 2, 1}}, 0.25f)};
        tweak(in);
        Writer w(path);
        for (NodeInput& n : in) w.addNode(std::move(n));
        w.finish();
    }
    std::vector<Violation> run(bool quick = false) {
        ValidateOptions o;
        o.quick = quick;
        return validate(Database::open(path, false), o);
    }
    // Expects a violation whose message contains `text`.
    void expectViolation(const std::string& text, bool quick = false) {
        std::vector<Violation> v = run(quick);
        std::string all;
        for (const Violation& x : v) all += x.message + "\n";
        EXPECT_NE(all.find(text), std::string::npos) << "wanted '" << text << "', got:\n" << all;
    }
    void patch(const std::function<void(std::vector<uint8_t>&)>& edit) {
        std::vector<uint8_t> file = readFile(path);
        edit(file);
        writeFile(path, file);
    }
};

TEST_F(Validate, CleanDatabaseHasNoViolation) {
    write([](auto&) {});
    EXPECT_TRUE(run().empty());
    EXPECT_TRUE(run(true).empty());
}

TEST_F(Validate, LevelNotParentPlusOne) {
    write([](auto& in) { in[2].level = 3; });
    expectViolation("node 2: level 3 is not parent level 0 + 1");
}

TEST_F(Validate, RootWithNonZeroLevel) {
    write([](auto& in) { in[0].level = 1, in[1].level = in[2].level = 2; });
    expectViolation("node 0: has no parent but level 1");
}

TEST_F(Validate, ChildBoundsOutsideParent) {
    write([](auto& in) { in[1].bounds.max.z = 1.01f; });
    expectViolation("node 1: bounding box is not inside its parent's");
}

TEST_F(Validate, ChildBoundsWithinToleranceAccepted) {
    write([](auto& in) { in[1].bounds.max.z = 1 + 1e-5f; });  // < 1e-4 of the diagonal 3
    EXPECT_TRUE(run().empty());
}

TEST_F(Validate, NonFiniteBounds) {
    write([](auto& in) { in[1].bounds.min.x = std::nanf(""); });
    expectViolation("node 1: bounding box is not finite");
}

TEST_F(Validate, CostDisagreesWithEquation31) {
    write([](auto& in) { in[1].cost = 123; });
    expectViolation("node 1: cost 123 differs from eq. 3.1");
}

TEST_F(Validate, GeometricErrorIncreases) {
    write([](auto& in) { in[2].geometricError = 0.75f; });
    expectViolation("node 2: geometric error 0.750000 exceeds its parent's 0.500000");
}

TEST_F(Validate, TwoRootsInOneBlockAndMissingBlockRoot) {
    write([](auto& in) {
        in[2].parent = kNone;
        in[2].level = 0;
        in[1].block = 1;
    });
    expectViolation("node 2: is a second root of block 0");
    expectViolation("block 1 has no root node");
    expectViolation("node 1: block 1 differs from its parent's");
}

TEST_F(Validate, BlobCountsDisagreeWithDecodedData) {
    write([](auto& in) {
        in[1].blobs[1].info.triangles = 9;  // the record (and the node sums) claim 9, the mesh has 8
        in[2].blobs[0].info.width = 16;
        in[2].blobs[1].info.attributes = kAttrPosition;
    });
    expectViolation("node 2: blob 5 decodes to attribute mask 3, its record claims 1");
    expectViolation("node 1: blob 3 decodes to 8 triangles and 9 vertices, its record claims 9 and 9");
    expectViolation("node 2: blob 4 decodes to 8x8x3, its record claims 16x8x3");
    EXPECT_TRUE(run(true).empty());  // --quick does not decode
}

// FORMAT.md "Position lattice": a blob's positions take at most 23 bits (accepted before stop 38).
TEST_F(Validate, AbsurdPositionBitsInABlobRecord) {
    write([](auto& in) { in[1].blobs[1].info.positionBits = 255; });
    expectViolation("node 1: blob 3 claims 255-bit positions (at most 23)", true);
    expectViolation("node 1: blob 3 claims 255-bit positions (at most 23)");
}

TEST_F(Validate, NodeCountsDisagreeWithBlobs) {
    write([](auto&) {});
    patch([](auto& f) { patchRecord(f, layout::kTagNode, 1, kNodeTextured, uint32_t(99)); });
    expectViolation("node 1: triangle/vertex/texel counts differ", true);
}

TEST_F(Validate, CorruptBlobBytes) {
    write([](auto&) {});
    Database db = Database::open(path);
    const uint64_t at = db.skeleton().blobs[5].offset + 3;
    patch([&](auto& f) { f[at] ^= 0x10; });
    expectViolation("node 2: blob 5 (node 2) checksum mismatch (corrupt data)");
    EXPECT_TRUE(run(true).empty());
}

TEST_F(Validate, UndecodableBlobWithCorrectChecksum) {
    write([](auto&) {});
    Database db = Database::open(path);
    const BlobRef b = db.skeleton().blobs[1];
    patch([&](auto& f) {
        for (uint64_t i = 0; i < b.size; ++i) f[b.offset + i] = 0x5A;
        patchRecord(f, layout::kTagBlob, 1, 48, layout::checksum(std::span(f).subspan(b.offset, b.size)));
    });
    expectViolation("node 0: blob 1: bad Draco geometry");
}

TEST_F(Validate, CycleInChildList) {
    write([](auto&) {});
    patch([](auto& f) { patchRecord(f, layout::kTagNode, 2, kNodeNextSibling, uint32_t(1)); });
    expectViolation("node 1: is reached twice through the child/sibling links (a cycle or a shared node)");
}

TEST_F(Validate, ChildListedUnderWrongParentAndUnreachable) {
    write([](auto&) {});
    patch([](auto& f) { patchRecord(f, layout::kTagNode, 1, kNodeNextSibling, uint32_t(kNone)); });
    expectViolation("node 2: is not reachable");
    patch([](auto& f) { patchRecord(f, layout::kTagNode, 2, kNodeParent, uint32_t(1)); });
    expectViolation("node 2: level 1 is not parent level 1 + 1");
}

TEST_F(Validate, BytesBelongingToNoBlob) {
    write([](auto&) {});
    patch([](auto& f) {
        const uint64_t size = layout::load<uint64_t>(f, recordOffset(f, layout::kTagBlob, 5) + kBlobSize);
        patchRecord(f, layout::kTagBlob, 5, kBlobSize, size - 1);
    });
    expectViolation("belong to no blob", true);
    expectViolation("node 2: data size does not equal the sum of its blob sizes", true);
}

TEST_F(Validate, CTexturedFromMetadata) {
    Writer w(path, 0.5);
    w.setMeta("c_textured", "0.5");
    w.addNode(node(kNone, 0, {{0, 0, 0}, {1, 1, 1}}, 0));
    w.finish();
    EXPECT_TRUE(run().empty());
    ValidateOptions o;
    o.cTextured = 0.127;
    EXPECT_FALSE(validate(Database::open(path), o).empty());
}

// A META c_textured every player refuses is a violation ("valid" until stop 45).
TEST_F(Validate, CTexturedOutOfRangeInMetadata) {
    for (const char* value : {"-1", "0", "5"}) {
        Writer w(path, 0.5);
        w.setMeta("c_textured", value);
        w.addNode(node(kNone, 0, {{0, 0, 0}, {1, 1, 1}}, 0));
        w.finish();
        expectViolation(std::string("metadata c_textured='") + value + "' is not in (0, 1]");
    }
}

// META keys the readers interpret: a value they refuse is a violation; a well-formed one is not.
TEST_F(Validate, UpAndOffsetMetadata) {
    for (const auto& [key, value, violation] : std::vector<std::array<std::string, 3>>{
             {"up", "y", ""},
             {"up", "x", "META up 'x' is neither y nor z"},
             {"offset", "512360,4123471.5,-250", ""},
             {"offset", "1,2", "META offset '1,2': expected X,Y,Z (three numbers within +-1e15)"},
             {"offset", "1,nan,2", "META offset '1,nan,2': expected X,Y,Z (three numbers within +-1e15)"},
             // Bytes a terminal must not get raw: a NUL cut the line, 0xFF reached it (until stop 49).
             {"up", std::string("\xFF\xFE\0x\x01", 5), "META up '\\xFF\\xFE\\x00x\\x01' is neither y nor z"},
             {"up", "\u00e9", "META up '\u00e9' is neither y nor z"},  // UTF-8 as it is
             // The build constants `hlod stats` reads, checked as a build checks them ("valid" until stop 49).
             {"c_desiredTris", "600", ""},
             {"c_desiredTris", "1e300", "metadata c_desiredTris = 1e+300: must be in [1, 4294967295] (triangles per node)"},
             {"c_desiredTris", "nan", "metadata constant c_desiredTris: 'nan' is not a finite number"},
             {"c_levelFactor", "-1", "metadata c_levelFactor = -1: must be a whole number in [2, 64] (children per node)"}}) {
        {
            Writer w(path, 0.127);
            w.setMeta(key, value);
            w.addNode(node(kNone, 0, {{0, 0, 0}, {1, 1, 1}}, 0));
            w.finish();
        }
        const std::vector<Violation> found = run();
        if (violation.empty()) {
            EXPECT_TRUE(found.empty()) << key << "=" << value;
            continue;
        }
        ASSERT_EQ(found.size(), 1u) << key << "=" << value;
        EXPECT_EQ(found[0].message, violation);
    }
}

}  // namespace
}  // namespace hlod::test
