// `hlod view DB`: the interactive walk-through of thesis Ch. 6 — a GLFW window, free 6-DOF
// navigation at any speed (standing still allowed), the Player of Ch. 4 choosing the nodes
// every frame, and optional recording of the flight to a camera path file
// (player/CAMERA_PATH.md) that `hlod play --path` replays.
#include "player/cli/subcommands.h"

#include "formats/constants.h"
#include "formats/interrupt.h"
#include "formats/temp_files.h"
#include "formats/up_axis.h"
#include "player/camera_path.h"
#include "player/gl/gl_renderer.h"
#include "player/player.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

namespace hlod::cli {
namespace {

struct ViewArgs {
    std::string database;
    std::string record;
    GlOptions gl{1280, 720, true, false, "hlod view"};
    ConstantOptions constants{"view", kUsedByPlayer};
    uint64_t memoryBudget = 0;
    bool colorByLevel = false;
    bool strict = false;
    double speed = 0;        // m/s; 0: a twentieth of the model's diagonal per second
    std::string up;  // empty: the database's (FORMAT.md META "up")
    PlayerOptions loading;  // --loader, --on-miss, disk model, vm settings (player/LOADERS.md)
    std::string loader = "thesis", onMiss = "parent";
};

// Mouse and scroll state kept between frames (GLFW delivers scroll through a callback).
struct InputState {
    double lastX = 0, lastY = 0;
    bool dragging = false;
    double speed = 1;
    double scroll = 0;
};

constexpr double kTurnRate = 1.0;        // radians per second for arrow keys / Q,E
constexpr double kMouseRadians = 0.004;  // per pixel dragged

double axis(GLFWwindow* w, int positive, int negative) {
    return (glfwGetKey(w, positive) == GLFW_PRESS ? 1.0 : 0.0) - (glfwGetKey(w, negative) == GLFW_PRESS ? 1.0 : 0.0);
}

// WASD move, R/F (or Space/C) rise/sink, Q/E roll, arrows or left-drag to look,
// scroll or +/- to change speed; nothing pressed: the camera stands still.
NavigationInput readInput(GLFWwindow* w, InputState& s, double dt) {
    s.speed *= std::pow(1.25, s.scroll);
    s.scroll = 0;
    if (glfwGetKey(w, GLFW_KEY_EQUAL) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_KP_ADD) == GLFW_PRESS) s.speed *= std::pow(2.0, dt);
    if (glfwGetKey(w, GLFW_KEY_MINUS) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_KP_SUBTRACT) == GLFW_PRESS) s.speed /= std::pow(2.0, dt);
    NavigationInput in;
    in.dt = dt;
    in.speed = s.speed;
    in.move[0] = axis(w, GLFW_KEY_D, GLFW_KEY_A);
    in.move[1] = std::clamp(axis(w, GLFW_KEY_R, GLFW_KEY_F) + axis(w, GLFW_KEY_SPACE, GLFW_KEY_C), -1.0, 1.0);
    in.move[2] = axis(w, GLFW_KEY_S, GLFW_KEY_W);
    in.yaw = axis(w, GLFW_KEY_LEFT, GLFW_KEY_RIGHT) * kTurnRate * dt;
    in.pitch = axis(w, GLFW_KEY_UP, GLFW_KEY_DOWN) * kTurnRate * dt;
    in.roll = axis(w, GLFW_KEY_Q, GLFW_KEY_E) * kTurnRate * dt;
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    const bool pressed = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (pressed && s.dragging) {
        in.yaw -= (x - s.lastX) * kMouseRadians;
        in.pitch -= (y - s.lastY) * kMouseRadians;
    }
    s.dragging = pressed;
    s.lastX = x;
    s.lastY = y;
    return in;
}

// Outside the model's bounds on the side of -forward, above it, looking at its centre.
Camera startCamera(const Box3f& b, int upAxis, double aspect) {
    const double center[3] = {(b.min.x + b.max.x) / 2.0, (b.min.y + b.max.y) / 2.0, (b.min.z + b.max.z) / 2.0};
    const double size[3] = {double{b.max.x} - b.min.x, double{b.max.y} - b.min.y, double{b.max.z} - b.min.z};
    const double diagonal = std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
    Camera camera;
    camera.aspect = aspect;
    for (int i = 0; i < 3; ++i) camera.position[i] = center[i];
    if (upAxis == 2) {  // Z up: look along +Y, camera +Y is world +Z (rotation of 90° about X)
        camera.orientation[0] = std::sqrt(0.5);
        camera.orientation[3] = std::sqrt(0.5);
        camera.position[1] -= 0.6 * diagonal;
        camera.position[2] += 0.3 * diagonal;
    } else {            // Y up: the default orientation looks along -Z
        camera.position[2] += 0.6 * diagonal;
        camera.position[1] += 0.3 * diagonal;
    }
    NavigationInput tilt;
    tilt.pitch = -0.45;  // look down at the centre
    navigate(camera, tilt);
    return camera;
}

