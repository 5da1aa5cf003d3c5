// `hlod compare DB --path P --policies thesis,none,...`: replays one camera path through each
// selection policy (player/policy.h) under identical conditions (synchronous loader, the same
// cost-model seed; optional fixed step, so that frame i is the same viewpoint for every policy,
// and preload, everything resident, as Funkhouser & Séquin 1993 §7 ran) and writes one table
// (player/compare.h) as text, CSV and JSON, a per-frame CSV, and gnuplot PNGs: frame time per
// policy (FS Fig. 7 style), visible vs displayed triangles (Gobbetti & Bouvier 1999) and the
// benefit gap to the oracle over time. player/POLICIES.md.
#include "player/cli/subcommands.h"

#include "formats/calibration.h"
#include "formats/constants.h"
#include "formats/db.h"
#include "formats/temp_files.h"
#include "player/compare.h"
#include "player/cost_model_renderer.h"
#include "player/gl/gl_renderer.h"
#include "player/replay.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace hlod::cli {
namespace {

struct CompareArgs {
    std::string db, path, policies, prefix, renderer = "model";
    std::vector<std::string> policySettings;
    double stepMs = 0;
    bool preload = false, plots = true;
    uint64_t maxFrames = 0, warmup = 100;
    int width = 1280, height = 720;
    PlayerOptions player;
    CostModel model;
    std::optional<double> flatRate;  // --model-ms-per-flat-tri; default: consistent with c_textured
    ConstantOptions constants{"compare", kUsedByPlayer};
    std::string loader = "thesis", onMiss = "parent", units = "m";
};

std::vector<std::string> splitNames(const std::string& list) {
    std::vector<std::string> names;
    std::stringstream in(list);
    for (std::string name; std::getline(in, name, ',');) {
        if (name.empty()) throw std::invalid_argument("--policies: empty policy name in '" + list + "'");
        makePolicy(name);  // unknown names are a usage error before any work
        if (std::find(names.begin(), names.end(), name) != names.end())  // two rows no table or CSV tells apart
            throw std::invalid_argument("--policies: '" + name + "' is given twice in '" + list + "'");
        names.push_back(name);
    }
    if (names.empty() || list.back() == ',') throw std::invalid_argument("--policies: empty policy name in '" + list + "'");
    return names;
}

PolicyRun runPolicy(const CompareArgs& a, const Database& db, const Constants& c, const CameraPath& path,
                    const std::string& policy) {
    std::unique_ptr<Renderer> renderer = a.renderer == "gl" ? makeGlRenderer(GlOptions{a.width, a.height, false, false})
                                                            : std::make_unique<CostModelRenderer>(a.model);
    PlayerOptions po = a.player;
    po.policy = policy;
    po.onLoadFailure = [&db](const LoadFailure& f) { warnLoadFailure("compare", db, f); };
    Player player(db, c, *renderer, po);
    uint64_t invalidCuts = 0;
    std::string firstInvalid;
    ReplayOptions ro;
    ro.maxFrames = a.maxFrames;
    ro.aspect = double(a.width) / a.height;
    ro.fixedStepMs = a.stepMs;
    const Skeleton& s = player.skeleton();
    std::vector<uint8_t> resident(s.nodes.size());
    std::vector<DrawnNode> drawn;
    const double still[3] = {0, 0, 0};
    const std::vector<FrameStats> frames = replayPath(player, path, ro, [&](const FrameStats& f) {
        View view = makeView(player.camera(), still, 0);  // as the frame saw it (fitClipPlanes)
        for (uint32_t id = 0; id < s.nodes.size(); ++id) resident[id] = player.resident(id);
        drawn.clear();
        for (const DrawItem& d : player.front()) drawn.push_back({d.node});
        std::string problem = checkCut(s, drawn, resident, [&](uint32_t id) { return frustumVis(view, s.nodes[id].bounds) >= 1; },
                                       player.frontSkipsBlocks());
        if (!problem.empty() && invalidCuts++ == 0) firstInvalid = "frame " + std::to_string(f.frame) + ": " + problem;
    });
    PolicyRun run = policyRun(policy, frames, a.warmup);  // the full frames go when this returns
    run.invalidCuts = invalidCuts;
    run.firstInvalid = std::move(firstInvalid);
    if (a.maxFrames == 0 && run.frames.size() == ro.frameCap)
        std::cerr << "hlod compare: warning: " << policy << " stopped after " << ro.frameCap
                  << " frames, before the path's end (--frames N replays more)\n";
    return run;
}

std::string framesCsv(const std::vector<PolicyRun>& runs, const PolicyRun* oracle) {
    std::ostringstream os;
    os << "policy,frame,time_s,target_ms,actual_ms,benefit,gap,tris_drawn,visible_tris,selection_ms\n";
    char buf[256];
    for (const PolicyRun& r : runs) {
        std::vector<double> gaps = oracle ? benefitGaps(r, *oracle) : std::vector<double>(r.frames.size(), NAN);
        for (size_t i = 0; i < r.frames.size(); ++i) {
            const CompareFrame& f = r.frames[i];
            std::string gap = std::isnan(gaps[i]) ? "" : std::to_string(gaps[i]);
            std::snprintf(buf, sizeof buf, "%s,%llu,%.6f,%.3f,%.4f,%.6g,%s,%llu,%llu,%.4f\n", r.policy.c_str(),
                          (unsigned long long)f.frame, f.timeSeconds, f.targetMs, f.actualMs, f.benefit, gap.c_str(),
                          (unsigned long long)f.triangles, (unsigned long long)f.visibleTriangles, f.selectionMs);
            os << buf;
        }
    }
    return os.str();
}

// gnuplot script with the data inline ($dN datablocks): one frame-time panel per policy (FS
// Fig. 7), visible vs displayed triangles per policy (GB 1999) and, with an oracle, the gap of
// each policy over time. Returns false if gnuplot fails.
bool plot(const std::string& prefix, const std::vector<PolicyRun>& runs, const PolicyRun* oracle) {
    std::ostringstream gp;
    for (size_t k = 0; k < runs.size(); ++k) {
        std::vector<double> gaps = oracle ? benefitGaps(runs[k], *oracle) : std::vector<double>();
        gp << "$d" << k << " << EOD\n";
        for (size_t i = 0; i < runs[k].frames.size(); ++i) {
            const CompareFrame& f = runs[k].frames[i];
            gp << i << ' ' << f.actualMs << ' ' << f.targetMs << ' '
               << (oracle && !std::isnan(gaps[i]) ? std::to_string(gaps[i]) : "NaN") << ' ' << f.triangles << ' '
               << f.visibleTriangles << '\n';
        }
        gp << "EOD\n";
    }
    gp << "set terminal pngcairo size 900," << 160 * runs.size() + 80 << " font ',9'\n"
       << "set output '" << prefix << "-frame-time.png'\n"
       << "set multiplot layout " << runs.size() << ",1 title 'frame time per policy (ms; dashed: target)'\n"
       << "set lmargin 10\nunset key\n";
    for (size_t k = 0; k < runs.size(); ++k)
        gp << "set ylabel '" << runs[k].policy << "'\n"
           << (k + 1 == runs.size() ? "set xlabel 'frame'\n" : "unset xlabel\n")
           << "plot $d" << k << " using 1:2 with lines lc rgb '#1f4e9a', $d" << k
           << " using 1:3 with lines dt 2 lc rgb '#b00000'\n";
    gp << "unset multiplot\n";
    // Gobbetti & Bouvier's "visible vs displayed triangles": full detail of the drawn visible
    // nodes against what was drawn.
    gp << "set output '" << prefix << "-triangles.png'\n"
       << "set multiplot layout " << runs.size() << ",1 title 'triangles per frame: visible at full detail (grey), displayed (blue)'\n";
    for (size_t k = 0; k < runs.size(); ++k)
        gp << "set ylabel '" << runs[k].policy << "'\n"
           << (k + 1 == runs.size() ? "set xlabel 'frame'\n" : "unset xlabel\n")
           << "plot $d" << k << " using 1:6 with lines lc rgb '#999999', $d" << k << " using 1:5 with lines lc rgb '#1f4e9a'\n";
    gp << "unset multiplot\n";
    if (oracle) {
        gp << "set terminal pngcairo size 900,420 font ',9'\nset output '" << prefix << "-gap.png'\n"
           << "set key outside right\nset xlabel 'frame'\nset ylabel '(B_oracle - B) / B_oracle'\n"
           << "set title 'benefit gap to the oracle'\nplot ";
        for (size_t k = 0; k < runs.size(); ++k)
            gp << (k ? ", " : "") << "$d" << k << " using 1:4 with lines title '" << runs[k].policy << "'";
        gp << "\n";
    }
    FILE* pipe = popen("gnuplot 2>/dev/null", "w");
    if (!pipe) return false;
    std::string text = gp.str();
    bool ok = std::fwrite(text.data(), 1, text.size(), pipe) == text.size();
    return pclose(pipe) == 0 && ok;
}

constexpr const char* kOutputSuffixes[] = {".txt", ".csv", ".json", "-frames.csv", "-frame-time.png", "-triangles.png", "-gap.png"};

int runCompare(CompareArgs& a) {
    for (const char* suffix : kOutputSuffixes)
        if (!a.prefix.empty()) {  // checked before the replays, not at their end
            const std::string name = suffix;
            checkOutputFile(a.prefix + name, name.ends_with(".png") ? "a plot" : name == "-frames.csv" ? "the frames" : "the table",
                            {a.db, a.path, a.constants.configFile});
        }
    Constants c;
    applyConstantOptions(a.constants, c, std::cout);
    std::vector<std::string> names = splitNames(a.policies);
    a.player.policyOptions = parsePolicySettings(a.policySettings);
    checkPolicySettings(names, a.player.policyOptions);
    if (a.stepMs < 0) throw std::invalid_argument("--step-ms must be >= 0");
    checkOverhead(a.player.overheadMs, c, "--overhead-ms");
    a.player.metresPerUnit = parseUnits(a.units);
    CameraPath path = readCameraPath(a.path);
    Database db = Database::open(a.db);
    a.player.threadedLoader = false;
    a.player.preload = a.preload;
    a.player.viewportHeight = a.height;
    a.player.loader = loaderKindByName(a.loader);
    a.player.onMiss = onMissByName(a.onMiss);
    // eq. 3.1 weights of the database's node costs, as `hlod play` applies them.
    const double cTextured = databaseCTextured(db);
    a.model.msPerUntexturedTriangle =
        a.flatRate ? *a.flatRate : consistentUntexturedRate(a.model.msPerTexturedTriangle, cTextured);
    printConstants(std::cout, c, kUsedByPlayer);
    std::cout << "c_textured: " << formatConstant(cTextured) << " (the database's: eq. 3.1 weights of its node costs)\n"
              << "units: " << a.units << " (" << formatConstant(a.player.metresPerUnit) << " m a database unit; teleports above "
              << formatConstant(a.player.teleportSpeed) << " m/s)\n";

    warnTeleportingPath("compare", path, a.player, path.duration());
    std::vector<PolicyRun> runs;
    for (const std::string& name : names) {
        runs.push_back(runPolicy(a, db, c, path, name));
        if (runs.back().invalidCuts)
            std::cerr << "hlod compare: warning: " << name << ": " << runs.back().invalidCuts
                      << " frames with an invalid cut (first: " << runs.back().firstInvalid << ")\n";
    }
    const PolicyRun* oracle = nullptr;
    for (const PolicyRun& r : runs)
        if (r.policy == "oracle" && a.stepMs > 0) oracle = &r;
    std::vector<CompareRow> rows = compareRows(runs, oracle);
    std::ostringstream text;
    writeCompareText(text, rows);
    std::cout << text.str();
    if (!oracle) std::cout << "gap: " << (a.stepMs > 0 ? "no oracle among the policies" : "needs --step-ms (aligned frames)") << '\n';
    if (!a.prefix.empty()) {
        std::vector<std::pair<std::string, std::string>> setup = {
            {"database", a.db}, {"path", a.path}, {"policies", a.policies}, {"renderer", a.renderer},
            {"step_ms", std::to_string(a.stepMs)}, {"preload", a.preload ? "yes" : "no"},
            {"warmup_frames", std::to_string(a.warmup)}, {"target_ms", std::to_string(c.targetTimeMs)},
            {"model_ms_per_tri", std::to_string(a.model.msPerTexturedTriangle)},
            {"model_ms_per_flat_tri", std::to_string(a.model.msPerUntexturedTriangle)},
            {"c_textured", formatConstant(cTextured)}, {"seed", std::to_string(a.model.seed)},
            {"loader_policy", a.loader}, {"on_miss", a.onMiss}};
        appendLoaderInfo(setup, a.player);
        // An earlier run's set goes first: an interrupted write, --no-plots or no oracle (no -gap.png)
        // never leaves this run's files beside an older run's (until stop 44 they were mixed).
        for (const char* suffix : kOutputSuffixes) {
            std::error_code ec;
            if (std::filesystem::is_regular_file(a.prefix + suffix, ec)) std::filesystem::remove(a.prefix + suffix, ec);
        }
        writeTextFile(a.prefix + ".txt", "the table", text.str());
        std::ostringstream csv;
        writeCompareCsv(csv, rows);
        writeTextFile(a.prefix + ".csv", "the table", csv.str());
        writeTextFile(a.prefix + ".json", "the table", compareJson(rows, setup) + "\n");
        writeTextFile(a.prefix + "-frames.csv", "the frames", framesCsv(runs, oracle));
        std::cout << "wrote " << a.prefix << ".txt, .csv, .json, -frames.csv\n";
        if (a.plots) {
            if (plot(a.prefix, runs, oracle))
                std::cout << "wrote " << a.prefix << "-frame-time.png, -triangles.png" << (oracle ? ", -gap.png" : "") << '\n';
            else
                std::cerr << "hlod compare: warning: gnuplot failed or is missing (Debian gnuplot-nox): no PNG plots\n";
        }
    }
    return 0;
}

}  // namespace

