// The thesis engine as a selection policy: the breadth-first traversal of thesis §4.2 (time
// slices eq. 4.1, hysteresis, cumHyst) exactly as selectFront runs it (player/selection.cpp),
// and `thesis-rh`, the same traversal with the thesis's §6.6 future work: "accumulate unused
// time slices and give it to other nodes", passed on in the manner of Robin Hood (Hernández &
// Beneš, §5 eqs 2-4: each instance takes what it needs of its share and hands the remainder to
// the next, from simple to complex).
#include "player/policy.h"

namespace hlod {
namespace {

class ThesisPolicy final : public SelectionPolicy {
public:
    explicit ThesisPolicy(bool passRemainders) : passRemainders_(passRemainders) {}
    const char* name() const override { return passRemainders_ ? "thesis-rh" : "thesis"; }

    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        SelectionParams params = selectionParams(f.constants, f.hlod0ShareMs, f.vTime, f.requireLoadedChildren);
        params.initialHyst = f.initialHyst;
        params.passRemainders = passRemainders_;
        return traverseThesis(f.skeleton, params, f.evaluate, state, f.resident);
    }

private:
    bool passRemainders_;
};

}  // namespace

std::unique_ptr<SelectionPolicy> makeThesisPolicy(const PolicyOptions&) { return std::make_unique<ThesisPolicy>(false); }
std::unique_ptr<SelectionPolicy> makeThesisRhPolicy(const PolicyOptions&) { return std::make_unique<ThesisPolicy>(true); }

}  // namespace hlod
