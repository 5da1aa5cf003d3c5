// Interrupted runs (SIGINT, SIGTERM, SIGHUP: Ctrl-C, `kill`, a closed terminal) leave no
// temporaries: every temporary file or folder of hlod is made by createTemporary, which records
// it; forgetTemporary takes it off the record once it is an output (renamed, inside
// uninterrupted()) or removed by its owner. A process that called removeTemporariesOnInterrupt()
// (hlod's main) removes what is recorded when such a signal arrives, then ends by that signal
// (status 128 + N in a shell), as it would have without the handler. Until stop 45 a Ctrl-C left
// them all (224 MB for a synthesised city) until the next run to the same output swept them
// (formats/temp_files.h: SIGKILL still leaves them to that sweep).
#pragma once

#include <functional>
#include <string>

namespace hlod {

// mkstemp (folder false: returns the open descriptor) or mkdtemp (folder true: returns 0) of
// `pattern` (...XXXXXX, completed in place), recorded; -1 with errno set when it fails.
int createTemporary(std::string& pattern, bool folder);
// Runs `step` (the renames that publish a temporary, and its forgetTemporary) with no interruption
// sweep during it: a sweep between removing an earlier output and renaming the new one onto its
// name would leave neither.
void uninterrupted(const std::function<void()>& step);
// Takes `path` off the record (its owner removed it, or it was never recorded).
void forgetTemporary(const std::string& path);

// Blocks SIGINT, SIGTERM and SIGHUP in this thread and every thread it starts later, and starts
// the thread that waits for them: call it first in main(), before any other thread exists.
void removeTemporariesOnInterrupt();

// For an interactive loop (`hlod view`): after deferInterrupts(), the first such signal no longer
// ends the process but is kept for interruptedBy() (0 until then), so the loop can end as its quit
// key does (the flight recorded) and end with resumeInterrupts(): the sweep, then the end by that
// signal. A second signal ends the process at once. (Until stop 49 Ctrl-C lost the flight.)
void deferInterrupts();
int interruptedBy();
// Ends deferring: a signal kept, or one that arrives while this runs, ends the process now
// (endByInterrupt); later ones end it at once. The loop's last step, so that a signal after its
// last interruptedBy() is not lost (`hlod view` exited 0 for one until stop 51).
void resumeInterrupts();
[[noreturn]] void endByInterrupt(int signal);

}  // namespace hlod
