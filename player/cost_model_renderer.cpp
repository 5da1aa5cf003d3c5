// Cost-model renderer: frame time = overhead + sum over drawn nodes of (textured and
// untextured triangle costs) * (1 + the node's fixed error), times (1 + seeded Gaussian noise).
// It stands in for the graphics pipeline of thesis Fig. 4.1 when selection is what is studied.
#include "player/cost_model_renderer.h"

#include <xxhash.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

namespace hlod {

double consistentUntexturedRate(double msPerTexturedTriangle, double cTextured) {
    return msPerTexturedTriangle * (1 - cTextured) / cTextured;  // eq. 3.1 weights
}

CostModelRenderer::CostModelRenderer(const CostModel& model) : model_(model), rng_(model.seed) {}

void CostModelRenderer::upload(DecodedNode&& node) {
    uint64_t textured = 0, untextured = 0;
    for (size_t i = 0; i < node.meshes.size(); ++i) {
        bool isTextured = i < node.meshTexture.size() && node.meshTexture[i] >= 0;
        (isTextured ? textured : untextured) += node.meshes[i].triangleCount();
    }
    // A fixed per-node error drawn from the node id and the seed: the same in every run.
    uint64_t key[2] = {node.id, model_.seed};
    double unit = double(XXH3_64bits(key, sizeof key) >> 11) / double(1ull << 53);  // [0, 1)
    double error = model_.nodeError * (2 * unit - 1);
    double ms = (textured * model_.msPerTexturedTriangle + untextured * model_.msPerUntexturedTriangle) * (1 + error);
    nodes_[node.id] = ms;
    ++uploads_;
}

void CostModelRenderer::evict(uint32_t node) {
    nodes_.erase(node);
}

double CostModelRenderer::trueCostMs(uint32_t node) const {
    auto it = nodes_.find(node);
    if (it == nodes_.end()) throw std::logic_error("cost model renderer: node " + std::to_string(node) + " is not uploaded");
    return it->second;
}

double CostModelRenderer::drawFrame(const Camera&, std::span<const DrawItem> items, const FrameOptions&) {
    double ms = model_.overheadMs;
    for (const DrawItem& item : items) ms += trueCostMs(item.node);
    std::normal_distribution<double> noise(0.0, model_.noise);
    ms *= std::max(0.1, 1 + noise(rng_));
    // At most a second of real time a frame: far beyond any frame budget, and a modelled time of
    // hours (an absurd --model-* option) neither hangs the replay nor overflows the clock.
    if (model_.realTime) std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(std::min(ms, 1000.0)));
    return ms;
}

}  // namespace hlod