void addCompare(CLI::App& app, int& status) {
    auto a = std::make_shared<CompareArgs>();
    CLI::App* sub = app.add_subcommand("compare", "replay one path through several selection policies and tabulate them");
    addDatabaseArgument(*sub, a->db);
    sub->add_option("--path", a->path, "camera path file (player/CAMERA_PATH.md; see `hlod path`)")->required();
    sub->add_option("--policies", a->policies, "comma-separated policies: " + policyNamesList())->required();
    sub->add_option("--policy-set", a->policySettings, "policy setting P.NAME=VALUE (repeatable; player/POLICIES.md)");
    sub->add_option("--step-ms", a->stepMs, "fixed step: frame i sampled at i x this (ms); 0 (default): simulated time as `hlod play`")
        ->check(finiteAtLeast(0));
    sub->add_flag("--preload", a->preload, "decode and upload every node at start, never evict (everything resident)");
    sub->add_option("-o,--output", a->prefix, "write PREFIX.txt, .csv, .json, -frames.csv, -frame-time.png, -triangles.png, -gap.png")
        ->check(nonEmptyPath());
    bool* plots = &a->plots;  // a plain flag: CLI11 shows a negated one as "--no-plots{false}"
    sub->add_flag_callback("--no-plots", [plots] { *plots = false; }, "skip the gnuplot PNGs");
    sub->add_option("--frames", a->maxFrames, "stop each replay after N frames (0, the default: at the end of the path, at most 1,000,000)")
        ->check(wholeNumber(a->maxFrames));
    sub->add_option("--warmup", a->warmup, "frames excluded from the table (at most half; default 100)")
        ->check(wholeNumber(a->warmup));
    addMemoryBudgetOption(*sub, a->player.memoryBudget, "");
    sub->add_option("--sync-loads", a->player.syncLoadsPerFrame, "nodes loaded per frame (synchronous loader; 0: none, hlod0 alone)" + defaultText(a->player.syncLoadsPerFrame))
        ->check(wholeNumber(a->player.syncLoadsPerFrame));
    addLoaderOptions(*sub, a->player, a->loader, a->onMiss);
    sub->add_option("--renderer", a->renderer, "model (default) or gl")->check(CLI::IsMember({"model", "gl"}));
    sub->add_option("--width", a->width, "viewport width, pixels" + defaultText(a->width))
        ->check(CLI::Range(1, 16384));
    sub->add_option("--height", a->height, "viewport height, pixels (benefit and pixel thresholds)" + defaultText(a->height))
        ->check(CLI::Range(1, 16384));
    sub->add_option("--v-time", a->player.initialVTime, "initial v_time in ms per unit of cost (default: measured)")
        ->check(finiteIn(0, kMaxFrameMs));
    sub->add_option("--overhead-ms", a->player.overheadMs, "fixed frame overhead (default: measured)")
        ->check(finiteIn(0, kMaxFrameMs));
    addUnitsOption(*sub, a->units);
    addTeleportSpeedOption(*sub, a->player.teleportSpeed);
    addCostModelOptions(*sub, a->model, a->flatRate);
    addConstantOptions(*sub, a->constants);
    sub->callback([a, sub, &status] {
        status = runGuarded("compare", [&] {
            checkLoaderOptions(*sub, a->loader);
            return runCompare(*a);
        });
    });
}

}  // namespace hlod::cli
