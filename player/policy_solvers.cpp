// The seed papers' solvers as selection policies (player/policy.h): each frame the visible
// blocks and their cuts at each depth become a multiple-choice knapsack (player/choice_map.h),
// a solver of player/choice.h picks one cut per block, and the picked cuts are the front.
//   fs-greedy, fs-incremental  Funkhouser & Séquin 1993 §4-6 (fs_greedy.cpp, fs_incremental.cpp)
//   rh                         Hernández & Beneš 2005 §5 eqs 1-11 (robin_hood.cpp)
//   gb                         Gobbetti & Bouvier 1999 §4-5, then rounded onto the tree (gb_barrier.cpp)
//   fs-hold                    FS §6's steps with symmetric hysteresis (choice_hold.cpp): the project's own
//   oracle                     the exact optimum (choice_oracle.cpp), a yardstick for `hlod compare`
// Settings (player/SOLVERS.md): every one takes allow_skip
// (FS skips objects; default 0: hlod0 is always drawn, as in the thesis) and pixel_ms (FS §4 C3,
// GB t_pix; default 0, the cost-model renderer has no per-pixel term).
#include "player/choice_map.h"
#include "player/policy.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace hlod {
namespace {

double norm3(const double v[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

class SolverPolicy : public SelectionPolicy {
public:
    SolverPolicy(const char* name, const PolicyOptions& o)
        : name_(name), allowSkip_(o.get(std::string(name) + ".allow_skip", 0) != 0),
          pixelMs_(o.get(std::string(name) + ".pixel_ms", 0)) {}
    const char* name() const override { return name_; }

    PolicyFront select(const PolicyFrame& f, SelectionState& state) override {
        if (prevLevel_.size() != f.skeleton.nodes.size()) {
            prevLevel_.assign(f.skeleton.nodes.size(), kSkipped);
            prevResolution_.assign(f.skeleton.nodes.size(), -1);
        }
        ChoiceMapOptions mo;
        mo.budgetMs = f.targetMs - f.overheadMs;
        mo.vTime = f.vTime;
        mo.pixelMs = pixelMs_;
        mo.allowSkip = allowSkip_;
        ChoiceMap m = mapChoice(f.skeleton, f.projection, f.evaluate, f.resident, state, mo);
        std::vector<int32_t> previous;
        for (const ChoiceObject& o : m.problem.objects) previous.push_back(prevLevel_[o.id]);
        auto t0 = std::chrono::steady_clock::now();
        Choice c = solve(f, m.problem, previous);
        double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        for (size_t i = 0; i < m.problem.objects.size(); ++i) prevLevel_[m.problem.objects[i].id] = c.level[i];
        for (uint32_t r : state.roots)
            if (state.nodes[r].frustumVis < 1) prevLevel_[r] = kSkipped;  // newly visible next time
        return front(f, m, c, ms, state);
    }

protected:
    virtual Choice solve(const PolicyFrame& f, ChoiceProblem& p, const std::vector<int32_t>& previous) = 0;
    std::vector<double> prevResolution_;  // per root: gb's last resolution (< 0: none)

private:
    // The chosen cuts; every child of a cut node was evaluated by mapChoice this frame.
    static PolicyFront front(const PolicyFrame& f, const ChoiceMap& m, const Choice& c, double ms, const SelectionState& state) {
        PolicyFront out;
        out.visited = m.visited;
        out.iterations = c.iterations;
        out.optimisationMs = ms;
        for (size_t i = 0; i < m.cuts.size(); ++i) {
            if (c.level[i] == kSkipped) {
                out.skipsBlocks = true;
                continue;
            }
            for (uint32_t id : m.cuts[i][size_t(c.level[i])]) {
                DrawReason why = DrawReason::Hysteresis;
                const Node& n = f.skeleton.nodes[id];
                if (n.firstChild == kNone) {
                    why = DrawReason::Leaf;
                } else {
                    uint32_t vis = 0, missing = 0;
                    for (uint32_t k = n.firstChild; k != kNone; k = f.skeleton.nodes[k].nextSibling)
                        if (state.nodes[k].frustumVis >= 1) ++vis, missing += !f.resident[k];
                    why = vis == 0 ? DrawReason::Culled : missing ? DrawReason::Miss : DrawReason::Hysteresis;
                    out.misses += missing;
                }
                out.drawn.push_back({id, why});
            }
        }
        return out;
    }

    const char* name_;
    bool allowSkip_;
    double pixelMs_;
    std::vector<int32_t> prevLevel_;  // per root: last frame's option (kSkipped: not visible)
};

// FS §5's own Benefit in place of the common measure (setting fs_benefit = 1): Size x Accuracy x
// Focus x Motion x Hysteresis with the weights of the settings (Importance 1: blocks have no types).
void useFsBenefit(const PolicyFrame& f, ChoiceProblem& p, const std::vector<int32_t>& previous,
                  const FsBenefitFactors& k, const double lastEye[3]) {
    double halfFov = f.camera.vfovDegrees * M_PI / 360.0;
    double moved[3] = {f.view.eye[0] - lastEye[0], f.view.eye[1] - lastEye[1], f.view.eye[2] - lastEye[2]};
    for (size_t i = 0; i < p.objects.size(); ++i) {
        ChoiceObject& o = p.objects[i];
        const Box3f& b = f.skeleton.nodes[o.id].bounds;
        double d[3] = {0.5 * (b.min.x + b.max.x) - f.view.eye[0], 0.5 * (b.min.y + b.max.y) - f.view.eye[1],
                       0.5 * (b.min.z + b.max.z) - f.view.eye[2]};
        double len = std::max(norm3(d), 1e-9);
        double cosA = (d[0] * f.view.forward[0] + d[1] * f.view.forward[1] + d[2] * f.view.forward[2]) / len;
        FsObjectView v;
        v.pixels = o.pixels;
        v.offCentre = std::acos(std::clamp(cosA, -1.0, 1.0)) / halfFov;
        v.speedPx = norm3(moved) * f.projection.focalPx / std::max(o.distance, 1.0);  // eye motion on screen
        for (size_t l = 0; l < o.options.size(); ++l) {
            v.polygonPx = o.pixels / std::max(o.options[l].samples, 1.0);
            o.options[l].benefit = fsBenefit(v, o.options[l].samples, int32_t(l), previous[i],
                                             int32_t(o.options.size()) - 1, k);
        }
    }
}

FsBenefitFactors fsFactors(const std::string& name, const PolicyOptions& o) {
    FsBenefitFactors k;
    k.focusWeight = o.get(name + ".focus", 0);
    k.motionWeight = o.get(name + ".motion", 0);
    k.hystWeight = o.get(name + ".hysteresis", 0);
    return k;
}

class FsPolicy final : public SolverPolicy {
public:
    FsPolicy(bool incremental, const PolicyOptions& o)
        : SolverPolicy(incremental ? "fs-incremental" : "fs-greedy", o), incremental_(incremental) {
        std::string n = name();
        fsBenefit_ = o.get(n + ".fs_benefit", 0) != 0;
        factors_ = fsFactors(n, o);
        greedy_.literal = o.get(n + ".literal", 0) != 0;
        greedy_.bestSingle = o.get(n + ".best_single", 1) != 0;
    }

private:
    Choice solve(const PolicyFrame& f, ChoiceProblem& p, const std::vector<int32_t>& previous) override {
        if (fsBenefit_) {
            useFsBenefit(f, p, previous, factors_, lastEye_);
        } else if (factors_.hystWeight > 0) {  // FS §5 Hysteresis factor on the common measure
            for (size_t i = 0; i < p.objects.size(); ++i) {
                std::vector<ChoiceOption>& opts = p.objects[i].options;
                if (previous[i] == kSkipped || opts.size() < 2) continue;
                for (size_t l = 0; l < opts.size(); ++l)
                    opts[l].benefit *= std::clamp(
                        1 - factors_.hystWeight * std::abs(int32_t(l) - previous[i]) / double(opts.size() - 1), 0.0, 1.0);
            }
        }
        std::copy(f.view.eye, f.view.eye + 3, lastEye_);
        return incremental_ ? fsIncremental(p, previous) : fsGreedy(p, greedy_);
    }
    bool incremental_, fsBenefit_ = false;
    FsBenefitFactors factors_;
    FsGreedyOptions greedy_;
    double lastEye_[3] = {0, 0, 0};
};

// The project's own policy (player/DEFAULT_POLICY.md): FS §6's raise and lower
// steps from last frame's cuts with a symmetric dead band, and a swap to the greedy's choice when
// it gains more than swap_gain (choice_hold.cpp).
class HoldPolicy final : public SolverPolicy {
public:
    explicit HoldPolicy(const PolicyOptions& o) : SolverPolicy("fs-hold", o) {
        hold_.headroom = o.get("fs-hold.headroom", hold_.headroom);
        hold_.swapGain = o.get("fs-hold.swap_gain", hold_.swapGain);
    }

private:
    Choice solve(const PolicyFrame&, ChoiceProblem& p, const std::vector<int32_t>& previous) override {
        return holdChoice(p, previous, hold_);
    }
    HoldOptions hold_;
};

class RhPolicy final : public SolverPolicy {
public:
    explicit RhPolicy(const PolicyOptions& o) : SolverPolicy("rh", o) {
        rh_.value = RhValue(int(o.get("rh.value", 8)) - 8);  // ranges checked by makePolicy
        rh_.c = o.get("rh.c", 1);
        rh_.logicMs = o.get("rh.logic_ms", 0);
    }

private:
    Choice solve(const PolicyFrame&, ChoiceProblem& p, const std::vector<int32_t>&) override {
        rh_.frameMs = p.budget;  // t_f: the objects' budget; eq. 7 with t_l and C (player/SOLVERS.md "rh")
        return robinHood(p, rh_);
    }
    RhOptions rh_;
};

class GbPolicy final : public SolverPolicy {
public:
    explicit GbPolicy(const PolicyOptions& o) : SolverPolicy("gb", o) {
        // GB's time budget (ms of wall clock) makes a run depend on the machine's load; off by
        // default so that runs repeat, the work bounded by max_newton instead.
        gb_.timeBudgetMs = o.get("gb.opt_ms", 0);
        gb_.accuracy = o.get("gb.accuracy", 1e-4);
        gb_.maxNewton = uint32_t(o.get("gb.max_newton", 200));
    }

private:
    Choice solve(const PolicyFrame&, ChoiceProblem& p, const std::vector<int32_t>&) override {
        std::vector<double> warm;
        bool any = false;
        for (const ChoiceObject& o : p.objects) {
            warm.push_back(prevResolution_[o.id]);
            any |= warm.back() >= 0;
        }
        if (!any) warm.clear();
        GbResult r = gbBarrier(p, warm, gb_);
        for (size_t i = 0; i < p.objects.size(); ++i) prevResolution_[p.objects[i].id] = r.resolution[i];
        Choice c = gbRound(p, r.resolution);
        c.iterations = r.newtonSteps;
        return c;
    }
    GbOptions gb_;
};

class OraclePolicy final : public SolverPolicy {
public:
    explicit OraclePolicy(const PolicyOptions& o) : SolverPolicy("oracle", o) {
        oracle_.maxStates = size_t(o.get("oracle.max_states", 1e6));
    }

private:
    Choice solve(const PolicyFrame&, ChoiceProblem& p, const std::vector<int32_t>&) override {
        return oracleChoice(p, oracle_).choice;
    }
    OracleOptions oracle_;
};

}  // namespace

std::unique_ptr<SelectionPolicy> makeFsGreedyPolicy(const PolicyOptions& o) { return std::make_unique<FsPolicy>(false, o); }
std::unique_ptr<SelectionPolicy> makeFsIncrementalPolicy(const PolicyOptions& o) {
    return std::make_unique<FsPolicy>(true, o);
}
std::unique_ptr<SelectionPolicy> makeHoldPolicy(const PolicyOptions& o) { return std::make_unique<HoldPolicy>(o); }
std::unique_ptr<SelectionPolicy> makeRhPolicy(const PolicyOptions& o) { return std::make_unique<RhPolicy>(o); }
std::unique_ptr<SelectionPolicy> makeGbPolicy(const PolicyOptions& o) { return std::make_unique<GbPolicy>(o); }
std::unique_ptr<SelectionPolicy> makeOraclePolicy(const PolicyOptions& o) { return std::make_unique<OraclePolicy>(o); }

}  // namespace hlod
