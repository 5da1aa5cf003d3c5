// Prioritized prefetching of Varadhan & Manocha 2002 §4.2: the angle priority of §4.2.2
// (AngPr, in the expanded prefetch frustum F_I), the integrated priority of §4.2.3 and its
// bins (Fig. 5): the range [0, delta] cut into intervals of one bin width, each bin a FIFO,
// popped from the bin holding the tolerance outwards, the lower bin first at equal distance.
#pragma once

#include <cstdint>
#include <cstddef>
#include <deque>
#include <vector>

namespace hlod {

struct VmOptions {
    double tolerance = 10;         // epsilon of a selector without one (player/LOADERS.md), pixels
    double deltaRatio = 1.2;       // delta / epsilon (Fig. 5: 12 / 10)
    double binsPerTolerance = 10;  // bin width = epsilon / this (Fig. 5: 1 with epsilon = 10)
    double marginDegrees = 15;     // theta1 = theta0 + margin + angular speed x lookahead
};

// AngPr(O) = 1 / (1 + (theta - theta0)+ / theta1)   (§4.2.2)
double angularPriority(double theta, double theta0, double theta1);
// Priority(O) = eps_O x AngPr if eps_O < eps, eps_O / AngPr if eps_O > eps   (§4.2.3)
double integratedPriority(double errorO, double tolerance, double angPr);

inline constexpr int kMaxVmBins = 100 * 100 + 1;

class VmBins {
public:
    // Bins of width `width` over [0, delta]: bin i holds [i w, (i + 1) w), i = 0 .. floor(delta / w);
    // std::invalid_argument beyond kMaxVmBins (hlod play's --vm-delta and --vm-bins: at most 100 each).
    VmBins(double tolerance, double delta, double width);
    int binOf(double priority) const;   // -1 beyond the last bin (not prefetched)
    bool push(uint32_t id, double priority);  // appended to its bin's queue; false when beyond
    uint32_t pop();                     // head of the highest-priority non-empty bin; kNoNode when none
    bool empty() const { return count_ == 0; }
    const std::vector<int>& order() const { return order_; }  // bins by decreasing priority

private:
    double width_;
    std::vector<std::deque<uint32_t>> bins_;
    std::vector<int> order_;
    size_t count_ = 0;
};

}  // namespace hlod
