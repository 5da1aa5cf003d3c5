// Build progress (progress.cpp): the stages of `hlod build` and `hlod split` with their figures,
// and the process's resident set size.
#pragma once

#include "formats/build_report.h"

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace hlod {

// progress.cpp: per-stage figures and a progress line at least every `interval` seconds while a
// stage runs: on a terminal one line redrawn in place (every 0.25 s), otherwise (a pipe, a log
// file) one plain line per `interval` (5 s), or one JSON object per line with --progress-json.
// A line names the stage, its percent, the textures loaded so far and an ETA only once the stage
// has a rate ("ETA --" before). Each stage also ends with one summary line. Thread-safe.
struct ProgressOptions {
    bool live = false;          // a terminal: redraw one line in place
    bool json = false;          // {"stage", "done", "total", "unit", "textures", "texels", "elapsed_s", "eta_s"} per line
    double interval = 5;        // seconds between lines when not live
    bool thread = true;         // a ticker thread calls poll(); false: the caller does (tests)
    std::function<double()> clock;  // seconds; empty = std::chrono::steady_clock
};
class Progress {
public:
    Progress(std::ostream& out, bool live);  // ProgressOptions{live}
    Progress(std::ostream& out, ProgressOptions options);
    ~Progress();
    void beginStage(const std::string& name, uint64_t totalItems, const std::string& unit = "tri");
    void advance(uint64_t items);
    void textureLoaded(uint64_t texels);  // a source texture decoded (work the item count does not show)
    void endStage();
    void message(const std::string& line);  // a warning or note, on its own line
    void poll();  // prints the progress line if one is due (the ticker thread calls it)
    std::vector<BuildStage> stages() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};
uint64_t currentRss();  // bytes
uint64_t peakRss();     // bytes
std::string formatBytes(uint64_t bytes);
// A path as one word of a POSIX shell, quoted when it needs it (META command, the commands warnings name).
std::string shellWord(const std::string& path);

}  // namespace hlod
