// Round trip of every node field, blob record and blob through Writer -> Database, with
// several textures per node, untextured sub-meshes, normals and colours; codecs; metrics;
// the synthetic database.
#include "helpers.h"

#include "formats/metrics.h"
#include "formats/validate.h"
#include "tests/support/synthetic.h"

#include <cmath>

namespace hlod::test {
namespace {

MeshData withNormalsAndColours(MeshData m) {
    for (size_t v = 0; v < m.vertexCount(); ++v) {
        m.normals.insert(m.normals.end(), {0, 0, 1});
        m.colors.insert(m.colors.end(), {uint8_t(v), uint8_t(2 * v), 200, 255});
    }
    return m;
}

// Node 0 (root): two textures (JPEG RGB, PNG RGBA), two textured sub-meshes, one untextured
// sub-mesh with normals and colours. Node 1 (child): one untextured sub-mesh.
NodeInput rootInput() {
    NodeInput in;
    in.bounds = {{-1, -2, -3}, {4, 5, 6}};
    in.staticBenefit = 12.5f;
    in.avgNormal = {0, 0.6f, 0.8f};
    in.geometricError = 0.25f;
    in.blobs.push_back(encodeTexture(gradientImage(32, 16, 3), Codec::Jpeg));
    in.blobs.push_back(encodeTexture(gradientImage(8, 8, 4), Codec::Png));
    in.blobs.push_back(encodeGeometry(gridMesh(4), DracoOptions{}));
    in.blobs.back().textureSlot = 0;
    in.blobs.push_back(encodeGeometry(gridMesh(3, 1), DracoOptions{}));
    in.blobs.back().textureSlot = 1;
    in.blobs.push_back(encodeGeometry(withNormalsAndColours(gridMesh(2, 2)), DracoOptions{}));
    return in;
}

TEST(RoundTrip, EveryFieldAndBlob) {
    TempDir dir;
    const std::string path = dir.file("a.hlod");
    NodeInput root = rootInput();
    std::vector<EncodedBlob> rootBlobs = root.blobs;
    NodeInput child;
    child.parent = 0;
    child.level = 1;
    child.bounds = {{0, 0, 0}, {1, 1, 1}};
    child.cost = 7.5f;
    child.geometricError = 0.125f;
    child.blobs.push_back(encodeGeometry(gridMesh(2), DracoOptions{}));
    {
        Writer w(path, 0.25);
        EXPECT_EQ(w.addNode(root), 0u);
        EXPECT_EQ(w.addNode(child), 1u);
        w.setMeta("tool", "test");
        w.setMeta("c_textured", "0.25");
        w.setMeta("tool", "test2");  // replaces
        w.finish();
    }
    Database db = Database::open(path);
    const Skeleton& s = db.skeleton();
    ASSERT_EQ(s.nodes.size(), 2u);
    ASSERT_EQ(s.blobs.size(), 6u);
    EXPECT_EQ(s.major, kFormatMajor);
    EXPECT_EQ(s.blockCount, 1u);
    ASSERT_EQ(s.meta.size(), 2u);
    EXPECT_EQ(*s.findMeta("tool"), "test2");
    EXPECT_EQ(s.findMeta("nope"), nullptr);

    const Node& n0 = s.nodes[0];
    EXPECT_EQ(n0.id, 0u);
    EXPECT_EQ(n0.parent, kNone);
    EXPECT_EQ(n0.firstChild, 1u);
    EXPECT_EQ(n0.nextSibling, kNone);
    EXPECT_EQ(n0.bounds.min.y, -2);
    EXPECT_EQ(n0.bounds.max.z, 6);
    EXPECT_EQ(n0.staticBenefit, 12.5f);
    EXPECT_EQ(n0.avgNormal.y, 0.6f);
    EXPECT_EQ(n0.geometricError, 0.25f);
    EXPECT_EQ(n0.texturedTriangles, 2u * 16 + 2 * 9);
    EXPECT_EQ(n0.untexturedTriangles, 2u * 4);
    EXPECT_EQ(n0.vertexCount, 25u + 16 + 9);
    EXPECT_EQ(n0.texelCount, 32u * 16 + 8 * 8);
    EXPECT_FLOAT_EQ(n0.cost, nodeCost(50, 8, 0.25));
    EXPECT_EQ(n0.firstBlob, 0u);
    EXPECT_EQ(n0.blobCount, 5u);
    EXPECT_EQ(n0.dataOffset, s.blobs[0].offset);
    EXPECT_EQ(n0.dataSize, s.blobs[4].offset + s.blobs[4].size - s.blobs[0].offset);

    const Node& n1 = s.nodes[1];
    EXPECT_EQ(n1.parent, 0u);
    EXPECT_EQ(n1.level, 1u);
    EXPECT_EQ(n1.cost, 7.5f);  // given explicitly
    EXPECT_EQ(n1.firstBlob, 5u);
    EXPECT_EQ(s.children(0), std::vector<uint32_t>{1});
    EXPECT_EQ(s.roots(), std::vector<uint32_t>{0});

    EXPECT_EQ(s.blobs[2].texture, 0u);
    EXPECT_EQ(s.blobs[3].texture, 1u);
    EXPECT_EQ(s.blobs[4].texture, kNone);
    EXPECT_EQ(s.blobs[4].attributes, kAttrPosition | kAttrTexcoord | kAttrNormal | kAttrColor);
    EXPECT_EQ(s.blobs[4].positionBits, 15);  // side 1: lattice step 2^-14 <= 1 / (2^14 - 1), 2^14 steps
    EXPECT_EQ(s.blobs[4].normalBits, 8);
    EXPECT_EQ(s.blobs[1].codec, Codec::Png);
    EXPECT_EQ(s.blobs[1].channels, 4);
    for (uint32_t i = 0; i < 5; ++i) {
        EXPECT_EQ(db.readBlob(i), rootBlobs[i].bytes) << "blob " << i;
        EXPECT_EQ(s.blobs[i].node, 0u);
    }

    MeshData m = decodeGeometry(db.readBlob(4), "blob 4");
    ASSERT_EQ(m.vertexCount(), 9u);
    EXPECT_EQ(m.normals.size(), 27u);
    EXPECT_EQ(m.colors.size(), 36u);
    EXPECT_NEAR(m.normals[2], 1.0f, 0.02f);
    Image png = decodeTexture(db.readBlob(1), Codec::Png, "blob 1");
    EXPECT_EQ(png.pixels, gradientImage(8, 8, 4).pixels);  // PNG is lossless
    std::vector<Violation> v = validate(db, {});  // only the explicit cost breaks eq. 3.1
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].message, "node 1: cost 7.5 differs from eq. 3.1 (6 with c_textured=0.25)");
}

