// Thesis §4.2 "Feedback Loop": v_time from estimated vs measured frame time (first loop) and the
// hlod0 share from refused nodes and over-target frames (second loop).
#include "player/feedback.h"

#include <algorithm>

namespace hlod {

double nextVTime(double vTime, double actualMs, double overheadMs, double drawnCost, double gain) {
    if (drawnCost <= 0) return vTime;
    double measured = std::max(actualMs - overheadMs, 0.0) / drawnCost;
    return std::max(vTime + gain * (measured - vTime), 1e-9);
}

double nextHlod0Share(double share, double targetMs, double actualMs, uint32_t refused, const ShareLoop& loop) {
    if (refused > 0 && actualMs < targetMs * (1 - loop.band)) share *= 1 + loop.step;
    if (actualMs > targetMs * (1 + loop.band)) share *= 1 - loop.step;
    return std::clamp(share, kMinShare * targetMs, kMaxShare * targetMs);
}

}  // namespace hlod
