// OpenGL renderer: offscreen through EGL (Mesa surfaceless / any GPU) or in a GLFW window.
#pragma once

#include "player/renderer.h"

#include <memory>
#include <string>

namespace hlod {

struct GlOptions {
    int width = 1280, height = 720;
    bool window = false;       // true: GLFW window (needs a display); false: EGL offscreen
    bool timerQueries = false; // false: frame time measured around glFinish
};

// Throws std::runtime_error with one line when no GL context can be created.
std::unique_ptr<Renderer> makeGlRenderer(const GlOptions& options);

}  // namespace hlod
