// Node textures keep their source's chroma (pipeline/TEXTURE_SIZE.md "Stop 17"): a JPEG's 4:2:0
// is read from its frame header (jpeg_quality.cpp); a 4:2:0 texture's atlas is made of the
// source's 16 x 16 blocks (its MCUs) on the source's grid, so its colour samples are the source's
// and cover no two groups; `--jpeg-chroma source` (the default) writes a 4:2:0 source's nodes
// 4:2:0 and every other 4:4:4, `4:4:4` and `4:2:0` force one.
#include "helpers.h"

#include "formats/build_report.h"
#include "formats/metrics.h"
#include "pipeline/texture_charts.h"
#include "tests/support/chunked_scan.h"
#include "tests/support/run_hlod.h"

namespace hlod::test {
namespace {

TEST(TextureChroma, FrameHeaderSaysWhetherAJpegIs420) {
    const Image rgb = noisyImage(64);
    EXPECT_TRUE(jpegChroma420(encodeTexture(rgb, Codec::Jpeg, 85, true).bytes));
    EXPECT_FALSE(jpegChroma420(encodeTexture(rgb, Codec::Jpeg, 85, false).bytes));
    EXPECT_FALSE(jpegChroma420(encodeTexture(rgb, Codec::Png).bytes));
    Image grey{64, 64, 1, std::vector<uint8_t>(64 * 64, 128)};
    EXPECT_FALSE(jpegChroma420(encodeTexture(grey, Codec::Jpeg, 85, true).bytes));  // one component: no chroma
    std::vector<uint8_t> cut = encodeTexture(rgb, Codec::Jpeg, 85, true).bytes;
    const uint8_t marker[2] = {0xFF, 0xC0};  // baseline frame header
    const size_t sof = static_cast<size_t>(std::search(cut.begin(), cut.end(), marker, marker + 2) - cut.begin());
    ASSERT_LT(sof, cut.size());
    cut.resize(sof + 12);  // the frame header cut short
    EXPECT_FALSE(jpegChroma420(cut));
    cut.resize(sof + 3);  // cut inside the segment's length: one of its two bytes
    EXPECT_FALSE(jpegChroma420(cut));
    EXPECT_FALSE(jpegChroma420(std::vector<uint8_t>{}));
}

// A progressive frame (SOF2) is read like a baseline one; a file cut inside a table's segment
// length, or inside the table, has no quality (0: unknown), never a guess.
TEST(TextureChroma, ProgressiveFramesAndHeadersCutShort) {
    std::vector<uint8_t> bytes = encodeTexture(noisyImage(64), Codec::Jpeg, 75, true).bytes;
    const uint8_t sof0[2] = {0xFF, 0xC0}, dqt[2] = {0xFF, 0xDB};
    const auto at = [&](const uint8_t* marker) { return static_cast<size_t>(std::search(bytes.begin(), bytes.end(), marker, marker + 2) - bytes.begin()); };
    const size_t sof = at(sof0), table = at(dqt);
    ASSERT_LT(sof, bytes.size());
    ASSERT_LT(table, sof);
    bytes[sof + 1] = 0xC2;  // the same frame header as a progressive one (T.81 §B.2.2: the same fields)
    EXPECT_TRUE(jpegChroma420(bytes));
    EXPECT_EQ(jpegQuality(bytes), 75);
    for (const size_t keep : {table + 2, table + 3, table + 4 + 1 + 63}) {  // no length, half a length, a table less one entry
        const std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + std::ptrdiff_t(keep));
        EXPECT_EQ(jpegQuality(cut), 0) << keep - table;
        EXPECT_FALSE(jpegChroma420(cut)) << keep - table;
    }
}

// A grey texture has no chroma: forced 4:2:0, its node textures stay one channel of 8 x 8 blocks,
// and a material without a texture is never 4:2:0.
TEST(TextureChroma, GreyAndUntexturedMaterialsAreNever420) {
    Image grey{256, 256, 1, {}};
    grey.pixels = noisyImage(256).pixels;
    grey.pixels.resize(256 * 256);
    const std::vector<Material> materials = {{"grey", "", std::make_shared<Image>(grey)}, {"none", "", nullptr},
                                             {"rgb", "", std::make_shared<Image>(noisyImage(256))}};
    std::vector<TextureProblem> problems;
    BlockTextures textures(materials, nullptr, false, problems, nullptr);
    for (const JpegChroma chroma : {JpegChroma::Source, JpegChroma::Full, JpegChroma::Half}) {
        EXPECT_FALSE(textures.chroma420(0, chroma)) << jpegChromaName(chroma);
        EXPECT_FALSE(textures.chroma420(1, chroma)) << jpegChromaName(chroma);
        EXPECT_EQ(textures.chroma420(2, chroma), chroma == JpegChroma::Half) << jpegChromaName(chroma);
    }
    MeshData mesh = chartsOver256();
    const Image atlas = textures.atlas(0, 1, mesh, textures.chroma420(0, JpegChroma::Half));
    EXPECT_EQ(atlas.channels, 1u);
    MeshData ofSixteen = chartsOver256();
    const Image wider = atlasTexture(textureView(grey), 1, ofSixteen, 16);
    EXPECT_LT(uint64_t(atlas.width) * atlas.height, uint64_t(wider.width) * wider.height);  // 8 x 8 blocks hold fewer texels
    EXPECT_THROW(atlasTexture(textureView(grey), 1, mesh, 12), std::invalid_argument);
}

// An atlas of 16 x 16 blocks keeps every UV at its place within the source's 16 x 16 grid and
// copies the texels triangles use exactly; its sides are whole blocks.
TEST(TextureChroma, AtlasOf16BlocksKeepsTheSourcesMcuGrid) {
    const Image source = noisyImage(256);
    const MeshData before = chartsOver256();
    MeshData after = before;
    const Image atlas = atlasTexture(textureView(source), 1, after, 16);
    EXPECT_EQ(atlas.width % 16, 0u);
    EXPECT_EQ(atlas.height % 16, 0u);
    for (size_t v = 0; v < before.vertexCount(); ++v)
        for (int a = 0; a < 2; ++a) {
            const double s = before.texcoords[2 * v + a] * 256.0, t = after.texcoords[2 * v + a] * double(a ? atlas.height : atlas.width);
            EXPECT_NEAR(std::fmod(s, 16.0), std::fmod(t, 16.0), 1e-3) << v;
        }
    EXPECT_EQ(textureFidelity(before, textureView(source), after, atlas).squaredError, 0);
}

// A 4:2:0 source's texels, re-coded 4:2:0 at its quality: on its own 16 x 16 grid the colour
// samples are nearly the source's (a re-coding close to lossless), on an 8-texel grid shifted by
// half an MCU they are averaged anew and lose more; 4:4:4 spends more bytes on the same texels.
TEST(TextureChroma, A420SourceRecodes420OnItsOwnGrid) {
    const Image original = noisyImage(256);
    const Image source = decodeTexture(encodeTexture(original, Codec::Jpeg, 85, true).bytes, Codec::Jpeg, "source");
    const MeshData before = chartsOver256();
    const auto coded = [&](int block, bool chroma420, size_t& bytes) {
        MeshData after = before;
        const Image atlas = atlasTexture(textureView(source), 1, after, block);
        const EncodedBlob blob = encodeTexture(atlas, Codec::Jpeg, 85, chroma420);
        bytes = blob.bytes.size();
        const TextureFidelity f = textureFidelity(before, textureView(source), after, decodeTexture(blob.bytes, Codec::Jpeg, "node"));
        return psnrDb(f.squaredError, f.samples);
    };
    size_t aligned = 0, shifted = 0, full = 0;
    const double onGrid = coded(16, true, aligned), offGrid = coded(8, true, shifted), full444 = coded(8, false, full);
    std::printf("4:2:0 on the MCU grid %.2f dB (%zu B), shifted %.2f dB (%zu B), 4:4:4 %.2f dB (%zu B)\n", onGrid, aligned, offGrid, shifted,
                full444, full);
    EXPECT_GT(onGrid, offGrid + 1.0);
    EXPECT_LT(aligned, full);
}

// Each node texture's chroma and block size against `expect(node)`; returns how many there are.
struct Expected {
    bool half = false;
    uint32_t block = 8;  // its sides are whole blocks
};
template <class Expect>
uint32_t textureBlobs(const std::string& db, Expect expect, const std::string& what) {
    const Database database = Database::open(db);
    const std::vector<Node>& nodes = database.skeleton().nodes;
    uint32_t textures = 0;
    for (uint32_t i = 0; i < nodes.size(); ++i)
        for (uint32_t b = 0; b < nodes[i].blobCount; ++b)
            if (database.skeleton().blobs[nodes[i].firstBlob + b].kind == BlobKind::Texture) {
                ++textures;
                const std::vector<uint8_t> bytes = database.readBlob(nodes[i].firstBlob + b);
                const Expected e = expect(i);
                EXPECT_EQ(jpegChroma420(bytes), e.half) << what << ", node " << i;
                const Image image = decodeTexture(bytes, Codec::Jpeg, "node");
                EXPECT_EQ(image.width % e.block, 0u) << what << ", node " << i;
                EXPECT_EQ(image.height % e.block, 0u) << what << ", node " << i;
            }
    return textures;
}

// The default follows each source: a 4:2:0 scan's node textures are 4:2:0, a 4:4:4 scan's 4:4:4,
// a baked atlas (charts from several sources on 8 x 8 blocks) 4:4:4; --jpeg-chroma forces either;
// the database records the setting.
TEST(TextureChroma, NodeTexturesFollowTheSourceUnlessForced) {
    for (const bool source420 : {true, false}) {
        TempDir dir;
        ChunkedScanOptions options;
        options.jpeg = true, options.jpegChroma420 = source420, options.textureSize = 128;
        const ChunkedScan scan = writeChunkedScan(dir.path.string(), "facade", facadeMesh(40), options);
        for (const std::string chroma : {"", "4:4:4", "4:2:0"}) {
            const std::string db = dir.file(chroma.empty() ? "default.hlod" : chroma == "4:4:4" ? "full.hlod" : "half.hlod");
            std::vector<std::string> args = {"build", scan.obj, "-o", db, "-j", "1"};
            if (!chroma.empty()) args.insert(args.end(), {"--jpeg-chroma", chroma});
            const RunResult build = runHlod(args);
            ASSERT_EQ(build.exitCode, 0) << build.outAndErr();
            const std::optional<BuildReport> report = readBuildReport(buildReportPath(db));  // nodes in the database's order (one block)
            ASSERT_TRUE(report.has_value());
            ASSERT_EQ(report->nodes.size(), Database::open(db).skeleton().nodes.size());
            uint32_t baked = 0, leaves420 = 0;
            const auto expect = [&](uint32_t node) {  // a baked atlas's charts lie on 8 x 8 blocks
                const bool isBaked = report->nodes[node].baked;
                baked += isBaked;
                const bool half = chroma.empty() ? source420 && !isBaked : chroma == "4:2:0";
                leaves420 += half && report->nodes[node].level == report->nodes.back().level;
                return Expected{half, half && !isBaked ? 16u : 8u};
            };
            const std::string what = std::string(source420 ? "4:2:0" : "4:4:4") + " source, --jpeg-chroma " + (chroma.empty() ? "default" : chroma);
            EXPECT_GT(textureBlobs(db, expect, what), 0u) << what;
            EXPECT_GT(baked, 0u) << what;  // the baked atlases are checked too
            EXPECT_EQ(leaves420 > 0, chroma.empty() ? source420 : chroma == "4:2:0") << what;
            const Database opened = Database::open(db);
            const auto& meta = opened.skeleton().meta;
            const auto recorded = std::find_if(meta.begin(), meta.end(), [](const auto& kv) { return kv.first == "jpeg.chroma"; });
            ASSERT_NE(recorded, meta.end()) << what;
            EXPECT_EQ(recorded->second, chroma.empty() ? "source" : chroma) << what;
        }
    }
}

}  // namespace
}  // namespace hlod::test
