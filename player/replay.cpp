// Simulated-time replay of a camera path (thesis Chapter 6 test runs): the clock advances by
// each frame's measured time, never by wall-clock time, so runs with the cost-model renderer
// are exactly repeatable.
#include "player/replay.h"

#include <algorithm>

namespace hlod {

std::vector<FrameStats> replayPath(Player& player, const CameraPath& path, const ReplayOptions& options,
                                   const std::function<void(const FrameStats&)>& onFrame) {
    std::vector<FrameStats> frames;
    const uint64_t last = options.maxFrames ? options.maxFrames : options.frameCap;
    double t = 0;
    while (t <= path.duration() && frames.size() < last) {
        FrameStats s = player.frame(sampleCameraPath(path, t, options.aspect), t);
        if (onFrame) onFrame(s);
        t = options.fixedStepMs > 0 ? double(frames.size() + 1) * options.fixedStepMs / 1000.0
                                    : t + std::max(s.actualMs, options.minFrameMs) / 1000.0;
        frames.push_back(std::move(s));
    }
    return frames;
}

}  // namespace hlod
