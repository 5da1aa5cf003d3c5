// Temporary files and folders that a run killed by SIGKILL cannot remove itself: each is named
// PREFIX-PID-XXXXXX (mkstemp / mkdtemp), and the next run that makes one with the same PREFIX
// removes those whose PID no longer runs (README "Reliability"). A PID reused by an unrelated
// process keeps its stale temporary until that process ends.
#pragma once

#include <string>

namespace hlod {

// "PREFIX-PID-XXXXXX" for this process, ready for mkstemp / mkdtemp.
std::string temporaryPattern(const std::string& prefix);
// Removes FOLDER/NAME-PID-* (files or folders) where PREFIX = FOLDER/NAME and PID is not a
// running process; errors are ignored (another run may remove them at the same time).
void removeStaleTemporaries(const std::string& prefix);

}  // namespace hlod
