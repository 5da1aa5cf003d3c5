// Thesis §4.2 "Feedback Loop": v_time from estimated vs measured frame time (first loop) and the
// hlod0 share from refused nodes and over-target frames (second loop).
#include "player/feedback.h"

#include <algorithm>
#include <cmath>

namespace hlod {

double nextVTime(double vTime, double actualMs, double overheadMs, double drawnCost, double gain) {
    if (drawnCost <= 0) return vTime;
    double measured = std::max(actualMs - overheadMs, 0.0) / drawnCost;
    return std::max(vTime + gain * (measured - vTime), 1e-9);
}

// §4.2: "a second feedback loop that gradually increases shareTime for hlod0 nodes if some nodes
// were not selected because their cumulative hysteresis value was below 0 and the actual total
// render time used was substantially below c_targetTime. Similarly, if the total render time
// substantially exceeds c_targetTime, we decrease shareTime for hlod0 nodes."
double nextHlod0Share(double share, double targetMs, double actualMs, uint32_t refused, const ShareLoop& loop) {
    const double e = (targetMs - actualMs) / targetMs;  // > 0: under target
    const bool raise = refused > 0 && e > loop.band, lower = e < -loop.band;
    double change = (raise || lower ? loop.gain * e : 0) + loop.leak * std::log(targetMs / share);
    change = std::clamp(change, -loop.step, loop.step);
    return std::clamp(share * (1 + change), kMinShare * targetMs, kMaxShare * targetMs);
}

}  // namespace hlod
