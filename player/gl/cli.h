// Subcommands contributed by the OpenGL renderer (registered in player/cli/main.cpp).
#pragma once

namespace CLI {
class App;
}

namespace hlod::cli {

// `hlod calibrate`: measure the render-time model and write a constants file (c_textured).
void addCalibrate(CLI::App& app, int& status);
// `hlod view DB`: interactive 6-DOF window on a database, optional path recording.
void addView(CLI::App& app, int& status);

}  // namespace hlod::cli
