// Options of `hlod path`, `hlod play` and `hlod compare` beside the loader's: the database's units
// (speeds are in m/s), --teleport-speed, --memory, the warning of a path faster than the teleport
// speed, and the check of a given fixed frame overhead against c_targetTime.
#include "player/cli/subcommands.h"

#include "formats/cli/command.h"
#include "formats/constants.h"
#include "player/camera_path.h"
#include "player/player.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <stdexcept>
#include <string>

namespace hlod::cli {

void addUnitsOption(CLI::App& sub, std::string& units) {
    sub.add_option("--units", units, "what one database unit is: m (default), cm, mm, km or a number of metres (speeds are in m/s)");
}

void addTeleportSpeedOption(CLI::App& sub, double& speed) {
    sub.add_option("--teleport-speed", speed, "m/s: faster camera moves count as this speed" + defaultText(speed))->check(finitePositive());
}

void addMemoryBudgetOption(CLI::App& sub, uint64_t& budget, const std::string& more) {
    sub.add_option("--memory", budget, "memory budget: bytes, or with a unit, e.g. 512M, 2G (0, the default: none)" + more)
        ->transform(CLI::AsSizeValue(false))
        ->transform(wholeNumber(budget));  // inserted before the size transform: "-1" is refused, not wrapped
}

void warnTeleportingPath(const std::string& command, const CameraPath& path, const PlayerOptions& options, double until) {
    const double share = shareFasterThan(path, options.teleportSpeed / options.metresPerUnit, until);
    if (share > 0.5)
        std::cerr << "hlod " << command << ": warning: the camera moves faster than --teleport-speed " << options.teleportSpeed
                  << " m/s over " << int(share * 100) << " % of the path's time: each such move counts as a cut (no distance, "
                  << "no velocity look-ahead); --units says what a database unit is if not " << formatConstant(options.metresPerUnit)
                  << " m (mm, cm, ...), and --teleport-speed raises the limit\n";
}

void checkOverhead(double overheadMs, const Constants& c, const std::string& source) {
    if (overheadMs >= c.targetTimeMs)
        throw std::invalid_argument(source + " " + formatConstant(overheadMs) + " ms is not below c_targetTime " + formatConstant(c.targetTimeMs) +
                                    " ms: no time would be left to draw (a longer --set c_targetTime, or a smaller overhead)");
}

}  // namespace hlod::cli
