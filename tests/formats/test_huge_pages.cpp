// formats/cli/huge_pages.h: `hlod` re-executes itself once with glibc.malloc.hugetlb=1 added to
// GLIBC_TUNABLES, keeps a user's other tunables, and leaves alone a process that opted out, that
// set the tunable itself, or that was re-executed already; a failed exec changes nothing.
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

}  // namespace
}  // namespace hlod::test
