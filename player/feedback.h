// The two feedback loops of thesis §4.2 as functions of one frame's measurements, so that the
// player applies them and the tests check them in isolation.
#pragma once

#include <cstdint>

namespace hlod {

// First loop: timeNeeded_n = v_time * cost_n. v_time moves `gain` of the way towards the rate
// measured this frame, (actual - fixed overhead) / sum of cost_n over the drawn nodes; unchanged
// when nothing was drawn. Kept above 1e-9 ms per unit of cost (timeNeeded divides the §4.2 hysteresis update).
double nextVTime(double vTime, double actualMs, double overheadMs, double drawnCost, double gain);

// Second loop: shareTime of the hlod0 nodes (the time eq. 4.1 splits among the visible roots),
// changed "gradually" (§4.2): a proportional controller on the relative frame-time error
// e = (target - actual) / target, with a leak towards the target. Values: player/SELECTION.md.
struct ShareLoop {
    double band = 0.1;    // "substantially" under / over the target: |e| > band
    double gain = 0.03;   // relative change of the share per unit of e
    double leak = 0.001;  // fraction of ln(target / share) recovered per frame
    double step = 0.05;   // largest relative change per frame
};

// The share stays within [kMinShare, kMaxShare] x c_targetTime. The upper bound is far above the
// target because most of the share is never drawn: a node whose slice cannot pay for all its
// visible children is drawn alone and the rest of its slice is unused (§5.2 "under-utilization"),
// and the loop is what gives that time back (player/SELECTION.md).
inline constexpr double kMinShare = 0.1, kMaxShare = 20;

// ln(share) moves by gain * e when sibling sets whose nodes were all loaded were refused
// (cumHyst < 0) and e > band (the frame came in "substantially below" the target), or when
// e < -band (it "substantially exceeds" it), plus leak * ln(target / share); the relative change
// is limited to +-step and the result clamped to the bounds. gain >= 1e6 with leak 0 is the
// bang-bang loop of earlier versions (+-step whenever outside the band).
double nextHlod0Share(double share, double targetMs, double actualMs, uint32_t refused, const ShareLoop& loop);

}  // namespace hlod
