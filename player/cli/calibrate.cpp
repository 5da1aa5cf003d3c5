// `hlod calibrate`: measures on this machine what thesis Table 6.1 says c_textured is set from
// ("measured render time", §3.3) plus the per-triangle cost and fixed overhead the feedback
// loop of §4.2 starts from, and writes them to a calibration file (formats/calibration.h) that
// `hlod build --calibration` and `hlod play --calibration` read.
#include "formats/temp_files.h"
#include "player/cli/subcommands.h"

#include "player/gl/gl_renderer.h"

#include <CLI/CLI.hpp>

#include <iomanip>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>

namespace hlod::cli {
namespace {

struct CalibrateArgs {
    std::string output = "calibration.conf";
    GlOptions gl;
    CalibrationOptions calibration;
};

void printCalibration(std::ostream& os, const Calibration& c) {
    os << "renderer: " << c.renderer << "\n" << std::setprecision(4);
    for (const CalibrationSample& s : c.samples)
        os << "  " << std::setw(10) << (s.textured ? "textured" : "untextured") << std::setw(9) << s.triangles
           << " triangles " << std::setw(9) << s.ms << " ms\n";
    os << "fixed overhead (empty frame): " << c.fixedOverheadMs << " ms\n"
       << "textured:   " << c.textured.intercept << " ms + " << c.textured.slope * 1e6 << " ns/triangle\n"
       << "untextured: " << c.untextured.intercept << " ms + " << c.untextured.slope * 1e6 << " ns/triangle\n"
       << "c_textured = " << c.cTextured << "  (ms per unit of eq. 3.1 cost: " << c.msPerCost << ")\n";
    for (const auto& [pixels, ms] : c.pixelSamples)
        os << "  " << std::setw(10) << "textured" << std::setw(10) << pixels << " pixels    " << std::setw(9) << ms << " ms\n";
    os << "per pixel:  " << c.msPerPixel * 1e6 << " ns/pixel (FS C3 / GB t_pix: --policy-set P.pixel_ms=" << c.msPerPixel
       << ")\n";
}

int runCalibrate(const CalibrateArgs& args) {
    std::set<uint32_t> sizes;  // the batches are grids: 1 and 2 triangles are both 2 (fitLine failed after measuring)
    for (uint32_t n : args.calibration.triangleCounts) sizes.insert(calibrationBatchTriangles(n));
    if (sizes.size() < 2)
        throw std::invalid_argument("--triangles: every batch is a grid of " + std::to_string(*sizes.begin()) +
                                    " triangles; fitting a line needs two sizes (give counts further apart)");
    TextFileWriter file(args.output, "calibration");  // an unwritable OUT fails before measuring
    std::unique_ptr<Renderer> renderer = makeGlRenderer(args.gl);
    const double aspect = static_cast<double>(args.gl.width) / args.gl.height;
    CalibrationOptions options = args.calibration;
    options.viewportPixels = double(args.gl.width) * args.gl.height;
    const Calibration calibration = calibrate(*renderer, aspect, options);
    printCalibration(std::cout, calibration);
    writeCalibration(calibration, file.stream());
    file.commit();
    std::cout << "wrote " << args.output << "\n";
    // `hlod play --calibration` refuses an overhead that leaves no time to draw (checkOverhead);
    // said here, where the frame size that caused it is known (a silent write until stop 49).
    if (const double target = Constants{}.targetTimeMs; calibration.fixedOverheadMs >= target)
        std::cerr << "hlod calibrate: warning: fixed_overhead_ms " << calibration.fixedOverheadMs << " is not below c_targetTime's default "
                  << target << " ms: `hlod play --calibration` refuses this file unless given a larger c_targetTime (a "
                  << "smaller --width/--height measures less)\n";
    return kExitOk;
}

}  // namespace

void addCalibrate(CLI::App& app, int& status) {
    auto args = std::make_shared<CalibrateArgs>();
    CLI::App* sub = app.add_subcommand("calibrate", "measure textured/untextured triangle costs and the fixed overhead "
                                                    "with OpenGL; write them to a calibration file");
    sub->add_option("-o,--output", args->output, "calibration file to write (formats/calibration.h)")
        ->capture_default_str()->check(nonEmptyPath());
    sub->add_option("--width", args->gl.width, "frame width")->capture_default_str()->check(CLI::Range(1, 16384));
    sub->add_option("--height", args->gl.height, "frame height")->capture_default_str()->check(CLI::Range(1, 16384));
    sub->add_flag("--timer-queries", args->gl.timerQueries, "time frames with GL_TIME_ELAPSED instead of glFinish");
    sub->add_option("--frames", args->calibration.frames, "frames per batch (median kept)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    sub->add_option("--triangles", args->calibration.triangleCounts, "triangle counts of the batches, 2 to 64 of them")
        ->check(CLI::Range(1u, 20000000u))
        ->expected(2, 64);
    sub->callback([args, &status] { status = runGuarded("calibrate", [&] { return runCalibrate(*args); }); });
}

}  // namespace hlod::cli
