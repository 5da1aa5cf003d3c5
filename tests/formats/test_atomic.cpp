// Atomic writing (FORMAT.md §Atomic writing): an unfinished or killed writer leaves nothing at
// PATH that opens as a database, and an existing database stays intact until finish().
#include "helpers.h"

#include "tests/support/synthetic.h"

#include <sys/wait.h>
#include <unistd.h>

namespace hlod::test {
namespace {

std::vector<std::string> filesIn(const std::filesystem::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir)) out.push_back(e.path().filename().string());
    return out;
}

NodeInput smallNode() {
    NodeInput in;
    in.bounds = {{0, 0, 0}, {1, 1, 1}};
    in.blobs.push_back(encodeGeometry(gridMesh(2), {}));
    return in;
}

TEST(Atomic, UnfinishedWriterLeavesNothing) {
    TempDir dir;
    const std::string path = dir.file("a.hlod");
    {
        Writer w(path);
        w.addNode(smallNode());
        EXPECT_EQ(filesIn(dir.path).size(), 1u);  // the temporary file
        EXPECT_FALSE(std::filesystem::exists(path));
    }
    EXPECT_TRUE(filesIn(dir.path).empty());
}

TEST(Atomic, ExistingDatabaseStaysIntactUntilFinish) {
    TempDir dir;
    const std::string path = dir.file("a.hlod");
    SyntheticOptions o;
    o.levels = 1;
    writeSyntheticDatabase(path, o);
    const std::vector<uint8_t> before = readFile(path);
    {
        Writer w(path);
        w.addNode(smallNode());
        EXPECT_EQ(readFile(path), before);
        EXPECT_EQ(Database::open(path).skeleton().nodes.size(), 4u);
    }
    EXPECT_EQ(readFile(path), before);  // abandoned writer: old database untouched
    Writer w(path);
    w.addNode(smallNode());
    w.finish();
    EXPECT_EQ(Database::open(path).skeleton().nodes.size(), 1u);
    EXPECT_EQ(filesIn(dir.path), std::vector<std::string>{"a.hlod"});
}

TEST(Atomic, KilledWriterLeavesNoValidDatabase) {
    TempDir dir;
    const std::string path = dir.file("a.hlod");
    pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        Writer w(path);
        w.addNode(smallNode());
        w.addNode(smallNode());
        _exit(0);  // killed: no destructor, no finish
    }
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_FALSE(std::filesystem::exists(path));
    std::vector<std::string> left = filesIn(dir.path);
    ASSERT_EQ(left.size(), 1u);
    EXPECT_EQ(left[0].rfind("a.hlod.tmp-", 0), 0u);
    EXPECT_THROW(Database::open(dir.file(left[0])), FormatError);  // zero header: not a database
}

TEST(Atomic, WriterRejectsBadLinksAndSlots) {
    TempDir dir;
    Writer w(dir.file("a.hlod"));
    NodeInput orphan = smallNode();
    orphan.parent = 3;
    EXPECT_THROW(w.addNode(orphan), std::invalid_argument);
    NodeInput slot = smallNode();
    slot.blobs[0].textureSlot = 0;  // a geometry blob, not a texture
    EXPECT_THROW(w.addNode(slot), std::invalid_argument);
    EXPECT_THROW(Writer(dir.file("no-such-dir/a.hlod")), std::runtime_error);
}

}  // namespace
}  // namespace hlod::test
