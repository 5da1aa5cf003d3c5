// The two feedback loops of thesis §4.2 as functions of one frame's measurements, so that the
// player applies them and the tests check them in isolation.
#pragma once

#include <cstdint>

namespace hlod {

// First loop: timeNeeded_n = v_time * cost_n. v_time moves `gain` of the way towards the rate
// measured this frame, (actual - fixed overhead) / sum of cost_n over the drawn nodes; unchanged
// when nothing was drawn. Kept above 1e-9 ms per unit of cost (timeNeeded divides the §4.2 hysteresis update).
double nextVTime(double vTime, double actualMs, double overheadMs, double drawnCost, double gain);

// Second loop: shareTime of the hlod0 nodes (the time eq. 4.1 splits among the visible roots).
struct ShareLoop {
    double band = 0.1;   // "substantially" under / over the target: outside target * (1 -+ band)
    double step = 0.05;  // multiplicative step per frame
};

// The share stays within [kMinShare, kMaxShare] x c_targetTime. The upper bound is far above the
// target because most of the share is never drawn: a node whose slice cannot pay for all its
// visible children is drawn alone and the rest of its slice is unused (§5.2 "under-utilization"),
// and the loop is what gives that time back. On the test city (equal-cost nodes) a walk holds
// it at 2-7 x c_targetTime and a drive at up to 20 x to fill the frame (player/SELECTION.md);
// a bound of 4 x left the drive at 88% of the target. Frames over target lower the share by
// `step` per frame whatever its value, so the bound only limits how far the share winds up.
inline constexpr double kMinShare = 0.1, kMaxShare = 20;

// Raises the share by `step` when sibling sets whose nodes were all loaded were refused
// (cumHyst < 0) while the frame came in under target * (1 - band); lowers it by `step` when the
// frame ran over target * (1 + band); then clamps it.
double nextHlod0Share(double share, double targetMs, double actualMs, uint32_t refused, const ShareLoop& loop);

}  // namespace hlod
