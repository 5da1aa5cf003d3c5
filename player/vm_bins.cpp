// Varadhan & Manocha 2002 §4.2.2 (AngPr) and §4.2.3 (integrated priority, bins of Fig. 5).
// Open choices (player/LOADERS.md): the bins cover [0, (floor(delta / w) + 1) w) as in Fig. 5
// (13 bins for delta = 12, w = 1, although the text says [0, delta]); a priority beyond the last
// bin is not prefetched (that is how "varying delta varies the number of ascendants prefetched");
// past the bins on the smaller side, the remaining ones follow in decreasing order (Fig. 5: 10, 9,
// 11, 8, 12, 7, 6, ..., 0).
#include "player/vm_bins.h"

#include "player/priority_queue.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hlod {

double angularPriority(double theta, double theta0, double theta1) {
    double over = std::max(theta - theta0, 0.0);  // (theta - theta0)+ of §4.2.2
    return 1 / (1 + over / theta1);
}

double integratedPriority(double errorO, double tolerance, double angPr) {
    if (errorO < tolerance) return errorO * angPr;
    if (errorO > tolerance) return errorO / angPr;
    return errorO;
}

VmBins::VmBins(double tolerance, double delta, double width) : width_(width) {
    const double bins = std::floor(delta / width) + 1;
    if (!(bins >= 1 && bins <= kMaxVmBins))
        throw std::invalid_argument("vm bins: delta / width must give 1.." + std::to_string(kMaxVmBins) + " bins");
    const int count = int(bins);
    bins_.resize(size_t(count));
    int center = std::clamp(int(std::floor(tolerance / width)), 0, count - 1);
    order_.push_back(center);
    for (int d = 1; int(order_.size()) < count; ++d) {
        if (center - d >= 0) order_.push_back(center - d);
        if (center + d < count) order_.push_back(center + d);
    }
}

int VmBins::binOf(double priority) const {
    if (!(priority >= 0)) return -1;
    double i = std::floor(priority / width_);
    return i < double(bins_.size()) ? int(i) : -1;
}

bool VmBins::push(uint32_t id, double priority) {
    int b = binOf(priority);
    if (b < 0) return false;
    bins_[size_t(b)].push_back(id);
    ++count_;
    return true;
}

uint32_t VmBins::pop() {
    for (int b : order_) {
        auto& q = bins_[size_t(b)];
        if (q.empty()) continue;
        uint32_t id = q.front();
        q.pop_front();
        --count_;
        return id;
    }
    return kNoNode;
}

}  // namespace hlod
