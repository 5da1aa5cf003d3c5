// Test support: runs the `hlod` tool (HLOD_BINARY, the path of the built binary, defined by the
// hlod_test_support target) or another program as a child process, without a shell, and
// captures its exit status, standard output and standard error separately.
#pragma once

#include <chrono>
#include <csignal>
#include <string>
#include <vector>

namespace hlod::test {

struct RunResult {
    int exitCode = -1;  // -1 when the process did not exit normally (signal) or could not start
    std::string out, err;
    std::string outAndErr() const { return out + err; }  // both streams, stdout first
};

struct RunOptions {
    std::vector<std::string> unsetEnv;  // environment variables removed for the child
};

// Runs argv[0] (searched in PATH when it has no '/') with argv[1..] as its arguments; standard
// input is /dev/null.
RunResult runProcess(const std::vector<std::string>& argv, const RunOptions& options = {});

// runProcess of HLOD_BINARY with `args` (the subcommand and its arguments).
RunResult runHlod(const std::vector<std::string>& args, const RunOptions& options = {});

// Starts HLOD_BINARY with `args` (output discarded) and sends it `signal` (SIGKILL by default)
// after `delay` if it is still running (the kill sweeps); false when it could not be started.
// SIGINT, SIGTERM and SIGHUP start at their default action (a test run in the background has them
// ignored). `waitStatus`, when given, receives waitpid's status.
bool runHlodAndKill(const std::vector<std::string>& args, std::chrono::microseconds delay, int signal = SIGKILL,
                    int* waitStatus = nullptr);

}  // namespace hlod::test
