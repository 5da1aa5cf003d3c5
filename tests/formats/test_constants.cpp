// Constants of thesis Table 6.1: names, parsing, bad values, config files, printing.
#include "formats/constants.h"

#include "helpers.h"

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
