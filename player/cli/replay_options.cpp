// Options of `hlod path`, `hlod play` and `hlod compare` beside the loader's: the database's units
// (speeds are in m/s) and the check of a given fixed frame overhead against c_targetTime.
#include "player/cli/subcommands.h"

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

void warnTeleportingPath(const std::string& command, const CameraPath& path, const PlayerOptions& options, double until) {
    const double share = shareFasterThan(path, options.teleportSpeed / options.metresPerUnit, until);
    if (share > 0.5)
        std::cerr << "hlod " << command << ": warning: the camera moves faster than --teleport-speed " << options.teleportSpeed
                  << " m/s over " << int(share * 100) << " % of the replayed time, so every such move counts as a teleport (no "
                  << "distance, no velocity look-ahead); if a database unit is not " << options.metresPerUnit
                  << " m, --units says what it is (mm, cm, ...)\n";
}

void checkOverhead(double overheadMs, const Constants& c, const std::string& source) {
    if (overheadMs >= c.targetTimeMs)
        throw std::invalid_argument(source + " " + formatConstant(overheadMs) + " ms is not below c_targetTime " + formatConstant(c.targetTimeMs) +
                                    " ms: no time would be left to draw (a longer --set c_targetTime, or a smaller overhead)");
}

}  // namespace hlod::cli
