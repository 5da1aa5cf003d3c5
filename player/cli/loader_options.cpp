// The loader options shared by `hlod play`, `hlod compare` and `hlod view` (player/LOADERS.md):
// the loader policy, what a miss does, the disk model and the vm loader's settings.
#include "player/cli/subcommands.h"

#include "player/player.h"

#include <CLI/CLI.hpp>

#include <stdexcept>
#include <string>

namespace hlod::cli {

void addLoaderOptions(CLI::App& sub, PlayerOptions& o, std::string& loader, std::string& onMiss) {
    sub.add_option("--loader", loader,
                   "loader policy (player/LOADERS.md): thesis (thesis §4.3, default), vm (Varadhan & Manocha 2002 "
                   "prioritized prefetching), demand (vm without prefetching), incore (everything loaded first)")
        ->check(CLI::IsMember({"thesis", "vm", "demand", "incore"}));
    sub.add_option("--on-miss", onMiss,
                   "a wanted node not loaded: parent (draw the loaded parent, never wait; default) or wait (the "
                   "frame waits for its fetch: the disk model's time under play's --sync-loader)")
        ->check(CLI::IsMember({"parent", "wait"}));
    sub.add_option("--disk-seek-ms", o.disk.seekMs, "disk model: ms per node fetched" + defaultText(o.disk.seekMs))->check(finiteAtLeast(0));
    sub.add_option("--disk-mbs", o.disk.bandwidthMBs, "disk model: stored MB/s" + defaultText(o.disk.bandwidthMBs))->check(finitePositive());
    sub.add_option("--disk-decode-ns", o.disk.decodeNsPerByte, "disk model: decode ns per decoded byte" + defaultText(o.disk.decodeNsPerByte))
        ->check(finiteAtLeast(0));
    sub.add_option("--vm-tolerance", o.vm.tolerance,
                   "vm: error tolerance epsilon for selectors without one (thesis: the units of the time-slice "
                   "mapping; sse uses sse.tolerance)" + defaultText(o.vm.tolerance))
        ->check(finitePositive());
    // At most 100 x 100 bins (Fig. 5 has 12): the bins are rebuilt whenever the view moves.
    sub.add_option("--vm-delta", o.vm.deltaRatio, "vm: delta / epsilon, the last bin (Fig. 5: 1.2; at most 100)")
        ->check(finiteAboveAtMost(0, 100));
    sub.add_option("--vm-bins", o.vm.binsPerTolerance, "vm: bins per epsilon (Fig. 5: 10; at most 100)")
        ->check(finiteAboveAtMost(0, 100));
    sub.add_option("--vm-margin-deg", o.vm.marginDegrees,
                   "vm: prefetch frustum half-angle = render's + this + angular speed x the lookahead (play's "
                   "--lookahead, 0.5 s)" + defaultText(o.vm.marginDegrees))
        ->check(finiteAtLeast(0));
}

// The vm loader's settings given with another loader were accepted and ignored (until stop 46).
void checkLoaderOptions(const CLI::App& sub, const std::string& loader) {
    if (loader == "vm") return;
    for (const char* name : {"--vm-tolerance", "--vm-delta", "--vm-bins", "--vm-margin-deg"})
        if (sub.count(name) > 0) throw std::invalid_argument(std::string(name) + " needs --loader vm");
}

void appendLoaderInfo(std::vector<std::pair<std::string, std::string>>& info, const PlayerOptions& o) {
    info.push_back({"disk_seek_ms", std::to_string(o.disk.seekMs)});
    info.push_back({"disk_mbs", std::to_string(o.disk.bandwidthMBs)});
    info.push_back({"disk_decode_ns_per_byte", std::to_string(o.disk.decodeNsPerByte)});
    if (o.loader != LoaderKind::Vm) return;
    info.push_back({"vm_tolerance", std::to_string(o.vm.tolerance)});
    info.push_back({"vm_delta_ratio", std::to_string(o.vm.deltaRatio)});
    info.push_back({"vm_bins_per_tolerance", std::to_string(o.vm.binsPerTolerance)});
    info.push_back({"vm_margin_deg", std::to_string(o.vm.marginDegrees)});
}

}  // namespace hlod::cli