double diagonalOf(const Box3f& b) {
    const double dx = double{b.max.x} - b.min.x, dy = double{b.max.y} - b.min.y, dz = double{b.max.z} - b.min.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

void appendKey(CameraPath& path, const Camera& camera, double time) {
    if (!path.keys.empty() && time <= path.keys.back().time) return;
    CameraKey key;
    key.time = time;
    std::copy_n(camera.position, 3, key.position);
    std::copy_n(camera.orientation, 4, key.orientation);
    key.vfovDegrees = camera.vfovDegrees;
    path.keys.push_back(key);
}

void showStatus(GLFWwindow* w, const FrameStats& s, double speed) {
    std::ostringstream title;
    title.precision(3);
    title << "hlod view  " << s.actualMs << " ms (target " << s.targetMs << ")  nodes " << s.residentNodes
          << "  resident " << s.residentBytes / (1 << 20) << " MiB  speed " << speed << " m/s";
    glfwSetWindowTitle(w, title.str().c_str());
}

int runView(const ViewArgs& args) {
    // The flight is written when the window closes: what would refuse it then is refused now, so no
    // flight is lost (until stop 44 `--record DB` wrote the path over the database, exit 0).
    std::optional<TextFileWriter> recordFile;
    if (!args.record.empty()) {
        refuseOutputOverInputs(args.record, {args.database, args.constants.configFile});
        recordFile.emplace(args.record, "camera path");
    }
    Constants constants;
    applyConstantOptions(args.constants, constants, std::cout);
    printConstants(std::cout, constants, kUsedByPlayer);
    const Database db = Database::open(args.database);
    std::unique_ptr<Renderer> renderer = makeGlRenderer(args.gl);
    GLFWwindow* window = glfwWindowOf(*renderer);
    PlayerOptions options = args.loading;
    options.loader = loaderKindByName(args.loader);
    options.onMiss = onMissByName(args.onMiss);
    options.memoryBudget = args.memoryBudget;
    options.frameOptions.colorByLevel = args.colorByLevel;
    options.strictLoads = args.strict;
    options.onLoadFailure = [&db](const LoadFailure& f) { warnLoadFailure("view", db, f); };
    Player player(db, constants, *renderer, options);
    const Box3f bounds = modelBounds(db.skeleton());
    const int up = args.up.empty() ? upAxisOf(db.skeleton(), args.database).axis : parseUpAxis(args.up, "--up");
    deferInterrupts();  // from here Ctrl-C quits as Escape does, the flight recorded
    std::cout << "up axis: " << (up == 1 ? "y" : "z") << (args.up.empty() ? " (the database's)" : " (--up)") << std::endl;
    Camera camera = startCamera(bounds, up, static_cast<double>(args.gl.width) / args.gl.height);
    InputState input;
    input.speed = args.speed > 0 ? args.speed : std::max(0.1, diagonalOf(bounds) / 20);
    glfwSetWindowUserPointer(window, &input);
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
        static_cast<InputState*>(glfwGetWindowUserPointer(w))->scroll += dy;
    });
    // Escape as an event, not a polled state: a quick tap between two slow frames still quits.
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
        if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
    });
    CameraPath recorded;
    const double start = glfwGetTime();
    double last = start, lastTitle = start;
    while (!glfwWindowShouldClose(window) && !interruptedBy()) {
        glfwPollEvents();
        const double now = glfwGetTime();
        navigate(camera, readInput(window, input, now - last));
        last = now;
        const FrameStats stats = player.frame(camera, now - start);
        if (!args.record.empty()) appendKey(recorded, camera, now - start);
        if (now - lastTitle > 0.5) {
            showStatus(window, stats, input.speed);
            lastTitle = now;
        }
    }
    if (!args.record.empty()) {
        if (recorded.keys.size() < 2 && interruptedBy()) endByInterrupt(interruptedBy());
        if (recorded.keys.size() < 2) throw std::runtime_error(args.record + ": fewer than two frames to record");
        writeCameraPath(recordFile->stream(), recorded);
        recordFile->commit();
        std::cout << "recorded " << recorded.keys.size() << " keys, " << recorded.duration() << " s to " << args.record << "\n";
    }
    std::cout.flush();
    resumeInterrupts();  // a signal kept, or one that comes from here on: status 128 + N, as any interrupted run
    return kExitOk;
}

}  // namespace

void addView(CLI::App& app, int& status) {
    auto args = std::make_shared<ViewArgs>();
    CLI::App* sub = app.add_subcommand(
        "view", "fly through a database in a window (WASD move, R/F rise/sink, Q/E roll, arrows or left-drag look, "
                "scroll or +/- speed, Esc or Ctrl-C quit)");
    addDatabaseArgument(*sub, args->database);
    sub->add_option("--record", args->record, "write the flight to this camera path file on exit")->check(nonEmptyPath());
    sub->add_option("--width", args->gl.width, "window width")->capture_default_str()->check(CLI::Range(1, 16384));
    sub->add_option("--height", args->gl.height, "window height")->capture_default_str()->check(CLI::Range(1, 16384));
    addMemoryBudgetOption(*sub, args->memoryBudget, " (thesis §4.3)");
    sub->add_flag("--color-by-level", args->colorByLevel, "shade nodes by level (grey levels)");
    addLoaderOptions(*sub, args->loading, args->loader, args->onMiss);
    sub->add_flag("--strict", args->strict,
                  "a node that cannot be read or decoded ends the session (exit 1); by default it is skipped "
                  "with one warning and its parent stays drawn");
    sub->add_option("--speed", args->speed, "initial speed in m/s (default or 0: model diagonal / 20)")->check(finiteAtLeast(0));
    sub->add_option("--up", args->up, "up axis of the model (default: the one the database records; z for a database without one)")
        ->check(CLI::IsMember({"y", "z"}));
    addConstantOptions(*sub, args->constants);
    sub->callback([args, sub, &status] {
        status = runGuarded("view", [&] {
            checkLoaderOptions(*sub, args->loader);
            return runView(*args);
        });
    });
}

}  // namespace hlod::cli