TEST(Codec, DracoKeepsGeometryWithinQuantization) {
    MeshData in = gridMesh(8, 10, 50);
    EncodedBlob blob = encodeGeometry(in, DracoOptions{});
    EXPECT_EQ(blob.info.triangles, 128u);
    EXPECT_EQ(blob.info.vertices, 81u);
    MeshData out = decodeGeometry(blob.bytes, "grid");
    ASSERT_EQ(out.triangleCount(), in.triangleCount());
    // Every decoded triangle's corners are input vertices, within 14-bit quantization of 50 m.
    double tol = 50.0 / (1 << 14) * 2;
    SurfaceMetrics a = surfaceMetrics(std::span(&in, 1)), b = surfaceMetrics(std::span(&out, 1));
    EXPECT_NEAR(a.area, b.area, a.area * 1e-3);
    EXPECT_NEAR(a.bounds.max.x, b.bounds.max.x, tol);
    EXPECT_NEAR(a.bounds.min.y, b.bounds.min.y, tol);
}

TEST(Codec, RejectsBadInputs) {
    MeshData bad = gridMesh(2);
    bad.indices.push_back(99);
    bad.indices.push_back(0);
    bad.indices.push_back(1);
    EXPECT_THROW(encodeGeometry(bad, {}), std::runtime_error);
    EXPECT_THROW(encodeGeometry(MeshData{}, {}), std::runtime_error);
    EXPECT_THROW(encodeTexture(gradientImage(4, 4, 4), Codec::Jpeg), std::runtime_error);  // JPEG has no alpha
    std::vector<uint8_t> junk(100, 0x42);
    EXPECT_THROW(decodeGeometry(junk, "junk"), FormatError);
    EXPECT_THROW(decodeTexture(junk, Codec::Jpeg, "junk"), FormatError);
    EXPECT_THROW(decodeTexture(junk, Codec::Png, "junk"), FormatError);
    try {
        decodeGeometry(junk, "the-name");
    } catch (const FormatError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("the-name: ", 0), 0u) << e.what();
    }
}

