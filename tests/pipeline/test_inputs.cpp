// Inputs as a class (README "Inputs"): one rule for every unusable texture (missing, empty,
// truncated, not an image, absurd size): a warning, its material untextured, counted in the
// summary and the build report; fatal with --strict (exit 2). The up axis recorded in the
// database. Progress lines when the output is not a terminal (injected clock, no wall time).
#include "helpers.h"

#include "formats/up_axis.h"
#include "tests/support/run_hlod.h"
#include "tests/support/synthetic.h"

#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <filesystem>
#include <sstream>

namespace hlod::test {
namespace {

// Writes an OBJ whose two materials both use `texture`, then the texture's bytes.
void writeTexturedObj(TempDir& dir, const std::string& texture, const std::vector<uint8_t>& bytes, bool writeTexture = true) {
    writeObj(dir.file("m.obj"), terrain(20, 100, true), texture);
    if (writeTexture) writeFile(dir.file(texture), bytes);
}

std::vector<uint8_t> truncated(std::vector<uint8_t> bytes) {
    bytes.resize(bytes.size() / 2);
    return bytes;
}

std::vector<uint8_t> text(const std::string& s) { return {s.begin(), s.end()}; }

struct BadTexture {
    const char* label;
    std::string file;
    std::vector<uint8_t> bytes;
    bool write = true;
    const char* problem;  // in the warning
};

std::vector<BadTexture> badTextures() {
    const std::vector<uint8_t> png = encodeTexture(testImage(64, 64), Codec::Png).bytes;
    const std::vector<uint8_t> jpeg = encodeTexture(testImage(64, 64), Codec::Jpeg, 90).bytes;
    return {
        {"missing", "gone.png", {}, false, "is missing"},
        {"empty", "empty.png", {}, true, "is empty (0 bytes)"},
        {"truncated PNG", "half.png", truncated(png), true, "corrupt texture"},
        {"truncated JPEG", "half.jpg", truncated(jpeg), true, "corrupt texture"},
        {"not an image", "text.png", text("this is not a picture\n"), true, "is not a readable image"},
        {"absurd size", "huge.ppm", text("P6\n100000 100000\n255\n\x01\x02\x03"), true, "has absurd size 100000x100000"},
    };
}

TEST(Textures, EveryUnusableTextureWarnsAndLeavesItsMaterialUntextured) {
    for (const BadTexture& bad : badTextures()) {
        SCOPED_TRACE(bad.label);
        TempDir dir;
        writeTexturedObj(dir, bad.file, bad.bytes, bad.write);
        const RunResult r = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--set", "c_desiredTris=200"});
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
        EXPECT_NE(r.out.find(bad.problem), std::string::npos) << r.out;
        EXPECT_NE(r.out.find(bad.file), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("material 'mat0' left untextured"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("material 'mat1' left untextured"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("textures: 2 unusable"), std::string::npos) << r.out;
        std::ifstream report(dir.file("m.hlod.build.json"));
        const nlohmann::json j = nlohmann::json::parse(report);
        ASSERT_EQ(j.at("texture_problems").size(), 2u);
        EXPECT_NE(j.at("texture_problems")[0].get<std::string>().find(bad.problem), std::string::npos);
        const Database db = Database::open(dir.file("m.hlod"));
        for (const Node& n : db.skeleton().nodes) EXPECT_EQ(n.texturedTriangles, 0u) << "node " << n.id;
        EXPECT_EQ(runHlod({"validate", dir.file("m.hlod")}).exitCode, 0);
    }
}

TEST(Textures, StrictMakesEveryUnusableTextureFatal) {
    for (const BadTexture& bad : badTextures()) {
        SCOPED_TRACE(bad.label);
        TempDir dir;
        writeTexturedObj(dir, bad.file, bad.bytes, bad.write);
        const RunResult r = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--strict"});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();  // an input that cannot be read (formats/cli/command.h)
        const size_t at = r.err.find("hlod build: ");
        ASSERT_NE(at, std::string::npos) << r.err;
        const std::string line = r.err.substr(at);
        EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << line;  // one line
        EXPECT_NE(line.find(bad.file), std::string::npos) << line;
        EXPECT_NE(line.find("(--strict)"), std::string::npos) << line;
        EXPECT_FALSE(std::filesystem::exists(dir.file("m.hlod")));
    }
}

// A material no library defines (its MTL missing, a folder, a FIFO, not an MTL, or defining other
// names) is the same kind of problem as an unusable texture: before stop 38 such a build said
// nothing (or, for a missing MTL, only warned) and --strict let it pass.
TEST(Textures, AMaterialNoLibraryDefinesFollowsTheTexturesRule) {
    const std::vector<std::pair<const char*, const char*>> cases = {
        {"missing", "not found"}, {"folder", "is not a regular file"}, {"fifo", "is not a regular file"},
        {"random bytes", nullptr}, {"other names", nullptr}};
    for (const auto& [label, libraryWarning] : cases) {
        SCOPED_TRACE(label);
        TempDir dir;
        std::ofstream(dir.file("a.obj")) << "mtllib x.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl m\nf 1 3 2\n";
        const std::string mtl = dir.file("x.mtl");
        if (label == std::string("folder")) std::filesystem::create_directory(mtl);
        if (label == std::string("fifo")) {
            ASSERT_EQ(::mkfifo(mtl.c_str(), 0644), 0);
        }
        if (label == std::string("random bytes")) writeFile(mtl, {0x00, 0xff, 0x13, 0x7f, 0x80, 0x0a, 0xfe, 0x01});
        if (label == std::string("other names")) std::ofstream(mtl) << "newmtl other\nKd 1 0 0\n";
        RunResult r = runHlod({"build", dir.file("a.obj"), "-o", dir.file("a.hlod")});
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
        if (libraryWarning) {
            EXPECT_NE(r.out.find("material library 'x.mtl' " + std::string(libraryWarning)), std::string::npos) << r.out;
        }
        EXPECT_NE(r.out.find(dir.file("a.obj") + ":2: material 'm' is defined in no material library; material 'm' left untextured"),
                  std::string::npos) << r.out;
        EXPECT_NE(r.out.find("textures: 1 unusable"), std::string::npos) << r.out;  // once per name
        r = runHlod({"build", dir.file("a.obj"), "-o", dir.file("s.hlod"), "--strict"});
        EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
        EXPECT_NE(r.err.find("material 'm' is defined in no material library (--strict)\n"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir.file("s.hlod")));
    }
}

TEST(Textures, AGoodTextureIsNoProblemWithOrWithoutStrict) {
    TempDir dir;
    writeTexturedObj(dir, "atlas.png", encodeTexture(testImage(64, 64), Codec::Png).bytes);
    const RunResult r = runHlod({"build", dir.file("m.obj"), "-o", dir.file("m.hlod"), "--strict"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_EQ(r.out.find("unusable"), std::string::npos) << r.out;
    const Database db = Database::open(dir.file("m.hlod"));
    EXPECT_GT(db.skeleton().nodes[0].texturedTriangles, 0u);
}

TEST(Textures, ReadersReportTheProblemAndClearTheMaterial) {
    TempDir dir;
    writeTexturedObj(dir, "empty.png", {});
    const SourceMesh s = readMesh(dir.file("m.obj"));
    ASSERT_EQ(s.stats.textureProblems.size(), 2u);
    EXPECT_NE(s.stats.textureProblems[0].what.find("is empty (0 bytes)"), std::string::npos);
    for (const Material& m : s.materials) EXPECT_TRUE(m.texturePath.empty());
}

// A texture name that is a folder was reported as missing (until stop 44); a FIFO is never opened.
TEST(Textures, AFolderOrAFifoIsNamedForWhatItIs) {
    TempDir dir;
    writeTexturedObj(dir, "atlas.png", {}, false);
    std::filesystem::create_directory(dir.file("atlas.png"));
    SourceMesh s = readMesh(dir.file("m.obj"));
    ASSERT_EQ(s.stats.textureProblems.size(), 2u);
    EXPECT_NE(s.stats.textureProblems[0].what.find("atlas.png' is a folder, not an image"), std::string::npos) << s.stats.textureProblems[0].what;
    std::filesystem::remove(dir.file("atlas.png"));
    ASSERT_EQ(mkfifo(dir.file("atlas.png").c_str(), 0600), 0);
    s = readMesh(dir.file("m.obj"));
    ASSERT_EQ(s.stats.textureProblems.size(), 2u);
    EXPECT_NE(s.stats.textureProblems[0].what.find("atlas.png' is not a regular file"), std::string::npos) << s.stats.textureProblems[0].what;
}

// An embedded glTF image that does not decode follows the same rule instead of failing the file.
TEST(Textures, AnUndecodableEmbeddedGltfImageIsATextureProblem) {
    TempDir dir;
    const std::vector<uint8_t> png = encodeTexture(testImage(16, 16), Codec::Png).bytes;
    for (const auto& bytes : {text("not a picture"), truncated(png)}) {
        std::ofstream(dir.file("t.gltf")) << triangleGltf(triangleBufferDataUri(), "data:image/png;base64," + base64(bytes));
        const SourceMesh s = readMesh(dir.file("t.gltf"));
        ASSERT_EQ(s.stats.textureProblems.size(), 1u);
        EXPECT_NE(s.stats.textureProblems[0].what.find(dir.file("t.gltf") + ": image 0 cannot be decoded"), std::string::npos)
            << s.stats.textureProblems[0].what;
        EXPECT_EQ(s.stats.textureProblems[0].material, "skin");
        EXPECT_FALSE(s.materials[0].image);
        const RunResult strict = runHlod({"build", dir.file("t.gltf"), "-o", dir.file("t.hlod"), "--strict"});
        EXPECT_EQ(strict.exitCode, 2) << strict.outAndErr();
        EXPECT_NE(strict.err.find("image 0 cannot be decoded"), std::string::npos) << strict.err;
        const RunResult lenient = runHlod({"build", dir.file("t.gltf"), "-o", dir.file("t.hlod")});
        EXPECT_EQ(lenient.exitCode, 0) << lenient.outAndErr();
        EXPECT_NE(lenient.out.find("material 'skin' left untextured"), std::string::npos) << lenient.out;
        EXPECT_NE(lenient.out.find("up axis: y (glTF is y-up)"), std::string::npos) << lenient.out;
        EXPECT_EQ(*Database::open(dir.file("t.hlod")).skeleton().findMeta("up"), "y");
    }
    std::ofstream(dir.file("t.gltf")) << triangleGltf(triangleBufferDataUri(), "data:image/png;base64," + base64(png));
    const SourceMesh good = readMesh(dir.file("t.gltf"));
    EXPECT_TRUE(good.stats.textureProblems.empty());
    ASSERT_TRUE(good.materials[0].image);
}

TEST(UpAxis, ChosenByFormatOrOption) {
    TempDir dir;
    EXPECT_EQ(chooseUpAxis("a.gltf", "").axis, "y");
    EXPECT_EQ(chooseUpAxis("a.GLB", "").axis, "y");
    EXPECT_EQ(chooseUpAxis("a.obj", "").axis, "z");
    EXPECT_EQ(chooseUpAxis("a.ply", "").axis, "z");
    EXPECT_EQ(chooseUpAxis("a.gltf", "z").axis, "z");
    EXPECT_EQ(chooseUpAxis("a.gltf", "z").reason, "--up");
    EXPECT_THROW(chooseUpAxis("a.obj", "w"), std::invalid_argument);
    std::filesystem::create_directories(dir.path / "mixed");
    std::ofstream(dir.file("mixed/a.obj")) << "";
    EXPECT_EQ(chooseUpAxis(dir.file("mixed"), "").axis, "z");
    std::ofstream(dir.file("mixed/b.glb")) << "";
    EXPECT_NE(errorOf([&] { chooseUpAxis(dir.file("mixed"), ""); }).find("give --up"), std::string::npos);
    EXPECT_EQ(chooseUpAxis(dir.file("mixed"), "y").axis, "y");
}

TEST(UpAxis, RecordedInTheDatabaseAndUsedByPathAndExport) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(20).mesh, true);
    const RunResult z = runHlod({"build", dir.file("t.ply"), "-o", dir.file("z.hlod"), "--set", "c_desiredTris=200"});
    ASSERT_EQ(z.exitCode, 0) << z.outAndErr();
    EXPECT_NE(z.out.find("up axis: z (OBJ/PLY"), std::string::npos) << z.out;
    const RunResult y = runHlod({"build", dir.file("t.ply"), "-o", dir.file("y.hlod"), "--up", "y", "--set", "c_desiredTris=200"});
    ASSERT_EQ(y.exitCode, 0) << y.outAndErr();
    EXPECT_NE(y.out.find("up axis: y (--up)"), std::string::npos) << y.out;
    const Database zdb = Database::open(dir.file("z.hlod")), ydb = Database::open(dir.file("y.hlod"));
    EXPECT_EQ(*zdb.skeleton().findMeta("up"), "z");
    EXPECT_EQ(upAxisOf(ydb.skeleton(), "y.hlod").axis, 1);
    EXPECT_TRUE(upAxisOf(ydb.skeleton(), "y.hlod").recorded);
    EXPECT_NE(ydb.skeleton().findMeta("command")->find("--up y"), std::string::npos);

    const RunResult p = runHlod({"path", dir.file("y.hlod"), "-o", dir.file("y.path")});
    ASSERT_EQ(p.exitCode, 0) << p.outAndErr();
    EXPECT_NE(p.out.find("up axis: y (recorded in the database)"), std::string::npos) << p.out;
    const RunResult po = runHlod({"path", dir.file("y.hlod"), "-o", dir.file("z.path"), "--up", "z"});
    EXPECT_NE(po.out.find("up axis: z (--up)"), std::string::npos) << po.out;

    ASSERT_EQ(runHlod({"export", "tiles", dir.file("y.hlod"), "-o", dir.file("ytiles")}).exitCode, 0);
    ASSERT_EQ(runHlod({"export", "tiles", dir.file("z.hlod"), "-o", dir.file("ztiles")}).exitCode, 0);
    std::ifstream yt(dir.file("ytiles/tileset.json")), zt(dir.file("ztiles/tileset.json"));
    const nlohmann::json yj = nlohmann::json::parse(yt), zj = nlohmann::json::parse(zt);
    EXPECT_EQ(yj.at("root").at("transform"), nlohmann::json({1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1}));
    EXPECT_FALSE(zj.at("root").contains("transform"));
    EXPECT_EQ(yj.at("asset").at("extras").at("hlod").at("up"), "y");

    // With --origin the y-up turn comes before the east-north-up placement: columns (x, y, z, t)
    // of the y-up transform are (east, up, -north, t) of the z-up one.
    const std::string origin = "37.8716,-122.2727,60";
    ASSERT_EQ(runHlod({"export", "tiles", dir.file("y.hlod"), "-o", dir.file("yplaced"), "--origin", origin}).exitCode, 0);
    ASSERT_EQ(runHlod({"export", "tiles", dir.file("z.hlod"), "-o", dir.file("zplaced"), "--origin", origin}).exitCode, 0);
    std::ifstream yp(dir.file("yplaced/tileset.json")), zp(dir.file("zplaced/tileset.json"));
    const nlohmann::json ty = nlohmann::json::parse(yp).at("root").at("transform"), tz = nlohmann::json::parse(zp).at("root").at("transform");
    for (int row = 0; row < 4; ++row) {
        EXPECT_NEAR(ty[0 + row].get<double>(), tz[0 + row].get<double>(), 1e-9);
        EXPECT_NEAR(ty[4 + row].get<double>(), tz[8 + row].get<double>(), 1e-9);
        EXPECT_NEAR(ty[8 + row].get<double>(), -tz[4 + row].get<double>(), 1e-9);
        EXPECT_NEAR(ty[12 + row].get<double>(), tz[12 + row].get<double>(), 1e-6);
    }
}

TEST(UpAxis, ADatabaseWithoutTheKeyIsZUp) {
    Skeleton s;
    EXPECT_EQ(upAxisOf(s, "old.hlod").axis, 2);
    EXPECT_FALSE(upAxisOf(s, "old.hlod").recorded);
    s.meta.emplace_back("up", "w");
    EXPECT_THROW(upAxisOf(s, "bad.hlod"), FormatError);
}

// FORMAT.md: a database written before the key (the Writer API alone writes no "up") reads as
// z-up everywhere, as before.
TEST(UpAxis, AnOldDatabaseIsReadAsZUpByPathAndExport) {
    TempDir dir;
    writeSyntheticDatabase(dir.file("old.hlod"), SyntheticOptions{});
    ASSERT_EQ(Database::open(dir.file("old.hlod")).skeleton().findMeta("up"), nullptr);
    const RunResult p = runHlod({"path", dir.file("old.hlod"), "-o", dir.file("old.path")});
    ASSERT_EQ(p.exitCode, 0) << p.outAndErr();
    EXPECT_NE(p.out.find("up axis: z (not recorded"), std::string::npos) << p.out;
    ASSERT_EQ(runHlod({"export", "tiles", dir.file("old.hlod"), "-o", dir.file("tiles")}).exitCode, 0);
    std::ifstream t(dir.file("tiles/tileset.json"));
    EXPECT_FALSE(nlohmann::json::parse(t).at("root").contains("transform"));
}

// A fake clock: progress lines are due by the injected time, never the wall clock.
struct FakeClock {
    double now = 0;
    ProgressOptions options(bool json = false) {
        ProgressOptions o;
        o.json = json, o.interval = 5, o.thread = false;
        o.clock = [this] { return now; };
        return o;
    }
};

std::vector<std::string> linesOf(const std::string& s) {
    std::vector<std::string> lines;
    std::istringstream in(s);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// Far from the origin (a scan in UTM metres), 32-bit float positions step more coarsely than the
// position lattice and detail below that step is lost at the read: the build warns, once per
// input (a folder once for all its files, with the centre of all their bounds: --offset moves
// every file; until stop 49 one line a file, each with its own centre), with a translation near
// the origin, and still builds. The same mesh near the origin does not warn.
TEST(Inputs, FarFromTheOriginWarnsWithAnOffset) {
    TempDir dir;
    Piece far = terrain(20);  // 100 units: 14-bit lattice step 2^-8, floats at 2^22 step 2^-1
    for (size_t v = 0; v < far.mesh.vertexCount(); ++v) far.mesh.positions[3 * v] += 4194304, far.mesh.positions[3 * v + 1] += 512;
    writePly(dir.file("near.ply"), terrain(20).mesh, true);
    writePly(dir.file("far.ply"), far.mesh, true);
    std::filesystem::create_directories(dir.file("blocks"));
    writePly(dir.file("blocks/a.ply"), far.mesh, true);
    for (size_t v = 0; v < far.mesh.vertexCount(); ++v) far.mesh.positions[3 * v] += 200;
    writePly(dir.file("blocks/b.ply"), far.mesh, true);
    const std::string step = " units from the origin, where positions (32-bit floats) step by 0.5";
    for (const std::string input : {"far.ply", "blocks"}) {
        const RunResult r = runHlod({"build", dir.file(input), "-o", dir.file(input + ".hlod")});
        ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
        const bool folder = input == "blocks";
        const std::string line = "warning: " + dir.file(input) + (folder ? " (2 of its 2 files)" : "") + ": coordinates reach " +
                                 (folder ? "4.1946e+06" : "4.1944e+06") + step;
        const size_t at = r.outAndErr().find(line);
        EXPECT_NE(at, std::string::npos) << r.outAndErr();
        EXPECT_EQ(r.outAndErr().find("from the origin", at + line.size()), std::string::npos) << r.outAndErr();  // once
        const std::string offset = folder ? "4194454,562,0" : "4194354,562,0";
        EXPECT_NE(r.outAndErr().find("build with --offset " + offset + " "), std::string::npos) << r.outAndErr();
    }
    const RunResult r = runHlod({"build", dir.file("near.ply"), "-o", dir.file("near.hlod")});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    EXPECT_EQ(r.outAndErr().find("from the origin"), std::string::npos) << r.outAndErr();
}

// The threshold is the lattice step itself: floats stepping by exactly the step do not warn.
TEST(Inputs, FloatPrecisionWarningThresholdIsTheLatticeStep) {
    const Box3f box{{0, 0, 0}, {4194304, 1, 1}};  // floats step by 0.5 from 2^22
    EXPECT_EQ(floatPrecisionWarning("m", box, 0.5), "");
    EXPECT_NE(floatPrecisionWarning("m", box, 0.25), "");
    EXPECT_EQ(floatPrecisionWarning("m", Box3f{{-1, -1, -1}, {1, 1, 1}}, 1e-6), "");  // floats step by 2^-23 at 1
    EXPECT_NE(floatPrecisionWarning("m", Box3f{{-4194304, 0, 0}, {0, 1, 1}}, 0.25), "");  // negative coordinates too
    EXPECT_EQ(floatPrecisionWarning("m", Box3f{{0, 0, 0}, {0, 0, 0}}, 0.25), "");
    EXPECT_EQ(floatPrecisionWarning("m", box, 0), "");
    EXPECT_EQ(floatPrecisionWarning("m", box, 0.7), "");  // the codec's lattice: 0.5
    EXPECT_NE(floatPrecisionWarning("m", box, 0.45).find("the position lattice step 0.25:"), std::string::npos);
    // The advice is the offset that centres the input: the given one plus the bounds' centre (the
    // centre alone until stop 48, so following it swapped the signs at every build).
    const Box3f moved{{-4194304, 0, 0}, {-4194302, 0, 0}};
    EXPECT_NE(floatPrecisionWarning("m", moved, 0.25).find("build with --offset -4194303,0,0 "), std::string::npos);
    EXPECT_NE(floatPrecisionWarning("m", moved, 0.25, {4194303, -2, 0}).find("build with --offset 0,-2,0 "), std::string::npos);
}

// An OBJ written with full double precision: 8 x 8 quads 0.1 apart, moved to (4194304, 1048576),
// where 32-bit floats step by 0.5 and 0.125.
void writeFarObj(const std::string& path, float spacing = 0.8f) {
    const Piece p = terrain(8, spacing);
    std::ofstream out(path);
    out.precision(17);
    for (size_t v = 0; v < p.mesh.vertexCount(); ++v)
        out << "v " << 4194304.0 + p.mesh.positions[3 * v] << ' ' << 1048576.0 + p.mesh.positions[3 * v + 1] << ' '
            << p.mesh.positions[3 * v + 2] << '\n';
    for (size_t t = 0; t < p.mesh.triangleCount(); ++t)
        out << "f " << p.mesh.indices[3 * t] + 1 << ' ' << p.mesh.indices[3 * t + 1] + 1 << ' ' << p.mesh.indices[3 * t + 2] + 1 << '\n';
}

// A far model whose every triangle collapses in float: the "empty mesh" error says why and gives the
// --offset (before stop 44 the warning was printed only once the split had succeeded: never).
TEST(Inputs, AFarModelWhoseTrianglesAllCollapseSaysWhy) {
    TempDir dir;
    writeFarObj(dir.file("far.obj"), 0.001f);
    const RunResult r = runHlod({"build", dir.file("far.obj"), "-o", dir.file("far.hlod")});
    EXPECT_EQ(r.exitCode, 2) << r.outAndErr();
    EXPECT_EQ(r.err.rfind("hlod build: " + dir.file("far.obj") + ": empty mesh (no valid triangles); coordinates reach ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("build with --offset 4194304,1048576,0 "), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// A model thinner than the position lattice's steps (a 100,000 x 1 strip: a step of 4 at 14 bits) is
// stored flat: a warning says so and how to keep it (status 0, no word, "valid" until stop 46); a finer
// step keeps it, without the warning.
TEST(Inputs, AModelThinnerThanTheLatticeIsWarnedOf) {
    TempDir dir;
    std::ofstream(dir.file("strip.obj")) << "v 0 0 0\nv 100000 0 0\nv 100000 1 0\nv 0 1 0\nf 1 2 3 4\n";
    const RunResult flat = runHlod({"build", dir.file("strip.obj"), "-o", dir.file("flat.hlod")});
    ASSERT_EQ(flat.exitCode, 0) << flat.outAndErr();
    EXPECT_NE(flat.outAndErr().find("warning: " + dir.file("strip.obj") + ": the position lattice flattens 2 of its 2 triangles "
                                    "(100.0 %) to lines or points"),
              std::string::npos) << flat.outAndErr();
    const RunResult kept = runHlod({"build", dir.file("strip.obj"), "-o", dir.file("kept.hlod"), "--draco-position-step", "0.25"});
    ASSERT_EQ(kept.exitCode, 0) << kept.outAndErr();
    EXPECT_EQ(kept.outAndErr().find("flattens"), std::string::npos) << kept.outAndErr();
}

// --offset subtracts in double before the floats: the far model keeps every triangle (without it,
// vertices 0.1 apart collapse onto 0.5 steps), no warning, META offset and the tileset record it;
// `hlod split --offset` carries it to the shard builds, which refuse another; a bad value is a usage error.
TEST(Inputs, OffsetKeepsDetailFarFromTheOriginAndIsRecorded) {
    TempDir dir;
    writeFarObj(dir.file("far.obj"));
    const RunResult lost = runHlod({"build", dir.file("far.obj"), "-o", dir.file("lost.hlod")});
    ASSERT_EQ(lost.exitCode, 0) << lost.outAndErr();
    EXPECT_NE(lost.outAndErr().find("degenerate triangles"), std::string::npos) << lost.outAndErr();
    EXPECT_NE(lost.outAndErr().find("build with --offset 4194305,1048576,0 "), std::string::npos) << lost.outAndErr();
    const RunResult kept = runHlod({"build", dir.file("far.obj"), "-o", dir.file("kept.hlod"), "--offset", "4194304,1048576,0"});
    ASSERT_EQ(kept.exitCode, 0) << kept.outAndErr();
    EXPECT_EQ(kept.outAndErr().find("degenerate"), std::string::npos) << kept.outAndErr();
    EXPECT_EQ(kept.outAndErr().find("from the origin"), std::string::npos) << kept.outAndErr();
    std::ifstream report(dir.file("kept.hlod.build.json"));
    EXPECT_EQ(nlohmann::json::parse(report).at("input_triangles"), 128);
    EXPECT_NE(runHlod({"inspect", dir.file("kept.hlod")}).out.find("offset: 4194304,1048576,0\n"), std::string::npos);
    ASSERT_EQ(runHlod({"export", "tiles", dir.file("kept.hlod"), "-o", dir.file("tiles")}).exitCode, 0);
    std::ifstream tileset(dir.file("tiles/tileset.json"));
    EXPECT_EQ(nlohmann::json::parse(tileset).at("asset").at("extras").at("hlod").at("offset"), nlohmann::json({4194304.0, 1048576.0, 0.0}));

    ASSERT_EQ(runHlod({"split", dir.file("far.obj"), "-o", dir.file("work"), "--offset", "4194304,1048576,0"}).exitCode, 0);
    const RunResult shard = runHlod({"build", dir.file("work"), "-o", dir.file("fromwork.hlod")});
    ASSERT_EQ(shard.exitCode, 0) << shard.outAndErr();
    EXPECT_EQ(readFile(dir.file("fromwork.hlod")), readFile(dir.file("kept.hlod")));
    const RunResult other = runHlod({"build", dir.file("work"), "-o", dir.file("other.hlod"), "--offset", "1,2,3"});
    EXPECT_EQ(other.exitCode, 2);
    EXPECT_NE(other.outAndErr().find("--offset differs from the split of"), std::string::npos) << other.outAndErr();
    for (const char* bad : {"1,2", "1,2,3,4", "1,x,3", "1,inf,3", "", "1e300,0,0"}) {  // 1e300: beyond a float once subtracted
        const RunResult r = runHlod({"build", dir.file("far.obj"), "-o", dir.file("bad.hlod"), "--offset", bad});
        EXPECT_EQ(r.exitCode, 2) << bad;
        EXPECT_NE(r.outAndErr().find("expected X,Y,Z"), std::string::npos) << r.outAndErr();
        EXPECT_FALSE(std::filesystem::exists(dir.file("bad.hlod")));
    }
}

TEST(Progress, APipeGetsALineEveryIntervalAndNoEtaBeforeARate) {
    std::ostringstream out;
    FakeClock clock;
    Progress progress(out, clock.options());
    progress.beginStage("build", 1000);
    ASSERT_EQ(linesOf(out.str()).size(), 1u);  // the stage's first line, at once
    EXPECT_NE(out.str().find("ETA --"), std::string::npos) << out.str();
    // A slow stage: textures decoding, nothing done for 20 s; then items at 10 per second.
    for (int second = 1; second <= 60; ++second) {
        clock.now = second;
        if (second <= 20 && second % 4 == 0) progress.textureLoaded(4096 * 4096);
        if (second > 20) progress.advance(10);
        progress.poll();
    }
    const std::vector<std::string> lines = linesOf(out.str());
    EXPECT_EQ(lines.size(), 1u + 60 / 5) << out.str();  // one every 5 s of the injected clock
    EXPECT_NE(lines[4].find("ETA --"), std::string::npos) << lines[4];  // t = 20 s, nothing done: no rate, no ETA
    EXPECT_NE(lines[4].find("textures 5 (83.9 Mtexel)"), std::string::npos) << lines[4];
    EXPECT_NE(lines[12].find("40.0%"), std::string::npos) << lines[12];  // t = 60 s: 400 of 1000
    EXPECT_NE(lines[12].find("ETA 90 s"), std::string::npos) << lines[12];  // 600 left at 400 / 60 s
    progress.endStage();
    EXPECT_EQ(linesOf(out.str()).size(), lines.size() + 1);
}

TEST(Progress, JsonLines) {
    std::ostringstream out;
    FakeClock clock;
    Progress progress(out, clock.options(true));
    progress.beginStage("read", 200, "B");
    clock.now = 5;
    progress.advance(50);
    progress.poll();
    progress.message("warning: a \"quoted\" name");
    progress.endStage();
    const std::vector<std::string> lines = linesOf(out.str());
    ASSERT_EQ(lines.size(), 4u) << out.str();
    std::vector<nlohmann::json> j;
    for (const std::string& line : lines) j.push_back(nlohmann::json::parse(line));
    EXPECT_TRUE(j[0].at("eta_s").is_null());
    EXPECT_EQ(j[1].at("stage"), "read");
    EXPECT_EQ(j[1].at("done"), 50);
    EXPECT_EQ(j[1].at("total"), 200);
    EXPECT_EQ(j[1].at("eta_s"), 15);
    EXPECT_EQ(j[2].at("message"), "warning: a \"quoted\" name");
    EXPECT_EQ(j[3].at("end"), true);
    // Work past the estimated total raises it: done never exceeds total.
    progress.beginStage("build", 100);
    clock.now = 10;
    progress.advance(150);
    progress.poll();
    progress.endStage();
    const std::vector<std::string> more = linesOf(out.str());
    ASSERT_EQ(more.size(), 7u) << out.str();
    for (size_t i = 5; i < 7; ++i) {
        const nlohmann::json k = nlohmann::json::parse(more[i]);
        EXPECT_EQ(k.at("done"), 150) << more[i];
        EXPECT_EQ(k.at("total"), 150) << more[i];
    }
}

TEST(Progress, ABuildIntoAPipePrintsStageLines) {
    TempDir dir;
    writePly(dir.file("t.ply"), terrain(30).mesh, true);
    const RunResult r = runHlod({"build", dir.file("t.ply"), "-o", dir.file("t.hlod"), "--progress-json"});
    ASSERT_EQ(r.exitCode, 0) << r.outAndErr();
    std::vector<std::string> stages;
    for (const std::string& line : linesOf(r.out))
        if (!line.empty() && line[0] == '{') {
            const nlohmann::json j = nlohmann::json::parse(line);
            if (j.contains("stage") && !j.contains("end")) stages.push_back(j.at("stage"));
        }
    EXPECT_EQ(stages, (std::vector<std::string>{"read", "split", "build", "write"})) << r.out;
}

}  // namespace
}  // namespace hlod::test
