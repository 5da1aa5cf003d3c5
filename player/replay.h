// Replaying a camera path through a Player in simulated time: frame i's camera is sampled at
// the sum of the previous frames' measured times, so a slow frame moves the camera further,
// as in a real walk (player/CAMERA_PATH.md).
#pragma once

#include "player/camera_path.h"
#include "player/player.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace hlod {

// Frames a replay keeps statistics of when no frame count is given (~0.4 KB each, so ~0.4 GB):
// before stop 36 a day-long path at the 0.1 ms minimum frame grew without bound (~100 MB/s).
constexpr uint64_t kDefaultFrameCap = 1'000'000;

struct ReplayOptions {
    uint64_t maxFrames = 0;       // 0: until the path ends, at most frameCap frames
    uint64_t frameCap = kDefaultFrameCap;
    double aspect = 16.0 / 9.0;
    double minFrameMs = 0.1;      // simulated time advances at least this much per frame
    // > 0: fixed-step mode, frame i sampled at i x fixedStepMs whatever the frames took, so that
    // every policy sees the same viewpoints (Funkhouser & Séquin 1993 Fig. 7; `hlod compare`).
    double fixedStepMs = 0;
};

std::vector<FrameStats> replayPath(Player& player, const CameraPath& path, const ReplayOptions& options,
                                   const std::function<void(const FrameStats&)>& onFrame = {});

}  // namespace hlod
