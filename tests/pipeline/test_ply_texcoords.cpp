// Textured PLY as MeshLab and Agisoft Metashape write it: texture coordinates per face (a
// `texcoord` list of 2 n floats), several textures named by `comment TextureFile` lines and
// chosen per face by `texnumber`. Read like the same OBJ, welded per (vertex, UV), built
// textured, and every malformed face named.
#include "helpers.h"

#include "tests/support/run_hlod.h"

namespace hlod::test {
namespace {

// `p` as a textured PLY: per-vertex x, y, z (and red, green, blue), per-face vertex_indices,
// texcoord (v flipped back, as OBJ) and texnumber = the triangle's material.
void writeFaceTexcoordPly(const std::string& path, const Piece& p, const std::vector<std::string>& textures, bool binary,
                          bool colors = false) {
    const MeshData& m = p.mesh;
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n";
    for (const std::string& t : textures) out << "comment TextureFile " << t << "\n";
    out << "element vertex " << m.vertexCount() << "\nproperty float x\nproperty float y\nproperty float z\n"
        << (colors ? "property uchar red\nproperty uchar green\nproperty uchar blue\n" : "") << "element face " << m.triangleCount()
        << "\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nproperty int texnumber\nend_header\n";
    auto put = [&](const auto& value) {
        if (binary) out.write(reinterpret_cast<const char*>(&value), sizeof value);
        else out << +value << " ";
    };
    for (size_t i = 0; i < m.vertexCount(); ++i) {
        for (int c = 0; c < 3; ++c) put(m.positions[3 * i + c]);
        for (int c = 0; colors && c < 3; ++c) put(static_cast<uint8_t>(i * 37 + c * 91));
        if (!binary) out << "\n";
    }
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        put(uint8_t{3});
        for (int k = 0; k < 3; ++k) put(static_cast<int32_t>(m.indices[3 * t + k]));
        put(uint8_t{6});
        for (int k = 0; k < 3; ++k) put(m.texcoords[2 * m.indices[3 * t + k]]), put(1.0f - m.texcoords[2 * m.indices[3 * t + k] + 1]);
        put(static_cast<int32_t>(p.materials[t]));
        if (!binary) out << "\n";
    }
}

void writeTextures(TempDir& dir) {
    writeFile(dir.file("a.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    writeFile(dir.file("b.png"), encodeTexture(testImage(8, 8), Codec::Png).bytes);
}

TEST(PlyFaceTexcoords, ReadAsTheSameObjIsRead) {
    const Piece p = terrain(8, 100, true);
    for (const bool binary : {false, true}) {
        SCOPED_TRACE(binary ? "binary" : "ascii");
        TempDir dir;
        writeTextures(dir);
        writeFaceTexcoordPly(dir.file("m.ply"), p, {"a.png", "b.png"}, binary, true);
        writeObj(dir.file("m.obj"), p, "a.png");
        const SourceMesh s = readMesh(dir.file("m.ply")), obj = readMesh(dir.file("m.obj"));
        const MeshData& m = s.piece.mesh;
        // Welded per (vertex, UV): the terrain has no seam, so one vertex each, as the OBJ.
        ASSERT_EQ(m.vertexCount(), p.mesh.vertexCount());
        EXPECT_EQ(m.indices, obj.piece.mesh.indices);
        ASSERT_EQ(m.texcoords.size(), obj.piece.mesh.texcoords.size());
        for (size_t i = 0; i < m.texcoords.size(); ++i) ASSERT_NEAR(m.texcoords[i], obj.piece.mesh.texcoords[i], 1e-5f) << i;
        EXPECT_EQ(s.piece.materials, p.materials);
        ASSERT_EQ(s.materials.size(), 2u);
        EXPECT_EQ(s.materials[0].texturePath, std::filesystem::canonical(dir.file("a.png")).string());
        EXPECT_EQ(s.materials[1].texturePath, std::filesystem::canonical(dir.file("b.png")).string());
        ASSERT_EQ(m.colors.size(), 4 * m.vertexCount());  // the vertices' colours follow their corners
        for (size_t c = 0; c < m.indices.size(); ++c)
            EXPECT_EQ(m.colors[4 * m.indices[c]], static_cast<uint8_t>(p.mesh.indices[c] * 37)) << "corner " << c;
    }
}

// A tiny budget: the parsed arrays (each corner's texture coordinate among them) go to spill
// files at once, and the mesh read back from them is the one read in memory.
TEST(PlyFaceTexcoords, ASpilledParseReadsTheSame) {
    TempDir dir;
    writeTextures(dir);
    writeFaceTexcoordPly(dir.file("m.ply"), terrain(16, 100, true), {"a.png", "b.png"}, true, true);
    RawMesh raw;
    raw.spillBeyond(1024, dir.file(""));
    parsePly(dir.file("m.ply"), raw);
    EXPECT_TRUE(raw.positions.spilled());
    const SourceMesh spilled = toSourceMesh(raw, "m.ply"), read = readMesh(dir.file("m.ply"));
    EXPECT_EQ(spilled.piece.mesh.positions, read.piece.mesh.positions);
    EXPECT_EQ(spilled.piece.mesh.texcoords, read.piece.mesh.texcoords);
    EXPECT_EQ(spilled.piece.mesh.colors, read.piece.mesh.colors);
    EXPECT_EQ(spilled.piece.mesh.indices, read.piece.mesh.indices);
    EXPECT_EQ(spilled.piece.materials, read.piece.materials);
}

TEST(PlyFaceTexcoords, ASeamVertexIsSplitOncePerUv) {
    // Four triangles around vertex 4; the two on the left give it u = 0.1, the two on the right 0.9.
    TempDir dir;
    std::ofstream(dir.file("s.ply")) << "ply\nformat ascii 1.0\ncomment TextureFile a.png\nelement vertex 5\n"
                                        "property float x\nproperty float y\nproperty float z\nelement face 4\n"
                                        "property list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n"
                                        "0 0 0\n2 0 0\n2 2 0\n0 2 0\n1 1 0\n"
                                        "3 0 1 4 6 0.1 0 0.9 0 0.1 0.5\n3 1 2 4 6 0.9 0 0.9 1 0.9 0.5\n"
                                        "3 2 3 4 6 0.9 1 0.1 1 0.9 0.5\n3 3 0 4 6 0.1 1 0.1 0 0.1 0.5\n";
    writeTextures(dir);
    const SourceMesh s = readMesh(dir.file("s.ply"));
    EXPECT_EQ(s.piece.mesh.triangleCount(), 4u);
    // Each corner vertex meets one UV in both its faces; vertex 4 meets two: 4 + 2 = 6 vertices,
    // not the 12 of one per corner.
    EXPECT_EQ(s.piece.mesh.vertexCount(), 6u);
    EXPECT_TRUE(s.stats.warnings.empty());
    // A corner's u = -0 is the other corner's u = 0: the two triangles share their edge's vertices.
    std::ofstream(dir.file("z.ply")) << "ply\nformat ascii 1.0\ncomment TextureFile a.png\nelement vertex 4\n"
                                        "property float x\nproperty float y\nproperty float z\nelement face 2\n"
                                        "property list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n"
                                        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                        "3 0 1 2 6 0 0 1 0 1 1\n3 0 2 3 6 -0 0 1 1 -0 1\n";
    const SourceMesh z = readMesh(dir.file("z.ply"));
    EXPECT_EQ(z.piece.mesh.vertexCount(), 4u);
}

TEST(PlyFaceTexcoords, BuildIsTexturedLikeTheObj) {
    TempDir dir;
    writeTextures(dir);
    const Piece p = terrain(20, 100, true);
    writeFaceTexcoordPly(dir.file("m.ply"), p, {"a.png", "a.png"}, false);
    writeObj(dir.file("m.obj"), p, "a.png");
    for (const char* input : {"m.ply", "m.obj"}) {
        const RunResult r = runHlod({"build", dir.file(input), "-o", dir.file(std::string(input) + ".hlod"), "--strict",
                                     "--set", "c_desiredTris=200"});
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    }
    const Database ply = Database::open(dir.file("m.ply.hlod")), obj = Database::open(dir.file("m.obj.hlod"));
    ASSERT_EQ(ply.skeleton().nodes.size(), obj.skeleton().nodes.size());
    for (size_t n = 0; n < ply.skeleton().nodes.size(); ++n) {
        EXPECT_GT(ply.skeleton().nodes[n].texturedTriangles, 0u) << "node " << n;
        EXPECT_EQ(ply.skeleton().nodes[n].texturedTriangles, obj.skeleton().nodes[n].texturedTriangles) << "node " << n;
    }
}

TEST(PlyFaceTexcoords, ATextureFileNameMayHoldSpaces) {
    TempDir dir;
    writeFile(dir.file("my atlas.png"), encodeTexture(testImage(16, 16), Codec::Png).bytes);
    writeFaceTexcoordPly(dir.file("m.ply"), terrain(4, 100, true), {"my atlas.png"}, false);  // texnumber 0 and 1
    const SourceMesh s = readMesh(dir.file("m.ply"));
    EXPECT_TRUE(s.stats.textureProblems.empty());
    EXPECT_EQ(s.materials[0].texturePath, std::filesystem::canonical(dir.file("my atlas.png")).string());
    // With one TextureFile line there is one texture: `texnumber` is not read.
    EXPECT_EQ(s.piece.materials, std::vector<uint32_t>(s.piece.mesh.triangleCount(), 0u));
}

TEST(PlyFaceTexcoords, BadFacesSayWhich) {
    const std::string vertices = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string faces = "element face 1\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n";
    const std::string points = "0 0 0\n1 0 0\n0 1 0\n";
    struct Case {
        const char* label;
        std::string text, error;
    } cases[] = {
        {"texcoord count", "ply\nformat ascii 1.0\n" + vertices + faces + "end_header\n" + points + "3 0 1 2 4 0 0 1 0\n",
         "t.ply: corrupt PLY (face 0 has 3 vertices but 4 texture coordinate values)"},
        {"texnumber beyond the textures",
         "ply\nformat ascii 1.0\ncomment TextureFile a.png\ncomment TextureFile b.png\n" + vertices + faces +
             "property int texnumber\nend_header\n" + points + "3 0 1 2 6 0 0 1 0 0 1 2\n",
         "t.ply: face 0 uses texture 2 but the header names 2 (comment TextureFile)"},
        {"fractional texnumber",
         "ply\nformat ascii 1.0\ncomment TextureFile a.png\ncomment TextureFile b.png\n" + vertices + faces +
             "property float texnumber\nend_header\n" + points + "3 0 1 2 6 0 0 1 0 0 1 0.5\n",
         "t.ply: face 0 uses texture 0.5 but the header names 2 (comment TextureFile)"},
        {"vertex out of range", "ply\nformat ascii 1.0\n" + vertices + faces + "end_header\n" + points + "3 0 1 7 6 0 0 1 0 0 1\n",
         "t.ply: face 0 uses vertex 7 but there are only 3"},
        {"faces first", "ply\nformat ascii 1.0\n" + faces + vertices + "end_header\n3 0 1 2 6 0 0 1 0 0 1\n" + points,
         "t.ply: unsupported PLY (face texture coordinates without vertices before them)"},
        {"texcoord list past its cap", "ply\nformat ascii 1.0\n" + vertices + faces + "end_header\n" + points + "3 0 1 2 2049 0\n",
         "t.ply: corrupt PLY (face with 2049 texcoord values)"},
        {"NaN texcoord", "ply\nformat ascii 1.0\n" + vertices + faces + "end_header\n" + points + "3 0 1 2 6 0 0 nan 0 0 1\n",
         "t.ply: face 0 has a NaN/Inf texture coordinate"},
        {"two face elements", "ply\nformat ascii 1.0\n" + vertices + faces + faces + "end_header\n" + points +
             "3 0 1 2 6 0 0 1 0 0 1\n3 0 1 2 6 0 0 1 0 0 1\n", "t.ply: unsupported PLY (two face elements)"},
        {"texcoord list cut short", "ply\nformat ascii 1.0\n" + vertices + faces + "end_header\n" + points + "3 0 1 2 255 0\n",
         ""},  // 255 values promised, 1 given: the file ends early
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.label);
        TempDir dir;
        writeTextures(dir);
        std::ofstream(dir.file("t.ply")) << c.text;
        const std::string error = errorOf([&] { readMesh(dir.file("t.ply")); });
        if (c.error.empty()) EXPECT_NE(error.find("t.ply: truncated PLY"), std::string::npos) << error;
        else EXPECT_NE(error.find(c.error), std::string::npos) << error;
    }
}

}  // namespace
}  // namespace hlod::test
