// Constants of thesis Table 6.1: names, parsing, bad values, config files, printing.
#include "formats/calibration.h"
#include "formats/constants.h"
#include "formats/errors.h"
#include "formats/setting_lines.h"

#include "helpers.h"

#include <functional>
#include <sstream>

namespace hlod::test {
namespace {

TEST(Constants, DefaultsAndNames) {
    Constants c;
    EXPECT_EQ(c.textured, 0.127);
    EXPECT_EQ(constantTable().size(), 9u);
    EXPECT_STREQ(constantTable()[0].name, "c_desiredTris");
    setConstant(c, "c_targetTime", "20");
    setConstantAssignment(c, "c_vis = 1.5");
    EXPECT_EQ(c.targetTimeMs, 20);
    EXPECT_EQ(c.vis, 1.5);
}

TEST(Constants, BadValuesAndNames) {
    Constants c;
    for (const char* v : {"", "abc", "1x", "nan", "inf", "1e999"})
        EXPECT_THROW(setConstant(c, "c_vis", v), std::invalid_argument) << v;
    EXPECT_THROW(setConstant(c, "c_nope", "1"), std::invalid_argument);
    EXPECT_THROW(setConstantAssignment(c, "c_vis"), std::invalid_argument);
    try {
        setConstant(c, "c_nope", "1");
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("c_targetTime"), std::string::npos);  // lists the known names
    }
    EXPECT_EQ(c.vis, Constants{}.vis);
}

// Absurd values (README "Reliability"): each violated range is one line naming the constant; a
// constant the use does not read is not checked.
TEST(Constants, AbsurdValuesAreRefusedForTheirUse) {
    const auto error = [](const char* assignment, ConstantUse use) -> std::string {
        Constants c;
        setConstantAssignment(c, assignment);
        try {
            validateConstants(c, use);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(error("c_targetTime=-5", kUsedByPlayer), "c_targetTime = -5: must be > 0 and at most 10000 (milliseconds: a frame of at most 10 s)");
    EXPECT_EQ(error("c_targetTime=0", kUsedByPlayer), "c_targetTime = 0: must be > 0 and at most 10000 (milliseconds: a frame of at most 10 s)");
    EXPECT_EQ(error("c_targetTime=1e9", kUsedByPlayer), "c_targetTime = 1e+09: must be > 0 and at most 10000 (milliseconds: a frame of at most 10 s)");
    EXPECT_EQ(error("c_levelFactor=1", kUsedByBuild), "c_levelFactor = 1: must be a whole number in [2, 64] (children per node)");
    EXPECT_EQ(error("c_levelFactor=0", kUsedByBuild), "c_levelFactor = 0: must be a whole number in [2, 64] (children per node)");
    EXPECT_EQ(error("c_levelFactor=1e300", kUsedByBuild), "c_levelFactor = 1e+300: must be a whole number in [2, 64] (children per node)");
    EXPECT_EQ(error("c_levelFactor=2.5", kUsedByBuild), "c_levelFactor = 2.5: must be a whole number in [2, 64] (children per node)");
    EXPECT_EQ(error("c_desiredTris=0.5", kUsedByBuild), "c_desiredTris = 0.5: must be in [1, 4294967295] (triangles per node)");
    EXPECT_EQ(error("c_desiredTris=1e300", kUsedByBuild), "c_desiredTris = 1e+300: must be in [1, 4294967295] (triangles per node)");
    EXPECT_EQ(error("c_textured=-1", kUsedByBuild), "c_textured = -1: must be in (0, 1]");
    EXPECT_EQ(error("c_hystSwitch=5000", kUsedByPlayer),
              "c_hystSwitch = 5000: must be <= c_hystLimit = 4510 (the counter could never reach it)");
    EXPECT_EQ(error("c_hystSwitch=0", kUsedByPlayer), "c_hystSwitch = 0: must be > 0");
    EXPECT_EQ(error("c_vis=-1", kUsedByPlayer), "c_vis = -1: must be >= 0");
    EXPECT_EQ(error("c_fore=-0.1", kUsedByPlayer), "c_fore = -0.1: must be >= 0");
    EXPECT_EQ(error("c_memory=0", kUsedByPlayer), "c_memory = 0: must be > 0 (bytes per unit of cost)");
    EXPECT_EQ(error("c_targetTime=-5", kUsedByBuild), "");  // not the build's
    EXPECT_EQ(error("c_levelFactor=1", kUsedByPlayer), "");
    EXPECT_EQ(error("c_vis=0", kUsedByPlayer), "");
    Constants defaults;
    EXPECT_NO_THROW(validateConstants(defaults, kUsedByAny));
}

TEST(Constants, ConfigFile) {
    TempDir dir;
    const std::string path = dir.file("c.conf");
    std::string text = "# tuned\nc_memory = 1000\n\n  c_fore=0.5   # comment\n";
    writeFile(path, std::vector<uint8_t>(text.begin(), text.end()));
    Constants c;
    loadConstantsFile(c, path);
    EXPECT_EQ(c.memory, 1000);
    EXPECT_EQ(c.fore, 0.5);
    text = "c_memory = 1\nc_fore = x\n";
    writeFile(path, std::vector<uint8_t>(text.begin(), text.end()));
    try {
        loadConstantsFile(c, path);
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ":2: ", 0), 0u) << e.what();
    }
    EXPECT_THROW(loadConstantsFile(c, dir.file("missing.conf")), std::runtime_error);
}

// A hand-written settings file is read a bounded line at a time: a line over kMaxSettingLine
// (here a file of 1 MiB without a newline) is refused at once, naming the file and the line,
// by both readers; a last line without its newline still counts.
TEST(Constants, OverlongLinesAreRefusedByTheConstantsAndCalibrationReaders) {
    TempDir dir;
    const std::string path = dir.file("long.conf");
    std::string text = "# hand-written\n" + std::string(1 << 20, 'x');
    writeFile(path, std::vector<uint8_t>(text.begin(), text.end()));
    Constants c;
    for (const auto& read : {std::function<void()>([&] { loadConstantsFile(c, path); }),
                             std::function<void()>([&] { readCalibration(path); })}) {
        try {
            read();
            FAIL() << "an overlong line was accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()), path + ":2: line longer than " + std::to_string(kMaxSettingLine) + " characters");
        }
    }
    text = "c_memory = 1000\nc_fore = 0.25";  // no final newline
    writeFile(path, std::vector<uint8_t>(text.begin(), text.end()));
    loadConstantsFile(c, path);
    EXPECT_EQ(c.fore, 0.25);
}

// The settings readers say why a file cannot be read (a folder read as "read error", a missing
// file gave no reason), and a calibration names each value once (three lines of c_textured made
// a complete file until stop 49).
TEST(Constants, UnreadableSettingsFilesAndRepeatedCalibrationNames) {
    TempDir dir;
    const std::string missing = dir.file("missing.conf");
    const auto message = [](const std::function<void()>& read) {
        try {
            read();
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    Constants c;
    EXPECT_EQ(message([&] { readCalibration(missing); }), missing + ": cannot read calibration file (No such file or directory)");
    EXPECT_EQ(message([&] { loadConstantsFile(c, missing); }), missing + ": cannot read constants file (No such file or directory)");
    const std::string folder = dir.path.string();
    EXPECT_EQ(message([&] { readCalibration(folder); }), folder + ": a folder, not a calibration file");
    EXPECT_EQ(message([&] { loadConstantsFile(c, folder); }), folder + ": a folder, not a constants file");
    const std::string path = dir.file("twice.conf");
    const std::string text = "c_textured = 0.5\nc_textured = 0.5\nc_textured = 0.5\n";
    writeFile(path, std::vector<uint8_t>(text.begin(), text.end()));
    EXPECT_EQ(message([&] { readCalibration(path); }), path + ":2: 'c_textured' given twice");
    EXPECT_EQ(shownBytes(std::string("a\0\xFF\xC3\xA9\x7F", 6)), "a\\x00\\xFF\xC3\xA9\\x7F");  // NUL, not UTF-8, é, DEL
    EXPECT_EQ(shownBytes(std::string(50, 'x')), std::string(40, 'x') + "...");
    EXPECT_EQ(shownBytes("\xC2\x85\xC0\xAF\xF8"), "\\xC2\\x85\\xC0\\xAF\\xF8");  // a C1 control, an overlong lead, F8
    // overlong 3- and 4-byte forms, a surrogate, above U+10FFFF; then the edges that are valid
    EXPECT_EQ(shownBytes("\xE0\x80\xAF|\xF0\x80\x80\xAF|\xED\xA0\x80|\xF4\x90\x80\x80"),
              "\\xE0\\x80\\xAF|\\xF0\\x80\\x80\\xAF|\\xED\\xA0\\x80|\\xF4\\x90\\x80\\x80");
    EXPECT_EQ(shownBytes("\xE0\xA0\x80\xED\x9F\xBF\xF0\x90\x80\x80\xF4\x8F\xBF\xBF"),
              "\xE0\xA0\x80\xED\x9F\xBF\xF0\x90\x80\x80\xF4\x8F\xBF\xBF");
}

TEST(Constants, PairsRoundTripAndPrint) {
    Constants c;
    c.textured = 0.1 + 0.2;  // not exactly representable in short decimal
    Constants d;
    for (const auto& [name, value] : constantsAsPairs(c)) setConstant(d, name, value);
    for (const ConstantInfo& info : constantTable()) EXPECT_EQ(c.*info.field, d.*info.field) << info.name;
    std::ostringstream os;
    printConstants(os, Constants{}, kUsedByBuild);
    EXPECT_EQ(os.str(), "constants: c_desiredTris=900 c_levelFactor=4 c_textured=0.127\n");
    os.str("");
    printConstants(os, Constants{}, kUsedByPlayer);
    EXPECT_EQ(os.str(), "constants: c_vis=1.275 c_fore=0.45 c_targetTime=30 c_hystSwitch=1500 c_hystLimit=4510 c_memory=935\n");
}

TEST(Constants, FileAppliesOnlyTheConstantsOfItsUseAndNamesTheOthers) {
    TempDir dir;
    const std::string path = dir.file("all.conf");
    std::ofstream(path) << "c_desiredTris = 300\nc_vis = 2\nc_memory = 1000\n";
    Constants c;
    EXPECT_EQ(loadConstantsFile(c, path, kUsedByBuild), (std::vector<std::string>{"c_vis", "c_memory"}));
    EXPECT_EQ(c.desiredTris, 300);
    EXPECT_EQ(c.vis, Constants{}.vis);
    EXPECT_EQ(loadConstantsFile(c, path, kUsedByPlayer), std::vector<std::string>{"c_desiredTris"});
    EXPECT_EQ(c.vis, 2);
    EXPECT_THROW(loadConstantsFile(c, dir.file("missing.conf")), InputError);
}

}  // namespace
}  // namespace hlod::test
