// The render-time model that `hlod calibrate` measures and its file (one struct, one reader, one
// writer). Frame time is modelled as time = overhead + perTri * N for N triangles of one kind.
// Eq. 3.1 weighs textured triangles by c and untextured by (1 - c), so the weights are in the
// ratio of the per-triangle times: c / (1 - c) = perTexturedTri / perUntexturedTri, i.e.
// c_textured = perTexturedTri / (perTexturedTri + perUntexturedTri). A node of cost (eq. 3.1)
// then renders in cost * msPerCost with msPerCost = perTexturedTri + perUntexturedTri.
//
// The file is "name = value" lines ('#' comments): renderer, c_textured, ms_per_cost,
// fixed_overhead_ms, textured_ms_per_tri, untextured_ms_per_tri, textured_intercept_ms,
// untextured_intercept_ms, and (optional, 0 when absent) ms_per_pixel; the measured samples
// follow as comments. `hlod build --calibration`
// takes c_textured from it, `hlod play --calibration` the initial v_time and the overhead.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace hlod {

// The longest frame time, in ms, a calibration or a player option may claim (a fixed overhead,
// v_time per unit of cost, the cost model's overhead): a frame of 10 s is no interactive renderer.
inline constexpr double kMaxFrameMs = 1e4;

struct CalibrationSample {
    uint32_t triangles = 0;
    bool textured = false;
    double ms = 0;   // median frame time
};

struct LinearFit {
    double intercept = 0, slope = 0;
};

struct Calibration {
    std::string renderer;             // Renderer::name()
    double fixedOverheadMs = 0;       // empty frame (thesis §4.2 footnote: rendering disabled)
    LinearFit textured, untextured;   // ms = intercept + slope * triangles
    double cTextured = 0;             // eq. 3.1 weight
    double msPerCost = 0;             // ms per unit of eq. 3.1 cost
    // Per covered pixel (Funkhouser & Séquin 1993 §4 C3, Gobbetti & Bouvier 1999 t_pix): slope
    // of ms over the pixels a fixed textured batch covers from several distances, >= 0.
    double msPerPixel = 0;
    std::vector<std::pair<double, double>> pixelSamples;  // (covered pixels, median ms), as comments
    std::vector<CalibrationSample> samples;  // written as comments, not read back
};

// The file's text (name = value lines; the samples as comments).
void writeCalibration(const Calibration& calibration, std::ostream& out);
// Writes it through a TextFileWriter (formats/temp_files.h): PATH appears complete or not at all;
// throws std::runtime_error "PATH: cannot write calibration (reason)".
void writeCalibration(const Calibration& calibration, const std::string& path);

// Reads a file written by writeCalibration. Throws InputError "PATH[:LINE]: problem" for a
// missing or unreadable file, an unknown name, a value that is not a finite number (or is negative,
// except the fitted lines' intercepts), c_textured outside (0, 1], or a missing figure.
Calibration readCalibration(const std::string& path);

}  // namespace hlod
