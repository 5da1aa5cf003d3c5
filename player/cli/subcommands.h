// The subcommands of player/ (registered by the table in hlod.cpp).
#pragma once

#include "formats/cli/command.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hlod {
class Database;
struct CameraPath;
struct Constants;
struct CostModel;
struct LoadFailure;
struct PlayerOptions;
}  // namespace hlod

namespace hlod::cli {

// `hlod play DB --path FILE`: replays a camera path through the Chapter 4 engine, writes the
// per-frame CSV (player/STATS.md) and prints a summary.
void addPlay(CLI::App& app, int& status);
// `hlod path DB --kind walk|drive|fly|erratic|line|zigzag -o FILE`: a camera path from the database's bounds.
void addPath(CLI::App& app, int& status);
// `hlod view DB`: interactive 6-DOF window on a database, optional path recording.
void addView(CLI::App& app, int& status);
// The one line `hlod play` and `hlod view` print on stderr for a node they skip because it
// cannot be read or decoded: "hlod COMMAND: warning: DB: node N: problem".
void warnLoadFailure(const std::string& command, const Database& db, const LoadFailure& failure);
// The c_textured the database's node costs were computed with (eq. 3.1), from its metadata
// (absent: the default); FormatError "DB: metadata c_textured is not in (0, 1]" for any other.
double databaseCTextured(const Database& db);
// The cost-model renderer's options of `hlod play` and `hlod compare` (--model-overhead-ms,
// --model-ms-per-tri, --model-ms-per-flat-tri into `flatRate`, --model-noise, --model-node-error,
// --seed).
void addCostModelOptions(CLI::App& sub, CostModel& model, std::optional<double>& flatRate);
// The loader options (--loader, --on-miss, --disk-*, --vm-*; player/LOADERS.md); the names of
// the loader and of the miss rule go to `loader` and `onMiss` (loaderKindByName, onMissByName).
void addLoaderOptions(CLI::App& sub, PlayerOptions& options, std::string& loader, std::string& onMiss);
// --units of `hlod path`, `hlod play` and `hlod compare`: what one database unit is, for speeds in
// m/s (a path's, --teleport-speed); parsed by parseUnits (player/camera_path.h).
void addUnitsOption(CLI::App& sub, std::string& units);
// --teleport-speed of `hlod play` and `hlod compare` (m/s): faster camera moves count as this speed.
void addTeleportSpeedOption(CLI::App& sub, double& speed);
// Warns (std::cerr) when the camera moves faster than --teleport-speed over most of the path's time
// up to `until`: every move a teleport (no distance, no velocity look-ahead), as a millimetre database
// played in metres gave (Lucy's drive: distance 0, until stop 48 without a word).
void warnTeleportingPath(const std::string& command, const CameraPath& path, const PlayerOptions& options, double until);
// --memory of `hlod play`, `hlod compare` and `hlod view`: the memory budget in bytes or with a
// unit (512M, 2G, as build's --memory-limit; until stop 48 bytes alone), 0: none.
void addMemoryBudgetOption(CLI::App& sub, uint64_t& budget, const std::string& more);
// Throws std::invalid_argument (usage) when a given fixed overhead (`source`: the option or the
// calibration file's key) leaves no time to draw within c_targetTime: the v_time loop fell to its
// floor and refined everything (50 ms frames for a 30 ms target, until stop 48). < 0: measured.
void checkOverhead(double overheadMs, const Constants& c, const std::string& source);
// Throws std::invalid_argument (usage) when a vm setting is given with another --loader.
void checkLoaderOptions(const CLI::App& sub, const std::string& loader);
// The disk model's figures (and the vm loader's settings) as "# key: value" lines of a run.
void appendLoaderInfo(std::vector<std::pair<std::string, std::string>>& info, const PlayerOptions& options);
// `hlod compare DB --path P --policies a,b,...`: one path through several selection policies,
// one table (player/POLICIES.md).
void addCompare(CLI::App& app, int& status);
// `hlod calibrate`: measures the render-time model with OpenGL and writes a calibration file.
void addCalibrate(CLI::App& app, int& status);

}  // namespace hlod::cli
