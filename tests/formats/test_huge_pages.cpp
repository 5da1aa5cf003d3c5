// formats/cli/huge_pages.h: `hlod` re-executes itself once with glibc.malloc.hugetlb=1 added to
// GLIBC_TUNABLES, keeps a user's other tunables, and leaves alone a process that opted out, that
// set the tunable itself, or that was re-executed already; a failed exec changes nothing; the
// heap is said to be on huge pages only with the tunable and a kernel that offers them.
// Checked in a forked child whose "program" is a shell printing what it was started with.
#include "helpers.h"

#include "formats/cli/huge_pages.h"

#include <fcntl.h>
#include <sys/wait.h>

namespace hlod::test {
namespace {

struct Env {
    const char* tunables = nullptr;  // nullptr: unset
    const char* hugePages = nullptr;
};

// What the child saw: "TUNABLES|HLOD_HUGE_PAGES" from the re-executed shell, or "returned:" and
// the same two values when reexecWithHugePages returned.
std::string childSees(const Env& env, const char* exe = "/bin/sh") {
    TempDir dir;
    const std::string out = dir.file("out.txt");
    const pid_t pid = fork();
    if (pid == 0) {
        const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        if (fd < 0 || dup2(fd, 1) < 0) _exit(3);
        env.tunables ? setenv("GLIBC_TUNABLES", env.tunables, 1) : unsetenv("GLIBC_TUNABLES");
        env.hugePages ? setenv("HLOD_HUGE_PAGES", env.hugePages, 1) : unsetenv("HLOD_HUGE_PAGES");
        char sh[] = "sh", c[] = "-c", script[] = "printf '%s|%s' \"$GLIBC_TUNABLES\" \"$HLOD_HUGE_PAGES\"";
        char* argv[] = {sh, c, script, nullptr};
        cli::reexecWithHugePages(argv, exe);
        const char* t = std::getenv("GLIBC_TUNABLES");
        const char* h = std::getenv("HLOD_HUGE_PAGES");
        std::printf("returned:%s|%s", t ? t : "", h ? h : "");
        std::fflush(stdout);
        _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    const std::vector<uint8_t> bytes = readFile(out);
    return std::string(bytes.begin(), bytes.end());
}

TEST(HugePages, ReexecutesOnceWithTheTunableAdded) {
    EXPECT_EQ(childSees({}), "glibc.malloc.hugetlb=1|1");
    EXPECT_EQ(childSees({"glibc.malloc.tcache_count=0", nullptr}), "glibc.malloc.tcache_count=0:glibc.malloc.hugetlb=1|1");
}

TEST(HugePages, LeavesAloneWhoOptedOutSetItOrWasReexecuted) {
    EXPECT_EQ(childSees({nullptr, "0"}), "returned:|0");
    EXPECT_EQ(childSees({"glibc.malloc.hugetlb=0", nullptr}), "returned:glibc.malloc.hugetlb=0|");
    EXPECT_EQ(childSees({nullptr, "1"}), "returned:|1");  // glibc may drop the tunable: no second exec
}

TEST(HugePages, AFailedExecChangesNothing) {
    EXPECT_EQ(childSees({}, "/nonexistent/hlod"), "returned:|");
    EXPECT_EQ(childSees({"glibc.malloc.tcache_count=0", nullptr}, "/nonexistent/hlod"), "returned:glibc.malloc.tcache_count=0|");
}

// The heap is on huge pages when the tunable is set and the kernel's mode allows them.
TEST(HugePages, HeapOnHugePagesNeedsTheTunableAndTheKernel) {
    TempDir dir;
    int files = 0;
    const auto mode = [&](const char* text) {
        const std::string path = dir.file("mode" + std::to_string(files++));
        std::ofstream(path) << text << "\n";
        return path;
    };
    const std::string madvise = mode("always [madvise] never"), always = mode("[always] madvise never"), never = mode("always madvise [never]");
    const char* before = std::getenv("GLIBC_TUNABLES");
    const std::string saved = before ? before : "";
    setenv("GLIBC_TUNABLES", "glibc.malloc.tcache_count=0:glibc.malloc.hugetlb=1", 1);
    EXPECT_TRUE(cli::heapOnHugePages(madvise.c_str()));
    EXPECT_TRUE(cli::heapOnHugePages(always.c_str()));
    EXPECT_FALSE(cli::heapOnHugePages(never.c_str()));
    EXPECT_FALSE(cli::heapOnHugePages(dir.file("absent").c_str()));
    setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=0", 1);
    EXPECT_FALSE(cli::heapOnHugePages(madvise.c_str()));
    unsetenv("GLIBC_TUNABLES");
    EXPECT_FALSE(cli::heapOnHugePages(madvise.c_str()));
    if (before) setenv("GLIBC_TUNABLES", saved.c_str(), 1);
}

}  // namespace
}  // namespace hlod::test
