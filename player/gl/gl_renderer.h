// OpenGL renderer: offscreen through EGL (Mesa surfaceless / any GPU) or in a GLFW window.
// Also what is built on it: calibration of the cost model (thesis §3.3 eq. 3.1, Table 6.1
// c_textured; Funkhouser & Séquin 1993 §4) and 6-DOF navigation for `hlod view` (thesis Ch. 6).
#pragma once

#include "formats/calibration.h"
#include "player/renderer.h"

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

struct GLFWwindow;

namespace hlod {

struct GlOptions {
    int width = 1280, height = 720;
    bool window = false;       // true: GLFW window (needs a display); false: EGL offscreen
    bool timerQueries = false; // false: frame time measured around glFinish
    std::string title = "hlod";
};

// No OpenGL 3.3 context can be had here (no EGL display or driver, no window system): what a
// caller may treat as "no GPU stack", unlike a context that exists but fails to set up the
// renderer (a shader that does not compile, an incomplete framebuffer: std::runtime_error).
struct NoGlContext : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Throws NoGlContext, or std::runtime_error for any other failure, with one line.
std::unique_ptr<Renderer> makeGlRenderer(const GlOptions& options);

// The GLFW window of a renderer made with window = true; nullptr for any other renderer.
GLFWwindow* glfwWindowOf(Renderer& renderer);

// Grey (0..1) that FrameOptions::colorByLevel gives to `level`: hlod0 darkest, each finer
// level lighter, 8 distinct greys repeating (as the grey-level LOD figures of the thesis and Funkhouser & Séquin 1993).
float levelGrey(uint32_t level);

// --- Calibration (`hlod calibrate`): the model and its file are in formats/calibration.h ----

struct CalibrationOptions {
    std::vector<uint32_t> triangleCounts = {2000, 25000, 50000, 100000, 150000};
    int warmupFrames = 2;
    int frames = 7;  // the median of these is kept per batch
    // Per-pixel term: a textured batch of pixelTriangles seen from these multiples of the
    // calibration camera's distance (coverage falls as 1 / k^2). viewportPixels = 0: not measured.
    std::vector<double> pixelDistances = {1, 1.25, 1.5, 2, 3, 4};
    uint32_t pixelTriangles = 2000;
    double viewportPixels = 0;
};

// Least squares line through (x, y); throws std::invalid_argument for fewer than two
// distinct x or mismatched sizes.
LinearFit fitLine(std::span<const double> x, std::span<const double> y);

// c_textured from the per-triangle times (see above); throws std::invalid_argument unless
// both are positive.
double texturedWeight(double perTexturedTriMs, double perUntexturedTriMs);

// A synthetic node: a grid of about `triangles` triangles in the plane z = 0 that covers
// about 2/3 of a 60° 16:9 view from calibrationCamera(); textured with a 1024² image or flat.
DecodedNode calibrationBatch(uint32_t id, uint32_t triangles, bool textured);
uint32_t calibrationBatchTriangles(uint32_t triangles);  // the triangles calibrationBatch draws
Camera calibrationCamera(double aspect);

// Draws the batches on `renderer` (any Renderer) and fits the model, with the per-pixel slope
// when options.viewportPixels > 0 (a negative fitted slope, noise, is stored as 0). Throws
// std::runtime_error when the measurements give no usable (positive) per-triangle cost.
Calibration calibrate(Renderer& renderer, double aspect, const CalibrationOptions& options);

// --- Navigation (`hlod view`) --------------------------------------------------------------
// One step of free 6-DOF flight in the camera's own frame: no up-vector constraint, any speed,
// zero input leaves the camera exactly where it is.
struct NavigationInput {
    double move[3] = {0, 0, 0};   // right, up, backward (camera axes), each in [-1, 1]
    double yaw = 0, pitch = 0, roll = 0;  // radians, about camera up, right and view axes
    double speed = 1;             // metres per second
    double dt = 0;                // seconds
};
void navigate(Camera& camera, const NavigationInput& input);

}  // namespace hlod
