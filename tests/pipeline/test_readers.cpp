// Readers (PLY ascii/binary, OBJ+MTL, glTF) on generated files and the real scans in
// ../shared/datasets, and one test per class of bad input.
#include "helpers.h"

#include "formats/codec.h"
#include "tests/support/run_hlod.h"

#include <nlohmann/json.hpp>

namespace hlod::test {
namespace {

std::string dataset(const std::string& relative) {
    const std::string path = sharedDir() + "/datasets/" + relative;
    return std::filesystem::exists(path) ? path : "";
}

void expectSameMesh(const MeshData& a, const MeshData& b) {
    ASSERT_EQ(a.indices, b.indices);
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (size_t i = 0; i < a.positions.size(); ++i) ASSERT_NEAR(a.positions[i], b.positions[i], 1e-4f);
    ASSERT_EQ(a.texcoords.size(), b.texcoords.size());
    for (size_t i = 0; i < a.texcoords.size(); ++i) ASSERT_NEAR(a.texcoords[i], b.texcoords[i], 1e-5f);
}

TEST(ReadPly, AsciiAndBinaryGiveTheSameMesh) {
    TempDir dir;
    const Piece p = terrain(12);
    writePly(dir.file("a.ply"), p.mesh, false);
    writePly(dir.file("b.ply"), p.mesh, true);
    const SourceMesh a = readMesh(dir.file("a.ply")), b = readMesh(dir.file("b.ply"));
    expectSameMesh(a.piece.mesh, p.mesh);
    expectSameMesh(b.piece.mesh, p.mesh);
    EXPECT_EQ(a.piece.materials.size(), p.mesh.triangleCount());
}

TEST(ReadPly, StanfordBunnyAscii) {
    const std::string path = dataset("A1_stanford_bunny/bun_zipper.ply");
    if (path.empty()) GTEST_SKIP() << "no ../shared/datasets";
    const SourceMesh s = readMesh(path);
    EXPECT_EQ(s.piece.mesh.vertexCount(), 35947u);
    EXPECT_EQ(s.piece.mesh.triangleCount() + s.stats.degenerateDropped, 69451u);
}

TEST(ReadPly, LucyBinary) {
    const std::string path = dataset("A3_stanford_lucy_100k/Lucy100k.ply");
    if (path.empty()) GTEST_SKIP() << "no ../shared/datasets";
    const SourceMesh s = readMesh(path);
    EXPECT_EQ(s.piece.mesh.triangleCount() + s.stats.degenerateDropped, 100000u);
}

TEST(ReadObj, BananaWithTextureAtlas) {
    const std::string path = dataset("A2_ycb_011_banana_textured_scan/textured_simple_reoriented.obj");
    if (path.empty()) GTEST_SKIP() << "no ../shared/datasets";
    const SourceMesh s = readMesh(path);
    EXPECT_EQ(s.piece.mesh.triangleCount() + s.stats.degenerateDropped, 15728u);
    EXPECT_EQ(s.piece.mesh.texcoords.size(), 2 * s.piece.mesh.vertexCount());
    ASSERT_FALSE(s.materials.empty());
    EXPECT_TRUE(s.materials[s.piece.materials[0]].texturePath.ends_with("texture_map.png"));
    EXPECT_TRUE(s.stats.warnings.empty());
}

TEST(ReadObj, ManyMaterialsAndFlippedV) {
    TempDir dir;
    const Piece p = terrain(8, 100, true);
    writeFile(dir.file("atlas.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    writeObj(dir.file("m.obj"), p, "atlas.png");
    const SourceMesh s = readMesh(dir.file("m.obj"));
    const MeshData& m = s.piece.mesh;  // corners are renumbered in first-use order: compare corners
    ASSERT_EQ(m.triangleCount(), p.mesh.triangleCount());
    for (size_t c = 0; c < m.indices.size(); ++c)
        for (int a = 0; a < 2; ++a) {
            ASSERT_NEAR(m.positions[3 * m.indices[c] + a], p.mesh.positions[3 * p.mesh.indices[c] + a], 1e-4f);
            ASSERT_NEAR(m.texcoords[2 * m.indices[c] + a], p.mesh.texcoords[2 * p.mesh.indices[c] + a], 1e-5f);
        }
    EXPECT_EQ(s.piece.materials, p.materials);
    EXPECT_EQ(s.materials[1].texturePath, std::filesystem::canonical(dir.file("atlas.png")).string());
}

// "v x y z r g b" (MeshLab's and many scanners' vertex colours): read, welded with their
// vertices, and built into the database; a mesh where one vertex lacks them is read without.
TEST(ReadObj, VertexColoursReachTheDatabase) {
    TempDir dir;
    const Piece p = terrain(6);
    std::ofstream out(dir.file("c.obj"));
    for (size_t i = 0; i < p.mesh.vertexCount(); ++i)
        out << "v " << p.mesh.positions[3 * i] << " " << p.mesh.positions[3 * i + 1] << " " << p.mesh.positions[3 * i + 2] << " "
            << (i % 5) / 4.0 << " 0.5 " << (i % 2 ? 1.5 : -0.5) << "\n";  // blue clamped to 0..1
    for (size_t t = 0; t < p.mesh.triangleCount(); ++t)
        out << "f " << p.mesh.indices[3 * t] + 1 << " " << p.mesh.indices[3 * t + 1] + 1 << " " << p.mesh.indices[3 * t + 2] + 1 << "\n";
    out.close();
    const SourceMesh s = readMesh(dir.file("c.obj"));
    ASSERT_EQ(s.piece.mesh.colors.size(), 4 * s.piece.mesh.vertexCount());
    for (size_t c = 0; c < s.piece.mesh.indices.size(); ++c) {
        const uint32_t v = p.mesh.indices[c];
        const uint8_t* rgba = &s.piece.mesh.colors[4 * s.piece.mesh.indices[c]];
        EXPECT_EQ(rgba[0], static_cast<uint8_t>(std::lround((v % 5) / 4.0 * 255))) << c;
        EXPECT_EQ(rgba[1], 128) << c;
        EXPECT_EQ(rgba[2], v % 2 ? 255 : 0) << c;
        EXPECT_EQ(rgba[3], 255) << c;
    }
    ASSERT_EQ(runHlod({"build", dir.file("c.obj"), "-o", dir.file("c.hlod")}).exitCode, 0);
    const Database db = Database::open(dir.file("c.hlod"));
    size_t coloured = 0;
    for (uint32_t b = 0; b < db.skeleton().blobs.size(); ++b)
        if (db.skeleton().blobs[b].kind == BlobKind::Geometry) {
            const MeshData m = decodeGeometry(db.readBlob(b), "blob");
            EXPECT_EQ(m.colors.size(), 4 * m.vertexCount()) << "blob " << b;
            coloured += !m.colors.empty();
        }
    EXPECT_GT(coloured, 0u);
    std::ofstream(dir.file("c.obj"), std::ios::app) << "v 0 0 9\n";  // one vertex without: no colours at all
    EXPECT_TRUE(readMesh(dir.file("c.obj")).piece.mesh.colors.empty());
}

// A UTF-8 byte order mark before the first keyword (Windows tools write one) hid the OBJ's
// `mtllib` and the MTL's `newmtl`: every material was left untextured.
TEST(ReadObj, AByteOrderMarkBeforeTheFirstKeyword) {
    TempDir dir;
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    const std::string bom = "\xEF\xBB\xBF";
    std::ofstream(dir.file("b.obj")) << bom << "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl m\nf 1/1 2/2 3/3\n";
    std::ofstream(dir.file("b.mtl")) << bom << "newmtl m\nKd 1 1 1\nmap_Kd a.png\n";
    const SourceMesh s = readMesh(dir.file("b.obj"));
    EXPECT_TRUE(s.stats.textureProblems.empty());
    ASSERT_EQ(s.piece.materials.size(), 1u);
    EXPECT_EQ(s.materials[s.piece.materials[0]].texturePath, std::filesystem::canonical(dir.file("a.png")).string());
    EXPECT_EQ(s.piece.mesh.texcoords.size(), 6u);
    // The mark is not counted in the bytes read: a file over the 4 KiB first read, its last line
    // without a newline, reads whole (its last face would end in three stray bytes, and ASan
    // would see the read past the buffer).
    std::ofstream big(dir.file("big.obj"));
    big << bom << "mtllib b.mtl\n";
    for (int i = 0; i < 200; ++i) big << "v " << i << " 0 0\nv " << i << " 1 0\nv " << i + 1 << " 1 0\nvt 0 0\n";
    big << "usemtl m\n";
    for (int i = 0; i < 200; ++i) big << "f " << 3 * i + 1 << "/1 " << 3 * i + 2 << "/1 " << 3 * i + 3 << "/1" << (i < 199 ? "\n" : "");
    big.close();
    ASSERT_GT(std::filesystem::file_size(dir.file("big.obj")), 4096u);
    EXPECT_EQ(readMesh(dir.file("big.obj")).piece.mesh.triangleCount(), 200u);
}

// A textured material with a face without `vt`: an unusable texture under the textures rule (a
// warning apart from it, which --strict let pass, until stop 46). Faces without `vt` of an
// untextured material or of none leave the other materials' textures (until stop 51 they left every
// material of the file untextured).
TEST(ReadObj, FacesWithoutTextureCoordinatesMakeTheirTextureUnusable) {
    TempDir dir;
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    std::ofstream(dir.file("b.mtl")) << "newmtl m\nKd 1 1 1\nmap_Kd a.png\n";
    std::ofstream(dir.file("b.obj")) << "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                        "usemtl m\nf 1/1 2/2 3/3\nf 1 3 4\n";
    const SourceMesh s = readMesh(dir.file("b.obj"));
    const std::string what = dir.file("b.obj") + ": texture '" + std::filesystem::canonical(dir.file("a.png")).string() +
                             "' cannot be mapped: not every face of material 'm' has texture coordinates";
    ASSERT_EQ(s.stats.textureProblems.size(), 1u);
    EXPECT_EQ(s.stats.textureProblems[0].what, what);
    EXPECT_TRUE(s.materials[s.piece.materials[0]].texturePath.empty());
    const RunResult strict = runHlod({"build", dir.file("b.obj"), "-o", dir.file("b.hlod"), "--strict"});
    EXPECT_EQ(strict.exitCode, 2) << strict.outAndErr();
    EXPECT_EQ(strict.err, "hlod build: " + what + " (--strict)\n");

    std::ofstream(dir.file("b.mtl")) << "newmtl m\nKd 1 1 1\nmap_Kd a.png\nnewmtl plain\nKd 1 0 0\n";
    std::ofstream(dir.file("c.obj")) << "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                        "f 1 2 4\nusemtl m\nf 1/1 2/2 3/3\nusemtl plain\nf 1 3 4\n";
    const SourceMesh mixed = readMesh(dir.file("c.obj"));
    EXPECT_TRUE(mixed.stats.textureProblems.empty());
    ASSERT_EQ(mixed.piece.mesh.triangleCount(), 3u);
    EXPECT_EQ(mixed.materials[mixed.piece.materials[1]].texturePath, std::filesystem::canonical(dir.file("a.png")).string());
    const MeshData& m = mixed.piece.mesh;
    auto uv = [&m](uint32_t t, int c) { return std::pair{m.texcoords[2 * m.indices[3 * t + c]], m.texcoords[2 * m.indices[3 * t + c] + 1]}; };
    EXPECT_EQ(uv(1, 2), (std::pair{1.0f, 0.0f}));  // vt 1 1, v flipped
    EXPECT_EQ(uv(0, 1), (std::pair{0.0f, 0.0f}));  // no vt: (0, 0)
    EXPECT_EQ(uv(2, 0), (std::pair{0.0f, 0.0f}));
    EXPECT_EQ(runHlod({"build", dir.file("c.obj"), "-o", dir.file("c.hlod"), "--strict"}).exitCode, 0);
}

// `map_Kd -s su sv -o ou ov` looks the texture up at (u su + ou, v sv + ov) (MTL specification;
// warned of and not applied until stop 51): texcoords are stored v-down (1 - v). A vt that a moving
// and a still material share becomes two vertices; a number not finite or beyond ±1000 leaves the
// material untextured (the textures rule).
TEST(ReadObj, TextureScaleAndOffsetMoveTheTextureCoordinates) {
    TempDir dir;
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    std::ofstream(dir.file("b.obj")) << "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                        "usemtl m\nf 1/1 2/2 3/3\nusemtl still\nf 1/1 3/3 4/4\n";
    auto uvOf = [](const SourceMesh& m, uint32_t triangle, int corner) {
        const uint32_t v = m.piece.mesh.indices[3 * triangle + corner];
        return std::pair{m.piece.mesh.texcoords[2 * v], m.piece.mesh.texcoords[2 * v + 1]};
    };
    struct Case {
        std::string options;
        float u, v;  // where vt (1, 1) of the moving material's triangle lands, OBJ's v up
    };
    // "-o 0 0.25": the MTL specification lets v and w out (tinyobjloader took the file for w, the
    // texture lost without a word until stop 47).
    for (const Case& c : {Case{"-s 0.5 2 1", 0.5f, 2}, Case{"-o 0 0.25", 1, 1.25f}, Case{"-s 2 -o 0.25 0.5 0", 2.25f, 1.5f},
                          Case{"-s -1 1 -o 1", 0, 1}, Case{"-s 1 500 -o 0 600", 1, 1100}, Case{"-s 1 1 1 -o 0 0 0", 1, 1}}) {
        std::ofstream(dir.file("b.mtl")) << "newmtl m\nmap_Kd " << c.options << " a.png\nnewmtl still\nmap_Kd a.png\n";
        const SourceMesh m = readMesh(dir.file("b.obj"));
        EXPECT_TRUE(m.stats.warnings.empty() && m.stats.textureProblems.empty()) << c.options;
        EXPECT_FALSE(m.materials[m.piece.materials[0]].texturePath.empty()) << c.options;
        const auto [u, v] = uvOf(m, 0, 2);
        EXPECT_FLOAT_EQ(u, c.u) << c.options;
        EXPECT_FLOAT_EQ(1 - v, c.v) << c.options;
        // The still material's corner on the same vt is where vt says.
        EXPECT_EQ(uvOf(m, 1, 1), (std::pair{1.0f, 0.0f})) << c.options;
        const bool moves = c.u != 1 || c.v != 1;
        EXPECT_EQ(m.piece.mesh.vertexCount(), moves ? 6u : 4u) << c.options;
    }
    // The numbers as written are checked, both axes before either is taken (a refused v left u moved).
    for (const std::string bad : {"-s nan 1", "-o 0 inf", "-s 1001", "-o 0 -2000", "-s 2 1 -o 0 2000"}) {
        std::ofstream(dir.file("b.mtl")) << "newmtl m\nmap_Kd " << bad << " a.png\nnewmtl still\nmap_Kd a.png\n";
        const SourceMesh m = readMesh(dir.file("b.obj"));
        EXPECT_TRUE(m.materials[m.piece.materials[0]].texturePath.empty()) << bad;
        ASSERT_EQ(m.stats.textureProblems.size(), 1u) << bad;
        EXPECT_EQ(m.stats.textureProblems[0].what, std::filesystem::canonical(dir.file("b.mtl")).string() +
                                                       ": material 'm': map_Kd -s/-o beyond ±1000 or not a number") << bad;
        EXPECT_EQ(uvOf(m, 0, 2), (std::pair{1.0f, 0.0f})) << bad;
    }
    // Lines ended by CR alone (old Mac tools), as tinyobjloader reads them.
    std::ofstream(dir.file("b.mtl")) << "newmtl m\rKd 1 1 1\rmap_Kd -o 0 0.25 a.png\rnewmtl still\r";
    const SourceMesh cr = readMesh(dir.file("b.obj"));
    EXPECT_EQ(cr.materials[cr.piece.materials[0]].texturePath, std::filesystem::canonical(dir.file("a.png")).string());
    // Options without a file: an unusable texture (the textures rule), not an untextured material without a word.
    std::ofstream(dir.file("b.mtl")) << "newmtl m\nmap_Kd -o 0 0.25\nnewmtl still\n";
    const SourceMesh none = readMesh(dir.file("b.obj"));
    EXPECT_TRUE(none.materials[none.piece.materials[0]].texturePath.empty());
    ASSERT_EQ(none.stats.textureProblems.size(), 1u);
    EXPECT_EQ(none.stats.textureProblems[0].what, std::filesystem::canonical(dir.file("b.mtl")).string() +
                                                      ": material 'm': map_Kd names no texture file");
}

// A line whose first word is no OBJ statement (`F` for `f`, control bytes) is counted and said once
// with the first one's line (skipped without a word until stop 46); the statements hlod does not draw
// (groups, smoothing) and comments are skipped quietly.
TEST(ReadObj, LinesOfNoStatementAreWarnedOfOnce) {
    TempDir dir;
    std::ofstream(dir.file("j.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n# c\ng part\ns 1\no thing\nf 1 2 3\nF 2 4 3\n\x01\x02 x\n";
    const SourceMesh m = readMesh(dir.file("j.obj"));
    EXPECT_EQ(m.piece.mesh.triangleCount(), 1u);
    ASSERT_EQ(m.stats.warnings.size(), 1u);
    EXPECT_EQ(m.stats.warnings[0], dir.file("j.obj") + ":10: 2 lines skipped whose first word is no OBJ statement (the first: 'F')");
}

// The OBJ specification's line continuation: a `\` at a line's end (before blanks or a CR) joins
// the next line, across the reader's 4 KiB first read too; a comment ending in `\` (a Windows
// folder), whole or after the data, does not swallow the line after it.
TEST(ReadObj, ABackslashContinuesALine) {
    TempDir dir;
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    std::ofstream(dir.file("b.mtl")) << "newmtl m\nKd 1 1 1\nmap_Kd a.png\n";
    std::ofstream plain(dir.file("plain.obj")), continued(dir.file("continued.obj"));
    plain << "mtllib b.mtl\n", continued << "mtllib b.mtl\n";
    for (int i = 0; i < 200; ++i) {
        plain << "v " << i << " 0 0\nv " << i << " 1 0\nv " << i + 1 << " 1 0\nvt 0 0\n";
        continued << "v " << i << " \\\n0 0\nv " << i << " 1 0\nv " << i + 1 << " 1 \\ \r\n 0\nvt 0 0\n";
    }
    plain << "usemtl m\n", continued << "# from C:\\scans\\\ng part # in C:\\scans\\\nusemtl m\n";
    for (int i = 0; i < 200; ++i) {
        plain << "f " << 3 * i + 1 << "/1 " << 3 * i + 2 << "/1 " << 3 * i + 3 << "/1\n";
        continued << "f " << 3 * i + 1 << "/1 \\\n" << 3 * i + 2 << "/1\t\\\n  " << 3 * i + 3 << "/1" << (i < 199 ? "\n" : " \\");
    }
    plain.close(), continued.close();
    ASSERT_GT(std::filesystem::file_size(dir.file("continued.obj")), 4096u);
    const SourceMesh a = readMesh(dir.file("plain.obj")), b = readMesh(dir.file("continued.obj"));
    EXPECT_EQ(b.piece.mesh.triangleCount(), 200u);
    EXPECT_EQ(a.piece.mesh.positions, b.piece.mesh.positions);
    EXPECT_EQ(a.piece.mesh.indices, b.piece.mesh.indices);
    EXPECT_EQ(a.piece.mesh.texcoords, b.piece.mesh.texcoords);
    EXPECT_EQ(b.piece.materials, std::vector<uint32_t>(200, a.piece.materials[0]));
    EXPECT_FALSE(b.materials[b.piece.materials[0]].texturePath.empty());  // `usemtl m` was read
    // An error in a line a final `\` continued names the last line there is.
    std::ofstream(dir.file("end.obj")) << "v 0 0 0\nv 1 0 0\nf 1 \\\n2 \\\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("end.obj")); }).find("end.obj:4: truncated or corrupt OBJ (face with fewer than 3"),
              std::string::npos)
        << errorOf([&] { readMesh(dir.file("end.obj")); });
}

// Names with spaces, as exporters write them unescaped: the library `my lib.mtl` (not `my` and
// `lib.mtl`), the material `my material` (as tinyobjloader reads its `newmtl`), the texture.
TEST(ReadObj, NamesWithSpaces) {
    TempDir dir;
    writeFile(dir.file("my tex.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    std::ofstream(dir.file("s.obj")) << "mtllib my lib.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                        "usemtl my material\nf 1/1 2/2 3/3\n";
    std::ofstream(dir.file("my lib.mtl")) << "newmtl my material\nKd 1 1 1\nmap_Kd my tex.png\n";
    const SourceMesh s = readMesh(dir.file("s.obj"));
    EXPECT_TRUE(s.stats.textureProblems.empty());
    EXPECT_TRUE(s.stats.warnings.empty());
    ASSERT_EQ(s.piece.materials.size(), 1u);
    EXPECT_EQ(s.materials[s.piece.materials[0]].texturePath, std::filesystem::canonical(dir.file("my tex.png")).string());
}

// One mesh (positions, TEXCOORD_0, uint32 indices in a data-URI buffer) instanced by a node
// translated by (10, 0, 0) whose child is scaled by 2 (or by the node tree `nodes`, root node 0).
const nlohmann::json kTwoNodes = {{{"translation", {10, 0, 0}}, {"children", {1}}}, {{"scale", {2, 2, 2}}, {"mesh", 0}}};
void writeGltf(const std::string& path, const MeshData& m, const nlohmann::json& nodes = kTwoNodes) {
    std::vector<uint8_t> buffer;
    auto append = [&](const void* p, size_t n) { buffer.insert(buffer.end(), (const uint8_t*)p, (const uint8_t*)p + n); };
    append(m.positions.data(), m.positions.size() * 4);
    append(m.texcoords.data(), m.texcoords.size() * 4);
    append(m.indices.data(), m.indices.size() * 4);
    const size_t vc = m.vertexCount(), p = vc * 12, t = vc * 8;
    const Box3f b = pieceBounds(m);
    nlohmann::json j = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", nodes},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}}}}}}},
        {"buffers", {{{"byteLength", buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(buffer)}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", p}},
                         {{"buffer", 0}, {"byteOffset", p}, {"byteLength", t}},
                         {{"buffer", 0}, {"byteOffset", p + t}, {"byteLength", m.indices.size() * 4}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", vc}, {"type", "VEC3"},
                        {"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}},
                       {{"bufferView", 1}, {"componentType", 5126}, {"count", vc}, {"type", "VEC2"}},
                       {{"bufferView", 2}, {"componentType", 5125}, {"count", m.indices.size()}, {"type", "SCALAR"}}}}};
    std::ofstream(path) << j.dump();
}

TEST(ReadGltf, NodeTransformsAreApplied) {
    TempDir dir;
    const Piece p = terrain(6);
    writeGltf(dir.file("t.gltf"), p.mesh);
    const SourceMesh s = readMesh(dir.file("t.gltf"));
    ASSERT_EQ(s.piece.mesh.indices, p.mesh.indices);
    for (size_t i = 0; i < p.mesh.vertexCount(); ++i) {
        EXPECT_FLOAT_EQ(s.piece.mesh.positions[3 * i], 10 + 2 * p.mesh.positions[3 * i]);
        EXPECT_FLOAT_EQ(s.piece.mesh.positions[3 * i + 1], 2 * p.mesh.positions[3 * i + 1]);
    }
    EXPECT_TRUE(s.piece.mesh.texcoords.empty());  // no textured material: UVs dropped
}

// Node trees: a chain deeper than the 64 levels once allowed is read; a node reached twice (here
// 40 levels of a node whose two children are the same node: 2^40 visits before) and a chain
// deeper than 1,000 levels are refused, each in one line.
TEST(ReadGltf, NodeTreesMustBeStrictTreesOfAtMostAThousandLevels) {
    TempDir dir;
    const Piece p = terrain(2);
    const auto chain = [](int length, bool shared) {
        nlohmann::json nodes = nlohmann::json::array();
        for (int i = 0; i < length; ++i)
            nodes.push_back({{"children", shared ? nlohmann::json{i + 1, i + 1} : nlohmann::json{i + 1}}});
        nodes.push_back({{"mesh", 0}});
        return nodes;
    };
    writeGltf(dir.file("deep.gltf"), p.mesh, chain(100, false));
    EXPECT_EQ(readMesh(dir.file("deep.gltf")).piece.mesh.triangleCount(), p.mesh.triangleCount());
    writeGltf(dir.file("shared.gltf"), p.mesh, chain(40, true));
    EXPECT_EQ(errorOf([&] { readMesh(dir.file("shared.gltf")); }),
              dir.file("shared.gltf") + ": node 1 is reached twice (glTF node trees are strict trees)");
    writeGltf(dir.file("deeper.gltf"), p.mesh, chain(1001, false));
    EXPECT_EQ(errorOf([&] { readMesh(dir.file("deeper.gltf")); }),
              dir.file("deeper.gltf") + ": node tree deeper than 1000 levels (not supported)");
}

TEST(BadInput, MissingFile) {
    EXPECT_NE(errorOf([] { readMesh("/nonexistent/x.ply"); }).find("/nonexistent/x.ply: no such file"), std::string::npos);
}

TEST(BadInput, UnsupportedFormat) {
    TempDir dir;
    writeFile(dir.file("x.stl"), {1, 2, 3});
    EXPECT_NE(errorOf([&] { readMesh(dir.file("x.stl")); }).find("unsupported format"), std::string::npos);
}

TEST(BadInput, TruncatedPly) {
    TempDir dir;
    for (bool binary : {false, true}) {
        writePly(dir.file("t.ply"), terrain(6).mesh, binary);
        std::vector<uint8_t> bytes = readFile(dir.file("t.ply"));
        bytes.resize(bytes.size() * 3 / 4);
        writeFile(dir.file("t.ply"), bytes);
        EXPECT_NE(errorOf([&] { readMesh(dir.file("t.ply")); }).find("truncated PLY"), std::string::npos) << binary;
    }
}

TEST(BadInput, CorruptPlyHeader) {
    TempDir dir;
    std::ofstream(dir.file("c.ply")) << "ply\nformat ascii 1.0\nelement vertex lots\nend_header\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("c.ply")); }).find("corrupt PLY header"), std::string::npos);
    std::ofstream(dir.file("d.ply")) << "solid x\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("d.ply")); }).find("not a PLY file"), std::string::npos);
}

TEST(BadInput, NaNCoordinate) {
    TempDir dir;
    std::ofstream(dir.file("n.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("n.ply")); }).find("vertex 1 has a NaN/Inf coordinate"), std::string::npos);
    // A finite coordinate beyond kMaxCoordinate overflows float areas: refused too (stop 36).
    std::ofstream(dir.file("h.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n1 -3e37 0\n0 1 0\n3 0 1 2\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("h.ply")); }).find("h.ply: vertex 1 has a coordinate beyond 1e15 (the limit)"),
              std::string::npos)
        << errorOf([&] { readMesh(dir.file("h.ply")); });
}

// Found by fuzz_ply (issue #15): a NaN float colour, face count or index was cast to an integer
// (undefined behaviour) instead of being refused.
TEST(BadInput, NaNColourFaceCountOrIndex) {
    TempDir dir;
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\n";
    std::ofstream(dir.file("c.ply")) << header << "property float red\nproperty float green\nproperty float blue\n"
                                     << "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                     << "0 0 0 1 1 1\n1 0 0 nan 1 1\n0 1 0 1 1 1\n3 0 1 2\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("c.ply")); }).find("a vertex colour is not a number"), std::string::npos);
    std::ofstream(dir.file("n.ply")) << header << "element face 1\nproperty list float int vertex_indices\nend_header\n"
                                     << "0 0 0\n1 0 0\n0 1 0\nnan 0 1 2\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("n.ply")); }).find("corrupt PLY (face with"), std::string::npos);
    std::ofstream(dir.file("i.ply")) << header << "element face 1\nproperty list uchar float vertex_indices\nend_header\n"
                                     << "0 0 0\n1 0 0\n0 1 0\n3 0 nan 2\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("i.ply")); }).find("out of range"), std::string::npos);
}

TEST(BadInput, OutOfRangeIndex) {
    TempDir dir;
    std::ofstream(dir.file("i.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("i.ply")); }).find("uses vertex 7 but there are only 3"), std::string::npos);
    // Until stop 44: a float index 1.5 was read as 1, an index of 2^32 printed as 4294967296.000000,
    // a duplicated property or a format version 2.0 went unremarked.
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string points = "0 0 0\n1 0 0\n0 1 0\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {head + "element face 1\nproperty list uchar float vertex_indices\nend_header\n" + points + "3 0 1.5 2\n",
         ": vertex index 1.5 is not a whole number"},
        {head + "element face 1\nproperty list uchar double vertex_indices\nend_header\n" + points + "3 0 4294967296 2\n",
         ": vertex index 4294967296 out of range"},
        {head + "property float x\nend_header\n" + points, ": corrupt PLY header (property 'x' twice in element 'vertex')"},
        {"ply\nformat ascii 2.0\nelement vertex 0\nend_header\n", ": unsupported PLY format version '2.0' (1.0 is read)"}};
    for (const auto& [text, problem] : cases) {
        std::ofstream(dir.file("k.ply")) << text;
        EXPECT_EQ(errorOf([&] { readMesh(dir.file("k.ply")); }), dir.file("k.ply") + problem);
    }
    std::ofstream(dir.file("w.ply")) << head << "element face 1\nproperty list uchar float vertex_indices\nend_header\n" << points << "3 0 1 2\n";
    EXPECT_EQ(readMesh(dir.file("w.ply")).piece.mesh.triangleCount(), 1u);  // whole floats are indices
    std::ofstream(dir.file("i.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("i.obj")); }), "");
}

TEST(BadInput, DegenerateTrianglesAreDroppedAndCounted) {
    TempDir dir;
    std::ofstream(dir.file("g.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 1 2 4\n";
    const SourceMesh s = readMesh(dir.file("g.obj"));
    EXPECT_EQ(s.piece.mesh.triangleCount(), 1u);
    EXPECT_EQ(s.stats.degenerateDropped, 2u);  // repeated vertex; collinear (zero area)
}

TEST(BadInput, EmptyMesh) {
    TempDir dir;
    std::ofstream(dir.file("e.obj")) << "# nothing\nv 0 0 0\n";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("e.obj")); }).find("empty mesh"), std::string::npos);
}

TEST(BadInput, MissingTextureIsAWarningAndUntextured) {
    TempDir dir;
    writeObj(dir.file("m.obj"), terrain(4), "nothere.jpg");
    const SourceMesh s = readMesh(dir.file("m.obj"));
    ASSERT_FALSE(s.stats.textureProblems.empty());
    EXPECT_NE(s.stats.textureProblems[0].what.find("texture '"), std::string::npos);
    EXPECT_NE(s.stats.textureProblems[0].what.find("nothere.jpg' is missing"), std::string::npos);
    for (const Material& m : s.materials) EXPECT_TRUE(m.texturePath.empty());
}

TEST(BadInput, TextureOutsideTheInputFolderIsRefused) {
    TempDir dir;
    std::filesystem::create_directories(dir.path / "in");
    writeObj(dir.file("in/m.obj"), terrain(4), "../secret.png");
    EXPECT_NE(errorOf([&] { readMesh(dir.file("in/m.obj")); }).find("texture '../secret.png' has a '..' component"), std::string::npos);
}

TEST(BadInput, CorruptGltf) {
    TempDir dir;
    std::ofstream(dir.file("c.gltf")) << "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [";
    EXPECT_NE(errorOf([&] { readMesh(dir.file("c.gltf")); }).find("corrupt glTF"), std::string::npos);
    writeFile(dir.file("c.glb"), {'g', 'l', 'T', 'F', 2, 0, 0, 0});
    EXPECT_NE(errorOf([&] { readMesh(dir.file("c.glb")); }).find("corrupt glTF"), std::string::npos);
    // An OBJ named .gltf: said in words, without nlohmann's "[json.exception.parse_error.101]" (until stop 45).
    std::ofstream(dir.file("o.gltf")) << "# an OBJ\nv 0 0 0\n";
    const std::string obj = errorOf([&] { readMesh(dir.file("o.gltf")); });
    EXPECT_EQ(obj.rfind(dir.file("o.gltf") + ": corrupt glTF (not JSON: parse error at line 1, column 1: ", 0), 0u) << obj;
    EXPECT_EQ(obj.find("json.exception"), std::string::npos) << obj;
}

}  // namespace
}  // namespace hlod::test
