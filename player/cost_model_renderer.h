// A renderer that draws nothing and returns a frame time from a configurable model of the
// true cost, with seeded noise and an optional per-node error, so that tests and comparisons
// of selection algorithms are exact and repeatable.
#pragma once

#include "formats/constants.h"
#include "player/renderer.h"

#include <cstdint>
#include <random>
#include <unordered_map>

namespace hlod {

struct CostModel {
    double overheadMs = 2.0;              // fixed per-frame cost (clear, swap, state)
    double msPerTexturedTriangle = 2e-4;  // ~130 k textured triangles in 28 ms (llvmpipe, 2 threads)
    double msPerUntexturedTriangle = 2e-4 * (1 - Constants{}.textured) / Constants{}.textured;  // eq. 3.1 weights
    double noise = 0.02;                  // relative sd of the Gaussian noise on each frame
    double nodeError = 0;                 // each node's true cost is off by a fixed factor in [-e, e]
    uint64_t seed = 1;
    bool realTime = false;                // sleep for the modelled time, so that a loading thread
                                          // gets the wall-clock time a real frame would give it (at most 1 s)
};

// The untextured rate that makes the model agree with eq. 3.1 (cost = textured x c_textured +
// untextured x (1 - c_textured)): a textured triangle costs c / (1 - c) of an untextured one, so
// the engine's estimate v_time x cost is right whatever the mix. `hlod play` applies it with the
// database's c_textured unless --model-ms-per-flat-tri is given.
double consistentUntexturedRate(double msPerTexturedTriangle, double cTextured);

class CostModelRenderer final : public Renderer {
public:
    explicit CostModelRenderer(const CostModel& model = {});
    std::string name() const override { return "model"; }
    void upload(DecodedNode&& node) override;
    void evict(uint32_t node) override;
    // Throws std::logic_error when asked to draw a node that is not uploaded.
    double drawFrame(const Camera& camera, std::span<const DrawItem> items, const FrameOptions& options) override;

    double trueCostMs(uint32_t node) const;  // without noise; throws if not uploaded
    uint64_t uploads() const { return uploads_; }

private:
    CostModel model_;
    std::mt19937_64 rng_;
    std::unordered_map<uint32_t, double> nodes_;  // node -> modelled ms
    uint64_t uploads_ = 0;
};

}  // namespace hlod
