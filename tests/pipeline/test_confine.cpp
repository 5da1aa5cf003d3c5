// The one confinement rule (resolveReference, README "Reliability"): every file an input refers
// to — MTL libraries and textures, glTF images and buffers, the meshes of a folder input — must
// resolve (after symbolic links) inside the input's folder; absolute paths, '..' and links out
// are refused with one line naming the input and the reference, unless --allow-outside-input.
// data: URIs are not files and keep working.
#include "helpers.h"

#include "formats/codec.h"
#include "tests/support/run_hlod.h"

#include <sys/stat.h>

namespace hlod::test {
namespace {

namespace fs = std::filesystem;

const ReadOptions kAllow = [] {
    ReadOptions o;
    o.allowOutsideInput = true;
    return o;
}();


// A folder `in/` inside the test's folder, and a file outside it (`secret.bin`, `secret.png`).
struct Layout {
    TempDir dir;
    Layout() {
        fs::create_directories(dir.path / "in");
        writeFile(dir.file("secret.bin"), triangleBuffer());
        writeFile(dir.file("secret.png"), encodeTexture(testImage(4, 4), Codec::Png).bytes);
    }
    std::string in(const std::string& name) const { return dir.file("in/" + name); }
};

void expectRefused(const std::string& error, const std::string& input, const std::string& reference) {
    EXPECT_NE(error.find(input + ": "), std::string::npos) << error;
    EXPECT_NE(error.find("'" + reference + "'"), std::string::npos) << error;
    EXPECT_NE(error.find("(refused; --allow-outside-input allows it)"), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

TEST(Confine, MtlTextureDotDotAndAbsoluteRefusedUnlessAllowed) {
    Layout l;
    for (const std::string& texture : {std::string("../secret.png"), l.dir.file("secret.png")}) {
        writeObj(l.in("m.obj"), terrain(4), texture);
        expectRefused(errorOf([&] { readMesh(l.in("m.obj")); }), l.in("m.obj"), texture);
        const SourceMesh s = readMesh(l.in("m.obj"), kAllow);
        EXPECT_EQ(s.materials[0].texturePath, fs::canonical(l.dir.file("secret.png")).string());
    }
}

// References as Windows tools write them are found where this file system has them: backslash
// separators, another case, an absolute path to the exporter's disk (its name beside the input).
// Never outside: a backslashed '..' is not followed, and a name two files match is not guessed.
TEST(Confine, WindowsStyleReferencesAreFoundInsideTheFolderOnly) {
    Layout l;
    fs::create_directories(l.dir.path / "in" / "textures");
    const std::vector<uint8_t> png = encodeTexture(testImage(4, 4), Codec::Png).bytes;
    writeFile(l.in("textures/atlas_1.png"), png);
    writeFile(l.in("atlas_2.png"), png);
    writeFile(l.in("twin.png"), png), writeFile(l.in("TWIN.png"), png);
    struct Case {
        std::string reference, found;  // found: "" = left missing (the textures rule's warning)
    } cases[] = {
        {"textures\\atlas_1.png", l.in("textures/atlas_1.png")},
        {"Textures\\ATLAS_1.PNG", l.in("textures/atlas_1.png")},
        {"C:\\Users\\scan\\atlas_2.png", l.in("atlas_2.png")},
        {"Atlas_2.png", l.in("atlas_2.png")},
        {"..\\secret.png", ""},   // the name alone is tried, inside: there is none
        {"Twin.png", ""},          // twin.png and TWIN.png: not guessed
        {"lod1/atlas_2.png", ""},  // a POSIX path is not taken for another file of its name
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.reference);
        writeObj(l.in("m.obj"), terrain(4), c.reference);
        const SourceMesh s = readMesh(l.in("m.obj"));
        if (c.found.empty()) {
            ASSERT_FALSE(s.stats.textureProblems.empty());
            EXPECT_NE(s.stats.textureProblems[0].what.find("is missing"), std::string::npos) << s.stats.textureProblems[0].what;
            EXPECT_TRUE(s.materials[0].texturePath.empty());
        } else {
            EXPECT_TRUE(s.stats.textureProblems.empty());
            EXPECT_EQ(s.materials[0].texturePath, fs::canonical(c.found).string());
        }
    }
    fs::create_directory_symlink(l.dir.path, l.dir.path / "in" / "Link");  // a link out, found by its case
    writeObj(l.in("m.obj"), terrain(4), "link\\secret.png");
    expectRefused(errorOf([&] { readMesh(l.in("m.obj")); }), l.in("m.obj"), "link\\secret.png");
}

TEST(Confine, MaterialLibraryOutsideRefused) {
    Layout l;
    writeObj(l.dir.file("m.obj"), terrain(4), "");
    std::ofstream(l.in("m.obj")) << "mtllib ../m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    expectRefused(errorOf([&] { readMesh(l.in("m.obj")); }), l.in("m.obj"), "../m.mtl");
    EXPECT_EQ(readMesh(l.in("m.obj"), kAllow).piece.mesh.triangleCount(), 1u);
}

TEST(Confine, GltfImageOutsideRefused) {
    Layout l;
    writeFile(l.in("t.bin"), triangleBuffer());
    std::ofstream(l.in("t.gltf")) << triangleGltf("t.bin", "../secret.png");
    expectRefused(errorOf([&] { readMesh(l.in("t.gltf")); }), l.in("t.gltf"), "../secret.png");
    EXPECT_EQ(readMesh(l.in("t.gltf"), kAllow).materials[0].texturePath, fs::canonical(l.dir.file("secret.png")).string());
}

TEST(Confine, GltfBufferOutsideRefusedAndNeverRead) {
    Layout l;
    for (const std::string& uri : {std::string("../secret.bin"), std::string("../../../../etc/passwd"), l.dir.file("secret.bin")}) {
        std::ofstream(l.in("b.gltf")) << triangleGltf(uri);
        expectRefused(errorOf([&] { readMesh(l.in("b.gltf")); }), l.in("b.gltf"), uri);
    }
    std::ofstream(l.in("b.gltf")) << triangleGltf("../secret.bin");
    EXPECT_EQ(readMesh(l.in("b.gltf"), kAllow).piece.mesh.triangleCount(), 1u);
    // Inside the folder (also in a subfolder) a buffer is read as before.
    fs::create_directories(l.in("sub"));
    writeFile(l.in("sub/t.bin"), triangleBuffer());
    std::ofstream(l.in("b.gltf")) << triangleGltf("sub/t.bin");
    EXPECT_EQ(readMesh(l.in("b.gltf")).piece.mesh.triangleCount(), 1u);
}

TEST(Confine, SymbolicLinkOutRefused) {
    Layout l;
    fs::create_symlink(l.dir.file("secret.bin"), l.in("link.bin"));
    std::ofstream(l.in("b.gltf")) << triangleGltf("link.bin");
    const std::string error = errorOf([&] { readMesh(l.in("b.gltf")); });
    expectRefused(error, l.in("b.gltf"), "link.bin");
    EXPECT_NE(error.find("symbolic link"), std::string::npos) << error;
    EXPECT_EQ(readMesh(l.in("b.gltf"), kAllow).piece.mesh.triangleCount(), 1u);
    fs::create_symlink(l.dir.file("secret.png"), l.in("link.png"));
    writeObj(l.in("m.obj"), terrain(4), "link.png");
    expectRefused(errorOf([&] { readMesh(l.in("m.obj")); }), l.in("m.obj"), "link.png");
    // A link that stays inside the folder is fine.
    writeFile(l.in("real.png"), readFile(l.dir.file("secret.png")));
    fs::create_symlink("real.png", l.in("inside.png"));
    writeObj(l.in("m.obj"), terrain(4), "inside.png");
    EXPECT_EQ(readMesh(l.in("m.obj")).materials[0].texturePath, fs::canonical(l.in("real.png")).string());
}

// Found by fuzz_obj: a reference with a name longer than the file system allows made
// std::filesystem throw past the reader (a crash in `hlod build`); it is now an InputError. A
// control character in a reference (a glTF URI may hold "\n") keeps the error on one line.
TEST(Confine, UnresolvableOrMultiLineReferenceIsOneLineInputError) {
    Layout l;
    const std::string longName(300, 'x');
    std::ofstream(l.in("m.obj")) << "mtllib " << longName << "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    for (const ReadOptions& options : {ReadOptions{}, kAllow})
        EXPECT_EQ(errorOf([&] { readMesh(l.in("m.obj"), options); }),
                  l.in("m.obj") + ": material library '" + longName + "' cannot be resolved (File name too long)");
    std::ofstream(l.in("n.gltf")) << triangleGltf("../a\\nb.bin");
    expectRefused(errorOf([&] { readMesh(l.in("n.gltf")); }), l.in("n.gltf"), "../a?b.bin");
}

TEST(Confine, DataUrisKeepWorking) {
    Layout l;
    const std::string png = "data:image/png;base64," + base64(encodeTexture(testImage(4, 4), Codec::Png).bytes);
    std::ofstream(l.in("d.gltf")) << triangleGltf(triangleBufferDataUri(), png);
    const SourceMesh s = readMesh(l.in("d.gltf"));
    EXPECT_EQ(s.piece.mesh.triangleCount(), 1u);
    ASSERT_TRUE(s.materials[0].image);
    EXPECT_EQ(s.materials[0].image->width, 4u);
}

TEST(Confine, BuildRefusesFolderMeshLinkedOutUnlessAllowed) {
    Layout l;
    fs::create_directories(l.dir.path / "blocks");
    writePly(l.dir.file("blocks/a.ply"), terrain(4).mesh, true);
    writePly(l.dir.file("elsewhere.ply"), terrain(4).mesh, true);
    fs::create_symlink(l.dir.file("elsewhere.ply"), l.dir.file("blocks/b.ply"));
    const RunResult r = runHlod({"build", l.dir.file("blocks"), "-o", l.dir.file("x.hlod")});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_NE(r.outAndErr().find("hlod build: " + l.dir.file("blocks") + ": mesh 'b.ply' resolves outside the input's folder"),
              std::string::npos)
        << r.outAndErr();
    EXPECT_FALSE(fs::exists(l.dir.file("x.hlod")));
    const RunResult ok = runHlod({"build", l.dir.file("blocks"), "-o", l.dir.file("x.hlod"), "--allow-outside-input"});
    EXPECT_EQ(ok.exitCode, 0) << ok.outAndErr();
}

TEST(Confine, BuildRefusesOutsideTextureWithOneLine) {
    Layout l;
    writeObj(l.in("m.obj"), terrain(4), l.dir.file("secret.png"));
    const RunResult r = runHlod({"build", l.in("m.obj"), "-o", l.dir.file("m.hlod")});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_NE(r.err.find("hlod build: " + l.in("m.obj") + ": texture '" + l.dir.file("secret.png") + "' is an absolute path"),
              std::string::npos)
        << r.outAndErr();
    const RunResult ok = runHlod({"build", l.in("m.obj"), "-o", l.dir.file("m.hlod"), "--allow-outside-input"});
    EXPECT_EQ(ok.exitCode, 0) << ok.outAndErr();
}

// A build whose output is its own mesh or a file the mesh refers to is refused, whatever
// --allow-outside-input says, and the file is untouched (before stop 36 the database replaced it).
TEST(Confine, BuildNeverWritesOverItsInputOrItsTexture) {
    Layout l;
    writeFile(l.in("tex.png"), encodeTexture(testImage(4, 4), Codec::Png).bytes);
    writeObj(l.in("m.obj"), terrain(4), "tex.png");
    const std::string mesh = readText(l.in("m.obj")), texture = readText(l.in("tex.png"));
    for (const char* allow : {"--strict", "--allow-outside-input"}) {
        RunResult r = runHlod({"build", l.in("m.obj"), "-o", l.in("m.obj"), allow});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod build: " + l.in("m.obj") + ": is also an input (" + l.in("m.obj") + "); write the output elsewhere\n");
        r = runHlod({"build", l.in("m.obj"), "-o", l.in("tex.png"), allow});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_NE(r.err.find("hlod build: " + l.in("m.obj") + ": texture 'tex.png' is the output of this run (" + l.in("tex.png") +
                             "; refused)"),
                  std::string::npos)
            << r.err;
    }
    EXPECT_EQ(readText(l.in("m.obj")), mesh);
    EXPECT_EQ(readText(l.in("tex.png")), texture);
    // A folder in the database's place is refused before the mesh is read, not after the build.
    fs::create_directories(l.dir.file("taken.hlod"));
    const RunResult r = runHlod({"build", l.in("m.obj"), "-o", l.dir.file("taken.hlod")});
    EXPECT_EQ(r.exitCode, 1) << r.outAndErr();
    EXPECT_EQ(r.err, "hlod build: " + l.dir.file("taken.hlod") + ": cannot write database (exists and is not a regular file)\n");
    EXPECT_EQ(r.out.find("split"), std::string::npos) << r.out;
}

// The build report DB.build.json is an output like the database: a link to the input, a FIFO or a
// folder in its place is refused before any work, and no database is written (before, the report
// was written in place at the end: through the link over the input, blocking on the FIFO, or
// failing after a complete database).
TEST(Confine, TheBuildReportIsCheckedBeforeAnyWorkAndNeverWrittenOverAnInput) {
    Layout l;
    writeObj(l.in("m.obj"), terrain(4), "");
    const std::string mesh = readText(l.in("m.obj"));
    fs::create_symlink(l.in("m.obj"), l.dir.file("link.hlod.build.json"));
    RunResult r = runHlod({"build", l.in("m.obj"), "-o", l.dir.file("link.hlod")});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_EQ(r.err, "hlod build: " + l.dir.file("link.hlod.build.json") + ": is also an input (" + l.in("m.obj") +
                         "); write the output elsewhere\n");
    EXPECT_EQ(readText(l.in("m.obj")), mesh);
    ASSERT_EQ(::mkfifo(l.dir.file("fifo.hlod.build.json").c_str(), 0644), 0);
    fs::create_directories(l.dir.file("folder.hlod.build.json"));
    for (const char* db : {"fifo.hlod", "folder.hlod"}) {
        r = runHlod({"build", l.in("m.obj"), "-o", l.dir.file(db)});
        EXPECT_EQ(r.exitCode, 1) << r.outAndErr();
        EXPECT_EQ(r.err, "hlod build: " + l.dir.file(db) + ".build.json: cannot write build report (exists and is not a regular file)\n");
        EXPECT_FALSE(fs::exists(l.dir.file(db)));
    }
    // A report that is a regular file is replaced as a whole.
    writeFile(l.dir.file("ok.hlod.build.json"), {'x'});
    r = runHlod({"build", l.in("m.obj"), "-o", l.dir.file("ok.hlod")});
    EXPECT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_EQ(readText(l.dir.file("ok.hlod.build.json")).front(), '{');
}

}  // namespace
}  // namespace hlod::test