// A texture blob whose header claims more texels than its bytes can code (the fuzzer's finding:
// a 700-byte JPEG claiming 26473 x 26376) is refused before its pixels are allocated.
TEST(Codec, RefusesATextureClaimingMoreTexelsThanItsBytesCanCode) {
    Image small{16, 16, 3, std::vector<uint8_t>(16 * 16 * 3, 128)};
    std::vector<uint8_t> jpeg = encodeTexture(small, Codec::Jpeg).bytes;
    size_t sof = 0;
    for (size_t i = 2; i + 9 < jpeg.size() && !sof; ++i)
        if (jpeg[i] == 0xFF && (jpeg[i + 1] == 0xC0 || jpeg[i + 1] == 0xC2)) sof = i;
    ASSERT_NE(sof, 0u) << "no SOF marker";
    const uint16_t height = 26376, width = 26473;  // big-endian, after the marker, length and precision
    jpeg[sof + 5] = uint8_t(height >> 8), jpeg[sof + 6] = uint8_t(height & 0xFF);
    jpeg[sof + 7] = uint8_t(width >> 8), jpeg[sof + 8] = uint8_t(width & 0xFF);
    try {
        decodeTexture(jpeg, Codec::Jpeg, "blob 7");
        FAIL() << "a decompression bomb was decoded";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("blob 7: texture claims 26473x26376 texels in"), std::string::npos) << e.what();
    }
    EXPECT_EQ(decodeTexture(encodeTexture(small, Codec::Jpeg).bytes, Codec::Jpeg, "ok").width, 16u);
}

TEST(Metrics, AreaNormalBenefit) {
    // Unit right triangle in the plane z=0 and one in x=0, areas 0.5 and 2.
    MeshData m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 2, 0, 0, 0, 2};
    m.indices = {0, 1, 2, 3, 4, 5};
    SurfaceMetrics s = surfaceMetrics(std::span(&m, 1));
    EXPECT_DOUBLE_EQ(s.area, 2.5);
    EXPECT_EQ(s.triangles, 2u);
    EXPECT_FLOAT_EQ(s.staticBenefit, std::sqrt(2 * 2.5f));
    // Area-weighted: 0.5 * (0,0,1) + 2 * (1,0,0), normalised.
    double len = std::sqrt(0.25 + 4.0);
    EXPECT_NEAR(s.avgNormal.x, 2 / len, 1e-6);
    EXPECT_NEAR(s.avgNormal.z, 0.5 / len, 1e-6);
    EXPECT_EQ(s.bounds.max.y, 2);
    EXPECT_EQ(nodeCost(100, 50, 0.2), 100 * 0.2f + 50 * 0.8f);
}

TEST(Synthetic, WritesAValidTree) {
    TempDir dir;
    const std::string path = dir.file("s.hlod");
    SyntheticOptions o;
    writeSyntheticDatabase(path, o);
    Database db = Database::open(path);
    const Skeleton& s = db.skeleton();
    EXPECT_EQ(s.blockCount, 4u);
    EXPECT_EQ(s.nodes.size(), 4u * (1 + 4 + 16));
    EXPECT_EQ(s.roots().size(), 4u);
    EXPECT_EQ(s.children(s.roots()[0]).size(), 4u);
    EXPECT_NE(s.findMeta("c_levelFactor"), nullptr);
    EXPECT_GT(s.nodes[0].texelCount, 0u);
    EXPECT_GT(s.nodes[0].geometricError, s.nodes[1].geometricError);
    std::vector<Violation> v = validate(db, {});
    for (const Violation& x : v) ADD_FAILURE() << x.message;

    SyntheticOptions flat;
    flat.textureSize = 0;
    flat.levelFactor = 3;
    flat.blocksX = 1;
    writeSyntheticDatabase(path, flat);
    Database db2 = Database::open(path);
    EXPECT_EQ(db2.skeleton().nodes.size(), 2u * (1 + 3 + 9));
    EXPECT_EQ(db2.skeleton().nodes[0].texturedTriangles, 0u);
    EXPECT_GT(db2.skeleton().nodes[0].untexturedTriangles, 0u);
    EXPECT_TRUE(validate(db2, {}).empty());
}

}  // namespace
}  // namespace hlod::test
