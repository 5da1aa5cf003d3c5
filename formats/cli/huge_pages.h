// Transparent huge pages for the tool's heap (issue #14, pipeline/HUGE_PAGES.md).
// A build allocates and frees blocks of megabytes all the time (atlases, baked texels, bounding
// volume hierarchies, libjpeg's buffers); glibc maps each large block afresh, and touching it
// costs one page fault per 4 KiB: about a million faults for the facade benchmark, a fifth of its
// CPU time on the machine the issue is measured on (~10 us a fault in its VM). glibc >= 2.35
// asks the kernel for 2 MiB pages on those mappings (madvise MADV_HUGEPAGE, honoured when
// /sys/kernel/mm/transparent_hugepage/enabled is `madvise` or `always`) when the tunable
// glibc.malloc.hugetlb=1 is set, which glibc reads only when a process starts: so the tool
// re-executes itself once with it. Large blocks are still returned to the kernel on free, so peak
// RSS stays what it was. Opt out with HLOD_HUGE_PAGES=0, or by setting glibc.malloc.hugetlb
// yourself (e.g. GLIBC_TUNABLES=glibc.malloc.hugetlb=0); under valgrind or a debugger set one
// of them, since the re-executed process is a new image.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace hlod::cli {

// Whether malloc is glibc's. AddressSanitizer and ThreadSanitizer bring their own allocator, which
// never reads glibc.malloc.hugetlb: under them re-executing only doubles the start (~0.5 s a run
// of the ASan build, whose tests run `hlod` hundreds of times), so `hlod` does not.
// (GCC names them __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__; every sanitizer build of `hlod`
// is a GCC build: scripts/test.sh.)
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kGlibcMalloc = false;
#else
inline constexpr bool kGlibcMalloc = true;
#endif

// Replaces the process by `exe` (this program, by default) with argv and GLIBC_TUNABLES +=
// glibc.malloc.hugetlb=1, HLOD_HUGE_PAGES=1, unless HLOD_HUGE_PAGES is set (to 0 by a user who
// opts out, to 1 by the re-executed process: one re-execution at most, even where glibc drops the
// tunable) or the tunable is set already. Returns when it does nothing or the exec fails, with
// the environment as it was.
inline void reexecWithHugePages(char** argv, const char* exe = "/proc/self/exe") {
    if (std::getenv("HLOD_HUGE_PAGES")) return;
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    const std::string before = tunables ? tunables : "";
    if (before.find("glibc.malloc.hugetlb") != std::string::npos) return;
    const std::string after = before.empty() ? "glibc.malloc.hugetlb=1" : before + ":glibc.malloc.hugetlb=1";
    if (setenv("GLIBC_TUNABLES", after.c_str(), 1) != 0 || setenv("HLOD_HUGE_PAGES", "1", 1) != 0) return;
    execv(exe, argv);
    unsetenv("HLOD_HUGE_PAGES");
    if (tunables) setenv("GLIBC_TUNABLES", before.c_str(), 1);
    else unsetenv("GLIBC_TUNABLES");
}

// Whether this process's large heap blocks go on transparent huge pages: glibc.malloc.hugetlb=1
// in its GLIBC_TUNABLES (which glibc read at start) and the kernel's mode, `thpMode`, `madvise`
// or `always`. The build prints it and records it in its report.
inline bool heapOnHugePages(const char* thpMode = "/sys/kernel/mm/transparent_hugepage/enabled") {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (!tunables || !std::strstr(tunables, "glibc.malloc.hugetlb=1")) return false;
    std::ifstream in(thpMode);
    std::string mode;
    std::getline(in, mode);
    return mode.find("[madvise]") != std::string::npos || mode.find("[always]") != std::string::npos;
}

}  // namespace hlod::cli
