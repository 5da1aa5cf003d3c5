// `hlod play DB --path FILE`: replays a camera path against a database with the engine of
// thesis Chapter 4 (selection §4.2, loading thread §4.3), in simulated time, and writes the
// per-frame statistics of Chapter 6 (player/STATS.md) plus a summary (text and --json).
#include "player/cli/subcommands.h"

#include "formats/calibration.h"
#include "formats/constants.h"
#include "formats/db.h"
#include "formats/image_io.h"
#include "formats/temp_files.h"
#include "player/cost_model_renderer.h"
#include "player/gl/gl_renderer.h"
#include "player/replay.h"
#include "player/stats.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <regex>
#include <vector>

namespace hlod::cli {
namespace {

struct PlayArgs {
    std::string db, path, renderer = "model", stats, json, framesDir;
    uint64_t maxFrames = 0, warmup = 100;
    uint32_t every = 1;
    bool syncLoader = false;
    int width = 1280, height = 720;
    PlayerOptions player;
    CostModel model;
    std::optional<double> flatRate;  // --model-ms-per-flat-tri; default: consistent with c_textured
    ConstantOptions constants{"play", kUsedByPlayer};
    std::string calibration;
    std::vector<std::string> policySettings;  // --policy-set P.NAME=VALUE
    std::string loader = "thesis", onMiss = "parent", units = "m";
};

std::unique_ptr<Renderer> makeRenderer(const PlayArgs& a) {
    if (a.renderer == "gl") return makeGlRenderer(GlOptions{a.width, a.height, false, false});
    return std::make_unique<CostModelRenderer>(a.model);
}

// --frames-dir holds this run's frames alone: an earlier run's frame_NNNNNN.png go (20 frames of a
// longer run stayed beside 5 new ones until stop 47), removed once the run is ready to draw, after
// a check before any work that none of them is an input of this run (a camera path or database
// under such a name was overwritten).
std::vector<std::filesystem::path> earlierFrames(const PlayArgs& a) {
    namespace fs = std::filesystem;
    static const std::regex frame(R"(frame_[0-9]{6,}\.png)");
    std::vector<fs::path> earlier;
    std::error_code ec;
    for (fs::directory_iterator it(a.framesDir, ec), end; !ec && it != end; it.increment(ec))
        if (std::regex_match(it->path().filename().string(), frame)) earlier.push_back(it->path());
    for (const fs::path& f : earlier) refuseOutputOverInputs(f.string(), {a.db, a.path, a.calibration, a.constants.configFile});
    return earlier;
}

int runPlay(PlayArgs& a) {
    checkOutputFile(a.stats, "statistics", {a.db, a.path, a.calibration, a.constants.configFile});  // before the run
    checkOutputFile(a.json == "-" ? "" : a.json, "summary", {a.db, a.path, a.calibration, a.constants.configFile});
    if (!a.stats.empty() && !a.json.empty() && a.json != "-" && sameOutput(a.stats, a.json))  // the CSV was lost under the JSON until stop 47
        throw std::invalid_argument("--stats and --json name the same file (" + a.json + ")");
    std::ostream& text = a.json == "-" ? std::cerr : std::cout;  // stdout holds the JSON alone
    Constants c;
    applyConstantOptions(a.constants, c, text);
    if (!a.calibration.empty()) {
        const Calibration calibration = readCalibration(a.calibration);
        a.player.initialVTime = calibration.msPerCost;
        a.player.overheadMs = calibration.fixedOverheadMs;
    }
    checkOverhead(a.player.overheadMs, c, a.calibration.empty() ? "--overhead-ms" : a.calibration + ": fixed_overhead_ms");
    a.player.metresPerUnit = parseUnits(a.units);
    if (!a.framesDir.empty() && a.renderer != "gl") throw std::invalid_argument("--frames-dir needs --renderer gl");
    const std::vector<std::filesystem::path> earlier = a.framesDir.empty() ? std::vector<std::filesystem::path>{} : earlierFrames(a);
    if (a.player.frameOptions.colorByLevel && a.renderer != "gl") throw std::invalid_argument("--color-by-level needs --renderer gl");
    if (a.every == 0) throw std::invalid_argument("--every must be at least 1");
    a.player.policyOptions = parsePolicySettings(a.policySettings);
    makePolicy(a.player.policy, a.player.policyOptions);  // an unknown name is a usage error before any work
    std::string names[] = {a.player.policy};
    checkPolicySettings(names, a.player.policyOptions);
    a.player.viewportHeight = a.height;
    a.player.loader = loaderKindByName(a.loader);
    a.player.onMiss = onMissByName(a.onMiss);
    CameraPath path = readCameraPath(a.path);
    Database db = Database::open(a.db);
    a.player.threadedLoader = !a.syncLoader;
    a.model.realTime = !a.syncLoader;  // the loading thread needs the frames' wall-clock time
    const double cTextured = databaseCTextured(db);
    a.model.msPerUntexturedTriangle =
        a.flatRate ? *a.flatRate : consistentUntexturedRate(a.model.msPerTexturedTriangle, cTextured);
    std::unique_ptr<Renderer> renderer = makeRenderer(a);
    a.player.onLoadFailure = [&db](const LoadFailure& f) { warnLoadFailure("play", db, f); };
    Player player(db, c, *renderer, a.player);
    if (!a.framesDir.empty()) createOutputFolder(a.framesDir, "PNG frames");
    std::error_code ignored;  // a frame another run removed meanwhile
    for (const std::filesystem::path& f : earlier) std::filesystem::remove(f, ignored);

    printConstants(text, c, kUsedByPlayer);
    std::vector<std::pair<std::string, std::string>> info = {
        {"database", a.db},
        {"path", a.path},
        {"renderer", renderer->name()},
        {"policy", a.player.policy},
        {"model_ms_per_tri", a.renderer == "model" ? std::to_string(a.model.msPerTexturedTriangle) : "-"},
        {"model_ms_per_flat_tri", a.renderer == "model" ? std::to_string(a.model.msPerUntexturedTriangle) : "-"},
        {"c_textured", formatConstant(cTextured) + " (the database's: eq. 3.1 weights of its node costs)"},
        {"memory_budget_bytes", std::to_string(a.player.memoryBudget)},
        {"loader", a.syncLoader ? "synchronous" : "thread"},
        {"loader_policy", loaderKindName(a.player.loader)},
        {"on_miss", onMissName(a.player.onMiss)}};
    appendLoaderInfo(info, a.player);
    info.insert(info.end(), {
        {"require_loaded_children", a.player.requireLoadedChildren ? "yes" : "no"},
        {"failed_load", a.player.strictLoads ? "fatal (--strict)" : "skipped, parent drawn"},
        {"overhead_ms", std::to_string(player.overheadMs())},
        {"initial_v_time", std::to_string(player.vTime())},
        {"lookahead_s", std::to_string(a.player.lookaheadSeconds)},
        {"teleport_speed", std::to_string(a.player.teleportSpeed) + " m/s"},
        {"units", a.units + " (" + formatConstant(a.player.metresPerUnit) + " m a database unit)"},
        {"v_time_gain", std::to_string(a.player.vTimeGain)},
        {"share_band", std::to_string(a.player.shareLoop.band)},
        {"share_gain", std::to_string(a.player.shareLoop.gain)},
        {"share_leak", std::to_string(a.player.shareLoop.leak)},
        {"share_step", std::to_string(a.player.shareLoop.step)},
        {"initial_hyst", std::to_string(a.player.initialHystSwitches * c.hystSwitch)},
        {"time", "simulated (camera sampled at the sum of measured frame times)"}});
    for (const auto& [k, v] : info) text << k << ": " << v << '\n';
    std::optional<TextFileWriter> csv;  // renamed into place when the run completes
    if (!a.stats.empty()) csv.emplace(a.stats, "statistics");
    if (csv) writeStatsPreamble(csv->stream(), c, info, player.levelCount());

    ReplayOptions ro;
    ro.maxFrames = a.maxFrames;
    ro.aspect = double(a.width) / a.height;
    auto frames = replayPath(player, path, ro, [&](const FrameStats& s) {
        if (csv) writeStatsRow(csv->stream(), s, player.levelCount());
        if (!a.framesDir.empty() && s.frame % a.every == 0) {
            char name[64];
            std::snprintf(name, sizeof name, "/frame_%06llu.png", (unsigned long long)s.frame);
            writePngFile(a.framesDir + name, renderer->readPixels());
        }
    });
    if (csv) csv->commit();
    if (a.maxFrames == 0 && frames.size() == ro.frameCap)
        std::cerr << "hlod play: warning: stopped after " << ro.frameCap << " frames, before the path's end (--frames N replays more)\n";
    if (!frames.empty()) warnTeleportingPath("play", path, a.player, frames.back().timeSeconds);
    StatsSummary summary = summarize(frames, a.warmup);
    printSummary(text, summary);
    if (a.json == "-") std::cout << summaryJson(summary, c) << '\n';
    else if (!a.json.empty()) writeTextFile(a.json, "summary", summaryJson(summary, c) + "\n");
    return 0;
}

}  // namespace

double databaseCTextured(const Database& db) {
    const std::string* meta = db.skeleton().findMeta("c_textured");
    Constants c;
    try {
        if (meta) setConstant(c, "c_textured", *meta);
    } catch (const std::invalid_argument&) {
        c.textured = -1;
    }
    if (!(c.textured > 0 && c.textured <= 1)) throw FormatError(db.path() + ": metadata c_textured is not in (0, 1]");
    return c.textured;
}

void addCostModelOptions(CLI::App& sub, CostModel& model, std::optional<double>& flatRate) {
    sub.add_option("--model-overhead-ms", model.overheadMs, "cost model: fixed ms per frame" + defaultText(model.overheadMs))
        ->check(finiteIn(0, kMaxFrameMs));
    sub.add_option("--model-ms-per-tri", model.msPerTexturedTriangle, "cost model: ms per textured triangle" + defaultText(model.msPerTexturedTriangle))
        ->check(finiteIn(0, 1));
    sub.add_option("--model-ms-per-flat-tri", flatRate,
                   "cost model: ms per untextured triangle (default: --model-ms-per-tri x (1 - c_textured) / "
                   "c_textured, the database's eq. 3.1 weights)")
        ->check(finiteIn(0, 1));
    sub.add_option("--model-noise", model.noise, "cost model: relative sd of per-frame noise" + defaultText(model.noise))
        ->check(finiteIn(0, 10));
    sub.add_option("--model-node-error", model.nodeError, "cost model: per-node cost error in [-e, e]" + defaultText(model.nodeError))
        ->check(finiteIn(0, 1));
    sub.add_option("--seed", model.seed, "cost model: noise and error seed (the same for every policy of `compare`)" + defaultText(model.seed))
        ->check(wholeNumber(model.seed));
}

void warnLoadFailure(const std::string& command, const Database& db, const LoadFailure& failure) {
    std::cerr << "hlod " << command << ": warning: " << db.path() << ": node " << failure.node << ": " << failure.problem
              << '\n';
}

void addPlay(CLI::App& app, int& status) {
    auto a = std::make_shared<PlayArgs>();
    CLI::App* sub = app.add_subcommand("play", "replay a camera path through the HLOD engine (thesis Chapter 4)");
    addDatabaseArgument(*sub, a->db);
    sub->add_option("--path", a->path, "camera path file (player/CAMERA_PATH.md; see `hlod path`)")->required();
    sub->add_option("--renderer", a->renderer, "model (cost model, draws nothing; default) or gl (OpenGL, EGL offscreen)")
        ->check(CLI::IsMember({"model", "gl"}));
    sub->add_option("--stats", a->stats, "per-frame CSV to write (player/STATS.md)")->check(nonEmptyPath());
    sub->add_option("--json", a->json, "write the summary as JSON to FILE ('-': stdout, and the text to stderr)")->check(nonEmptyPath());
    sub->add_option("--policy", a->player.policy, "selection policy (player/POLICIES.md): " + policyNamesList() +
                                                      "; default thesis");
    sub->add_option("--policy-set", a->policySettings, "policy setting P.NAME=VALUE (repeatable; player/POLICIES.md)");
    addMemoryBudgetOption(*sub, a->player.memoryBudget, "; lowest-priority nodes are evicted");
    sub->add_flag("--strict", a->player.strictLoads,
                  "a node that cannot be read or decoded ends the run (exit 1); by default it is skipped with "
                  "one warning, its parent stays drawn and failed_loads counts it");
    sub->add_flag("--require-loaded-children", a->player.requireLoadedChildren,
                  "switch to children only when all of them are loaded (thesis §5.2)");
    sub->add_option("--frames", a->maxFrames, "stop after N frames (0, the default: at the end of the path, at most 1,000,000)")
        ->check(wholeNumber(a->maxFrames));
    sub->add_option("--warmup", a->warmup, "frames excluded from the summary's distributions (at most half; default 100)")
        ->check(wholeNumber(a->warmup));
    sub->add_flag("--sync-loader", a->syncLoader,
                  "step the loader in the render thread: exactly repeatable and as fast as the CPU allows "
                  "(otherwise the cost model sleeps for each modelled frame time, so the loading thread gets "
                  "real time)");
    sub->add_option("--sync-loads", a->player.syncLoadsPerFrame, "with --sync-loader: nodes loaded per frame (0: none, hlod0 alone)" + defaultText(a->player.syncLoadsPerFrame))
        ->check(wholeNumber(a->player.syncLoadsPerFrame))
        ->needs("--sync-loader");
    addLoaderOptions(*sub, a->player, a->loader, a->onMiss);
    sub->add_option("--uploads", a->player.maxUploadsPerFrame, "GPU uploads per frame at most (0: none, hlod0 alone)" + defaultText(a->player.maxUploadsPerFrame))
        ->check(wholeNumber(a->player.maxUploadsPerFrame));
    sub->add_option("--v-time", a->player.initialVTime, "initial v_time in ms per unit of cost (default: measured)")
        ->check(finiteIn(0, kMaxFrameMs));
    sub->add_option("--overhead-ms", a->player.overheadMs, "fixed frame overhead (default: measured with drawing off)")
        ->check(finiteIn(0, kMaxFrameMs));
    sub->add_option("--calibration", a->calibration,
                    "calibration file of `hlod calibrate`: sets the initial v_time and the fixed overhead");
    sub->add_option("--lookahead", a->player.lookaheadSeconds,
                    "s: distance is also measured from the eye moved ahead by velocity x this (player/SELECTION.md)" + defaultText(a->player.lookaheadSeconds))
        ->check(finiteAtLeast(0));
    addTeleportSpeedOption(*sub, a->player.teleportSpeed);
    addUnitsOption(*sub, a->units);
    sub->add_option("--v-time-gain", a->player.vTimeGain, "first feedback loop: fraction of the v_time error corrected per frame" + defaultText(a->player.vTimeGain))
        ->check(finiteIn(0, 1));
    sub->add_option("--share-band", a->player.shareLoop.band,
                    "second feedback loop: frames outside target x (1 -+ band) move the hlod0 share" + defaultText(a->player.shareLoop.band))
        ->check(finiteIn(0, 1));
    sub->add_option("--share-gain", a->player.shareLoop.gain,
                    "second feedback loop: relative change of the hlod0 share per unit of relative frame-time error" + defaultText(a->player.shareLoop.gain))
        ->check(finiteAtLeast(0));
    sub->add_option("--share-leak", a->player.shareLoop.leak,
                    "second feedback loop: fraction of ln(target / share) recovered per frame" + defaultText(a->player.shareLoop.leak))
        ->check(finiteIn(0, 1));
    sub->add_option("--share-step", a->player.shareLoop.step,
                    "second feedback loop: largest relative change of the hlod0 share per frame" + defaultText(a->player.shareLoop.step))
        ->check(finiteIn(0, 1));
    sub->add_option("--initial-hyst", a->player.initialHystSwitches,
                    "hysteresis counter of a node evaluated first, in units of c_hystSwitch (default -1)")
        ->check(finiteNumber());
    sub->add_option("--frames-dir", a->framesDir, "write PNG frames here (needs --renderer gl)")->check(nonEmptyPath());
    sub->add_option("--every", a->every, "with --frames-dir: every Nth frame")
        ->check(wholeNumber(a->every))
        ->needs("--frames-dir");
    sub->add_flag("--color-by-level", a->player.frameOptions.colorByLevel, "shade nodes by level");
    sub->add_option("--width", a->width, "frame width (gl)" + defaultText(a->width))
        ->check(CLI::Range(1, 16384));
    sub->add_option("--height", a->height, "frame height (gl)" + defaultText(a->height))
        ->check(CLI::Range(1, 16384));
    addCostModelOptions(*sub, a->model, a->flatRate);
    addConstantOptions(*sub, a->constants);
    sub->callback([a, sub, &status] {
        status = runGuarded("play", [&] {
            checkLoaderOptions(*sub, a->loader);
            return runPlay(*a);
        });
    });
}

}  // namespace hlod::cli
