// `hlod export tiles` run as the built binary on a synthetic database and on the banana sample
// built by `hlod build`: the structural rules of the 3D Tiles validator (tileset_checks.h), every
// exported mesh decoded with Draco against the database's triangle counts, blobs reused byte for
// byte, the placement transform, the .3tz archive, and bad input (a corrupt blob, an output that
// is not an earlier export) failing with one line and no tileset left behind.
#include "formats/temp_files.h"
#include "tileset_checks.h"

#include "formats/db.h"
#include "formats/export_tiles.h"
#include "tests/formats/helpers.h"
#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

namespace hlod::test {
namespace {

namespace fs = std::filesystem;

nlohmann::json readJson(const std::string& path) {
    const std::vector<uint8_t> bytes = readFile(path);
    return nlohmann::json::parse(bytes.begin(), bytes.end());
}

// Every tile's content decoded: triangles per node equal the database's, textures reused as stored.
void expectContentMatchesDatabase(const std::string& dbPath, const std::string& folder) {
    const Database db = Database::open(dbPath);
    const Skeleton& s = db.skeleton();
    uint64_t exported = 0, stored = 0;
    for (const Node& n : s.nodes) {
        stored += n.triangles();
        const std::string glbPath = folder + "/tiles/" + std::to_string(n.id) + ".glb";
        if (n.triangles() == 0) {
            EXPECT_FALSE(fs::exists(glbPath)) << "node " << n.id;
            continue;
        }
        const GlbFile glb = readGlb(glbPath);
        uint64_t triangles = 0;
        for (const DecodedPrimitive& p : decodePrimitives(glb)) triangles += p.triangles;
        EXPECT_EQ(triangles, n.triangles()) << "node " << n.id;
        exported += triangles;
        // Images are the texture blobs' bytes, unchanged.
        std::vector<std::vector<uint8_t>> textures;
        for (uint32_t b = n.firstBlob; b < n.firstBlob + n.blobCount; ++b)
            if (s.blobs[b].kind == BlobKind::Texture) textures.push_back(db.readBlob(b));
        for (const auto& image : glb.json.value("images", nlohmann::json::array())) {
            const auto& view = glb.json["bufferViews"][image["bufferView"].get<size_t>()];
            const auto begin = glb.bin.begin() + view.value("byteOffset", 0l);
            const std::vector<uint8_t> bytes(begin, begin + view["byteLength"].get<long>());
            EXPECT_NE(std::find(textures.begin(), textures.end(), bytes), textures.end()) << "node " << n.id;
        }
        // Sampled CLAMP_TO_EDGE, as `hlod play` does (glTF's default REPEAT until stop 51).
        for (const auto& sampler : glb.json.value("samplers", nlohmann::json::array()))
            EXPECT_TRUE(sampler.value("wrapS", 0) == 33071 && sampler.value("wrapT", 0) == 33071) << "node " << n.id;
        if (!textures.empty()) {
            EXPECT_EQ(glb.json.value("samplers", nlohmann::json::array()).size(), 1u) << "node " << n.id;
        }
    }
    EXPECT_EQ(exported, stored);
}

struct ExportTiles : ::testing::Test {
    TempDir dir;
    std::string db = dir.file("s.hlod");
    void SetUp() override {
        SyntheticOptions o;
        o.levels = 3;
        writeSyntheticDatabase(db, o);
    }
};

TEST_F(ExportTiles, SyntheticDatabaseGivesAValidTileset) {
    const std::string out = dir.file("tiles");
    RunResult r = runHlod({"export", "tiles", db, "-o", out});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("3D Tiles 1.1 tileset, 85 tiles (84 with content)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("note: no --origin"), std::string::npos) << r.out;
    const std::vector<std::string> problems = checkTileset(out);
    for (const std::string& p : problems) ADD_FAILURE() << p;
    expectContentMatchesDatabase(db, out);
    // Readable by others (a web server serving it): not mkdtemp's 0700 (before stop 44).
    const std::filesystem::perms others = std::filesystem::perms::others_read | std::filesystem::perms::others_exec;
    EXPECT_EQ(std::filesystem::status(out).permissions() & others, others);

    const nlohmann::json t = readJson(out + "/tileset.json");
    const Skeleton s = Database::open(db).skeleton();
    const std::vector<uint32_t> roots = s.roots();
    ASSERT_EQ(t["root"]["children"].size(), roots.size());  // the hlod0 nodes are the root's children
    EXPECT_FALSE(t["root"].contains("content"));
    EXPECT_FALSE(t["root"].contains("transform"));
    EXPECT_NE(t["asset"]["extras"]["hlod"]["frame"].get<std::string>().find("local"), std::string::npos);
    EXPECT_EQ(t["root"]["refine"], "REPLACE");
    const auto& first = t["root"]["children"][0];
    EXPECT_EQ(first["content"]["uri"], "tiles/" + std::to_string(roots[0]) + ".glb");
    EXPECT_EQ(first["geometricError"].get<double>(), double(s.nodes[roots[0]].geometricError));
    EXPECT_GE(t["root"]["geometricError"].get<double>(), first["geometricError"].get<double>());
    EXPECT_EQ(t["geometricError"], t["root"]["geometricError"]);
}

TEST_F(ExportTiles, GlbUsesTheStoredDracoBytesAndUprightAxes) {
    const std::string out = dir.file("tiles");
    ASSERT_EQ(runHlod({"export", "tiles", db, "-o", out}).exitCode, 0);
    const Database d = Database::open(db);
    const Node& n = d.skeleton().nodes[0];
    const GlbFile glb = readGlb(out + "/tiles/0.glb");
    const auto& prim = glb.json["meshes"][0]["primitives"][0];
    const auto& view = glb.json["bufferViews"][prim["extensions"]["KHR_draco_mesh_compression"]["bufferView"].get<size_t>()];
    const auto begin = glb.bin.begin() + view.value("byteOffset", 0l);
    uint32_t geometry = n.firstBlob;
    while (d.skeleton().blobs[geometry].kind != BlobKind::Geometry) ++geometry;
    EXPECT_EQ(std::vector<uint8_t>(begin, begin + view["byteLength"].get<long>()), d.readBlob(geometry));
    EXPECT_EQ(glb.json["extensionsRequired"], nlohmann::json::array({"KHR_draco_mesh_compression"}));
    // Decoded, turned y-up by the node matrix and back z-up as 3D Tiles does, the vertices are
    // the database's: z up stays z up.
    const DecodedPrimitive p = decodePrimitives(glb)[0];
    for (const auto& v : p.positions) {
        EXPECT_GE(v[2], n.bounds.min.z - 1e-3);
        EXPECT_LE(v[2], n.bounds.max.z + 1e-3);
        EXPECT_GE(v[0], n.bounds.min.x - 1e-3);
        EXPECT_LE(v[1], n.bounds.max.y + 1e-3);
    }
}

TEST_F(ExportTiles, OriginPlacesTheLocalFrameEastNorthUp) {
    const std::string out = dir.file("tiles");
    RunResult r = runHlod({"export", "tiles", db, "-o", out, "--origin", "0,0,0"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json t = readJson(out + "/tileset.json");
    // At latitude 0, longitude 0: east = +y, north = +z, up = +x of ECEF, origin at (a, 0, 0).
    const std::vector<double> expected = {0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 6378137, 0, 0, 1};
    ASSERT_EQ(t["root"]["transform"].size(), 16u);
    for (int i = 0; i < 16; ++i) EXPECT_NEAR(t["root"]["transform"][i].get<double>(), expected[i], 1e-6) << i;
    EXPECT_EQ(t["asset"]["extras"]["hlod"]["origin"]["latitude"], 0.0);

    // Berkeley: the up column is the ellipsoid normal, the columns orthonormal.
    const auto m = eastNorthUpToEcef({37.8716, -122.2727, 100});
    const double up[3] = {m[8], m[9], m[10]};
    EXPECT_NEAR(std::hypot(up[0], up[1], up[2]), 1, 1e-12);
    EXPECT_NEAR(m[0] * m[4] + m[1] * m[5] + m[2] * m[6], 0, 1e-12);
    EXPECT_NEAR(std::asin(up[2]) * 180 / M_PI, 37.8716, 1e-9);
    EXPECT_NEAR(std::hypot(m[12], m[13], m[14]), 6370000, 10000);

    for (const char* bad : {"1,2", "91,0,0", "a,b,c", "1,2,3,4", "0,0,1e300", "0,0,-7e6"}) {  // accepted before stop 44: 1e300 m, -7e6 m (beyond the earth's centre)
        RunResult u = runHlod({"export", "tiles", db, "-o", dir.file("bad"), "--origin", bad});
        EXPECT_EQ(u.exitCode, 2) << bad;
        EXPECT_EQ(u.err.rfind("hlod export tiles: --origin", 0), 0u) << u.err;
        EXPECT_FALSE(fs::exists(dir.file("bad")));
    }
}

TEST_F(ExportTiles, CorruptBlobFailsWithOneLineAndLeavesNoTileset) {
    const Database d = Database::open(db);
    const BlobRef blob = d.skeleton().blobs[d.skeleton().nodes.back().firstBlob];
    const uint32_t index = d.skeleton().nodes.back().firstBlob;
    std::vector<uint8_t> bytes = readFile(db);
    bytes[blob.offset + blob.size / 2] ^= 0x5A;
    const std::string bad = dir.file("bad.hlod");
    writeFile(bad, bytes);
    const std::string out = dir.file("tiles");
    RunResult r = runHlod({"export", "tiles", bad, "-o", out});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err, "hlod export tiles: " + bad + ": blob " + std::to_string(index) + " (node " +
                         std::to_string(blob.node) + ") checksum mismatch (corrupt data)\n");
    EXPECT_FALSE(fs::exists(out));
    for (const auto& e : fs::directory_iterator(dir.path))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();

    // An earlier export at OUT is left as it was.
    ASSERT_EQ(runHlod({"export", "tiles", db, "-o", out}).exitCode, 0);
    const std::vector<uint8_t> before = readFile(out + "/tileset.json");
    EXPECT_EQ(runHlod({"export", "tiles", bad, "-o", out}).exitCode, 1);
    EXPECT_EQ(readFile(out + "/tileset.json"), before);
    EXPECT_TRUE(checkTileset(out).empty());
}

// A texture is copied as stored, so one whose checksum holds (the record's checksum fixed) but
// which does not decode is one line and status 1, not a tileset no viewer can show with status 0:
// its header zeroed (before stop 36), or its second half (before stop 38, which checked headers only).
TEST_F(ExportTiles, TextureThatDoesNotDecodeFailsWithOneLine) {
    const Database d = Database::open(db);
    uint32_t index = 0;
    while (d.skeleton().blobs[index].kind != BlobKind::Texture) ++index;
    const BlobRef blob = d.skeleton().blobs[index];
    const std::string where = ": node " + std::to_string(blob.node) + ": blob " + std::to_string(index) + ": ";
    for (const uint64_t from : {uint64_t(0), blob.size / 2}) {
        SCOPED_TRACE(from);
        std::vector<uint8_t> bytes = readFile(db);
        std::fill(bytes.begin() + long(blob.offset + from), bytes.begin() + long(blob.offset + blob.size), 0);
        patchRecord(bytes, layout::kTagBlob, index, 48, layout::checksum(std::span(bytes).subspan(blob.offset, blob.size)));
        const std::string bad = dir.file("zeroed.hlod"), out = dir.file("tiles");
        writeFile(bad, bytes);
        const RunResult r = runHlod({"export", "tiles", bad, "-o", out});
        EXPECT_EQ(r.exitCode, 1) << r.err;
        if (from == 0) {
            EXPECT_EQ(r.err, "hlod export tiles: " + bad + where + "bad JPEG texture: wrong signature\n");
        }
        EXPECT_EQ(r.err.rfind("hlod export tiles: " + bad + where, 0), 0u) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

TEST_F(ExportTiles, ReplacesAnEarlierExportOnly) {
    const std::string out = dir.file("tiles");
    ASSERT_EQ(runHlod({"export", "tiles", db, "-o", out}).exitCode, 0);
    RunResult again = runHlod({"export", "tiles", db, "-o", out, "--origin", "10,20,30"});
    ASSERT_EQ(again.exitCode, 0) << again.err;
    EXPECT_TRUE(readJson(out + "/tileset.json")["root"].contains("transform"));

    // A killed export's temporary (OUT.tmp-hlodSPACE-PID-XXXXXX, PID no longer running; 999999999 is
    // above any pid_max) is removed by the next export to OUT; a running one's is kept, and so is a
    // user's file of a name alike (`OUT.tmp-2023-backup` was swept until stop 47).
    const auto named = [](const std::string& prefix, long pid, const std::string& letters) {
        std::string name = temporaryPattern(prefix, pid);
        return name.replace(name.size() - 6, 6, letters);
    };
    const std::string stale = named(out + ".tmp", 999999999, "abcdef"), live = named(out + ".tmp", ::getpid(), "abcdef");
    const std::string users = out + ".tmp-2023-backup";
    fs::create_directories(users);
    fs::create_directories(stale + "/tiles");
    fs::create_directories(live);
    ASSERT_EQ(runHlod({"export", "tiles", db, "-o", out}).exitCode, 0);
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(live));
    EXPECT_TRUE(fs::exists(users));
    const std::string archive = dir.file("a.3tz"), staleArchive = named(archive + ".tmp", 999999999, "ghijkl");  // --3tz's is a file
    writeFile(staleArchive, {'P', 'K'});
    ASSERT_EQ(runHlod({"export", "tiles", db, "--3tz", "-o", archive}).exitCode, 0);
    EXPECT_FALSE(fs::exists(staleArchive));
    EXPECT_EQ(fs::status(archive).permissions() & fs::perms::others_read, fs::perms::others_read);

    const std::string other = dir.file("other");
    fs::create_directories(other);
    writeFile(other + "/notes.txt", {'h', 'i'});
    RunResult r = runHlod({"export", "tiles", db, "-o", other});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod export tiles: " + other + ": exists and is not a tileset folder (no tileset.json); not replaced\n");
    EXPECT_TRUE(fs::exists(other + "/notes.txt"));
    // A tileset.json alone does not make a folder an earlier export: a site holding other files
    // beside it is refused, not replaced (until stop 45 its other files were deleted, exit 0).
    writeFile(other + "/tileset.json", {'{', '}'});
    fs::create_directories(other + "/tiles");
    r = runHlod({"export", "tiles", db, "-o", other});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "hlod export tiles: " + other + ": holds notes.txt, which hlod export does not write; not replaced\n");
    EXPECT_TRUE(fs::exists(other + "/notes.txt"));
    fs::remove(other + "/notes.txt");
    writeFile(other + "/tiles/index.html", {'<'});
    r = runHlod({"export", "tiles", db, "-o", other});
    EXPECT_EQ(r.err, "hlod export tiles: " + other + ": holds tiles/index.html, which hlod export does not write; not replaced\n");
    fs::remove(other + "/tiles/index.html");
    r = runHlod({"export", "tiles", db, "-o", other + "/"});  // what is left is an export's: replaced; DIR/ is DIR
    EXPECT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_TRUE(fs::exists(other + "/tiles/0.glb"));
    for (const std::string& name : {std::string("/"), dir.file("a.3tz/")}) {  // no name (`DIR/` before stop 45)
        r = name == "/" ? runHlod({"export", "tiles", db, "-o", name}) : runHlod({"export", "tiles", db, "-o", name, "--3tz"});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod export tiles: " + name + ": not a file or folder name\n");
    }

    for (const bool archive : {false, true}) {  // a failed write, status 1 like every output's (2 until stop 46)
        const std::string nowhere = dir.file("no-such-folder/t");
        r = archive ? runHlod({"export", "tiles", db, "-o", nowhere, "--3tz"}) : runHlod({"export", "tiles", db, "-o", nowhere});
        EXPECT_EQ(r.exitCode, 1) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod export tiles: " + nowhere + ": its folder does not exist\n");
    }
    RunResult missing = runHlod({"export", "tiles", dir.file("none.hlod"), "-o", dir.file("x")});
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_EQ(missing.err, "hlod export tiles: " + dir.file("none.hlod") + ": no such file\n");
    RunResult help = runHlod({"export", "tiles", "--help"});
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_EQ(help.out.rfind("write a 3D Tiles 1.1 tileset", 0), 0u) << help.out;
    EXPECT_EQ(runHlod({"export"}).exitCode, 2);
}

uint16_t u16(const std::vector<uint8_t>& b, size_t at) {
    uint16_t v;
    std::memcpy(&v, b.data() + at, 2);
    return v;
}
uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}

TEST_F(ExportTiles, ArchiveIsAStoredZipWithItsIndexLast) {
    const std::string folder = dir.file("tiles"), archive = dir.file("s.3tz");
    ASSERT_EQ(runHlod({"export", "tiles", db, "-o", folder}).exitCode, 0);
    RunResult r = runHlod({"export", "tiles", db, "-o", archive, "--3tz"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::vector<uint8_t> zip = readFile(archive);
    ASSERT_GE(zip.size(), 22u);
    const size_t end = zip.size() - 22;
    ASSERT_EQ(u32(zip, end), 0x06054b50u);
    const uint16_t entries = u16(zip, end + 10);
    size_t at = u32(zip, end + 16);
    std::map<std::string, std::vector<uint8_t>> files;
    std::vector<uint64_t> offsets;
    std::string last;
    for (uint16_t i = 0; i < entries; ++i) {
        ASSERT_EQ(u32(zip, at), 0x02014b50u);
        EXPECT_EQ(u16(zip, at + 10), 0) << "stored, not compressed";
        const uint32_t size = u32(zip, at + 20), local = u32(zip, at + 42);
        last.assign(zip.begin() + long(at + 46), zip.begin() + long(at + 46 + u16(zip, at + 28)));
        const size_t data = local + 30 + u16(zip, local + 26) + u16(zip, local + 28);
        files[last].assign(zip.begin() + long(data), zip.begin() + long(data + size));
        offsets.push_back(local);
        at += 46 + u16(zip, at + 28) + u16(zip, at + 30) + u16(zip, at + 32);
    }
    EXPECT_EQ(last, "@3dtilesIndex1@");
    EXPECT_EQ(files["tileset.json"], readFile(folder + "/tileset.json"));
    EXPECT_EQ(files["tiles/0.glb"], readFile(folder + "/tiles/0.glb"));
    const std::vector<uint8_t>& index = files["@3dtilesIndex1@"];
    ASSERT_EQ(index.size(), 24u * (entries - 1));
    std::vector<uint64_t> indexed;
    for (size_t i = 0; i < index.size(); i += 24) {
        uint64_t offset, lo, hi, nextLo = 0, nextHi = 0;
        std::memcpy(&offset, index.data() + i + 16, 8);
        std::memcpy(&lo, index.data() + i, 8);
        std::memcpy(&hi, index.data() + i + 8, 8);
        if (i + 24 < index.size()) {
            std::memcpy(&nextLo, index.data() + i + 24, 8);
            std::memcpy(&nextHi, index.data() + i + 32, 8);
            EXPECT_TRUE(lo < nextLo || (lo == nextLo && hi <= nextHi)) << "index sorted by hash";
        }
        indexed.push_back(offset);
    }
    offsets.pop_back();  // the index does not list itself
    std::sort(indexed.begin(), indexed.end());
    std::sort(offsets.begin(), offsets.end());
    EXPECT_EQ(indexed, offsets);
}

// The banana scan built by the pipeline (real atlas texture, uneven Draco lattices).
TEST(ExportTilesSample, BananaBuiltByThePipeline) {
    TempDir dir;
    const std::string db = dir.file("banana.hlod"), out = dir.file("tiles");
    RunResult b = runHlod({"build", std::string(HLOD_SOURCE_DIR) + "/samples/banana/textured_simple_reoriented.obj", "-o", db});
    ASSERT_EQ(b.exitCode, 0) << b.err;
    RunResult r = runHlod({"export", "tiles", db, "-o", out, "--origin", "37.8716,-122.2727,200"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const std::string& p : checkTileset(out)) ADD_FAILURE() << p;
    expectContentMatchesDatabase(db, out);
}

}  // namespace
}  // namespace hlod::test
