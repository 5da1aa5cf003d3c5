// Temporary files and folders that a run killed by SIGKILL cannot remove itself: each is named
// PREFIX-hlodSPACE-PID-XXXXXX (mkstemp / mkdtemp; SPACE: 8 hex digits naming this host and PID
// namespace), and the next run in the same SPACE that makes one with the same PREFIX removes those
// of its user whose PID no longer runs (README "Reliability"). A PID reused by an unrelated process
// keeps its stale temporary until that process ends; another host's or container's are left to it.
// Until stop 47 the names were PREFIX-PID-XXXXXX, and a user's `hlod-build-2023-backup` folder (or
// an input named `DB.tmp-2024-v1.ply`) was swept as a killed run's.
#pragma once

#include <fstream>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>

#include <unistd.h>

namespace hlod {

// "PREFIX-hlodSPACE-PID-XXXXXX" for this process (or `pid`, a test's stale one), ready for mkstemp / mkdtemp.
std::string temporaryPattern(const std::string& prefix, long pid = ::getpid());
// Removes FOLDER/NAME-hlodSPACE-PID-XXXXXX (files or folders) of this user, where PREFIX =
// FOLDER/NAME, SPACE is this process's and PID is not a running process; errors are ignored
// (another run may remove them at the same time).
void removeStaleTemporaries(const std::string& prefix);

// An output PATH that exists must be a regular file (or a symbolic link to one, which the output
// replaces): a device, FIFO, socket or folder is never renamed over (as root, `-o /dev/null`
// replaced /dev/null before stop 36). Throws std::runtime_error "PATH: cannot write WHAT (exists
// and is not a regular file)".
void checkReplaceable(const std::string& path, const std::string& what);
// Throws std::invalid_argument "OUTPUT: is also an input (INPUT); write the output elsewhere" when
// OUTPUT and one of INPUTS name the same existing file (after symbolic links; hard links too), so
// an output never destroys what the run reads. Empty names are skipped.
void refuseOutputOverInputs(const std::string& output, std::initializer_list<std::string> inputs);
// Throws std::invalid_argument "OUTPUT: is inside an input folder (FOLDER); write the output
// elsewhere" when OUTPUT lies in FOLDER or below it (after symbolic links): a folder the run reads
// as a whole (a split's work folder, a shard), whose files it would replace.
void refuseOutputInsideFolder(const std::string& output, const std::string& folder);
// Whether two output paths name one file (after symbolic links, existing or not).
bool sameOutput(const std::string& a, const std::string& b);
// Whether PATH lies below FOLDER, after symbolic links (false when either cannot be resolved).
bool isInsideFolder(const std::string& path, const std::string& folder);
// The checks of a file output, before a run's work: a name ending in '/' (a folder) refused,
// refuseOutputOverInputs, then checkReplaceable. An empty OUTPUT (an option not given) passes.
void checkOutputFile(const std::string& output, const std::string& what, std::initializer_list<std::string> inputs);

// The first entry of FOLDER (recursively; a path relative to it) that `ours(relative, isFolder)`
// does not accept, or that is neither a regular file nor a folder; none when FOLDER holds only what
// a command writes. A folder output is replaced only when it holds nothing else: a marker file
// (tileset.json, manifest.json, shard.json) alone let a run delete a user's other files (until
// stop 45).
std::optional<std::string> foreignEntry(const std::string& folder,
                                        const std::function<bool(const std::string& relative, bool isFolder)>& ours);

// Creates FOLDER and its parents for a run's outputs. Throws std::runtime_error "FOLDER: cannot
// create the folder for WHAT (reason)" (one line, not std::filesystem's "filesystem error: ...").
void createOutputFolder(const std::string& folder, const std::string& what);

// A text output (a camera path, the statistics CSV, a JSON summary, compare's tables) written as
// PATH.tmp-hlodSPACE-PID-XXXXXX next to PATH and renamed onto it by commit(), so a failed write, a PATH that
// cannot be replaced (checkReplaceable: refused before anything is written) or an interrupted run leaves neither a half-written PATH nor the
// temporary (the destructor removes an uncommitted one; the next writer of PATH, a killed one's).
// Errors throw std::runtime_error "PATH: cannot write WHAT (reason)".
class TextFileWriter {
public:
    TextFileWriter(std::string path, std::string what);
    ~TextFileWriter();
    TextFileWriter(const TextFileWriter&) = delete;
    TextFileWriter& operator=(const TextFileWriter&) = delete;
    std::ostream& stream() { return out_; }
    void commit();

private:
    [[noreturn]] void fail(const std::string& reason);
    std::string path_, what_, temporary_;
    std::ofstream out_;
    bool committed_ = false;
};
void writeTextFile(const std::string& path, const std::string& what, const std::string& text);

// A staging folder next to `target` (TARGET.tmp-hlodSPACE-PID-XXXXXX), renamed to it (or its files moved
// into it) by its user's publish() when complete (then `kept`), removed otherwise (an interrupted
// run's at the signal, formats/interrupt.h; a killed run's by the next run's): a killed split,
// shard build or synth leaves no half-written TARGET.
struct StagingFolder {
    std::string path;
    bool kept = false;
    explicit StagingFolder(const std::string& target);
    void publish(const std::function<void()>& renames);  // runs the renames that make it TARGET
    ~StagingFolder();
    StagingFolder(const StagingFolder&) = delete;
    StagingFolder& operator=(const StagingFolder&) = delete;
};

}  // namespace hlod
