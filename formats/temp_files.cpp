// Stale temporaries of killed runs (formats/temp_files.h).
#include "formats/temp_files.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <filesystem>

namespace hlod {

std::string temporaryPattern(const std::string& prefix) { return prefix + "-" + std::to_string(getpid()) + "-XXXXXX"; }

void removeStaleTemporaries(const std::string& prefix) {
    namespace fs = std::filesystem;
    const fs::path p(prefix);
    const fs::path folder = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const std::string start = p.filename().string() + "-";
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= start.size() + 7 || name.compare(0, start.size(), start) != 0) continue;
        const char* first = name.data() + start.size();
        const char* last = name.data() + name.size() - 7;  // "-XXXXXX" made by mkstemp / mkdtemp
        long pid = 0;
        const auto [ptr, error] = std::from_chars(first, last, pid);
        if (error != std::errc() || ptr != last || *last != '-' || pid <= 0) continue;
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // running (or not ours to ask)
        std::error_code ignored;
        fs::remove_all(it->path(), ignored);
    }
}

}  // namespace hlod
