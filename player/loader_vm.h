// The out-of-core loader of Varadhan & Manocha 2002 §4 (`--loader vm`; `--loader demand` is the
// same without prefetching, their OOCNoPre): each frame's fetch command (§4.1 Stage II) loads
// the wanted-but-missing nodes first, in order; the rest of the time (Stages III and I) pops the
// highest-priority error bin (§4.2.3, Fig. 5; player/vm_bins.h) and loads the popped node's
// parent and children (PREFETCH), classifying each; a demand preempts a prefetch between two
// chunks. Replacement by the LRU variant of §4.3 (player/vm_lru.h): victims from the head, never a
// node drawn this frame, never hlod0; a prefetch never evicts a node accessed in this frame's
// fetch or the previous one ("recently fetched", §4.3). Open choices: player/LOADERS.md.
#pragma once

#include "player/benefit.h"
#include "player/loader.h"
#include "player/vm_bins.h"
#include "player/vm_lru.h"

#include <deque>
#include <unordered_map>

namespace hlod {

// One frame's classification data, copied for the loading thread.
struct VmFrame {
    double tolerance = 10;  // epsilon of §3.2 in the units of `errors`
    double delta = 12;      // delta of §4.2.3
    double binWidth = 1;
    // eps_O of the nodes the selector evaluated this frame (player/LOADERS.md: the thesis
    // selector's time slices mapped to pixels-like errors, or the projected error of `sse`).
    std::unordered_map<uint32_t, double> errors;
    // Visited nodes outside the render frustum (the cut beyond F_R, §4.2.2 visibility events):
    // classified with the front, loaded themselves when popped.
    std::vector<uint32_t> outside;
    bool nativeErrors = false;  // others: projectedErrorPx with `projection`; else inherited
    Projection projection;
    double eye[3] = {0, 0, 0}, forward[3] = {0, 0, -1};
    double theta0 = 0.5, theta1 = 0.8;  // half-angles of F_R and F_I (radians)
    bool moved = true;                  // the viewpoint changed: flush the bins (§4.2.3)
};

// The angle between the line of sight and the node's bounding sphere (0 when it meets the axis).
double angleToLineOfSight(const Node& node, const double eye[3], const double forward[3]);

class VmLoader final : public Loader {
public:
    VmLoader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options, bool prefetch);
    ~VmLoader() override;
    void update(const LoadRequest& request) override;

    // Test access (only while no thread runs).
    const InMemoryList& inMemoryList() const { return lru_; }

private:
    bool prefetch_;
    // guarded by mutex_
    InMemoryList lru_;
    VmBins bins_;
    std::shared_ptr<const VmFrame> vm_;
    std::deque<uint32_t> demand_;   // L_O of the last fetch command, in front order
    std::deque<std::pair<uint32_t, double>> expand_;  // PAR(O) and CHD(O) of popped nodes, with eps_O
    std::vector<uint64_t> classified_, accessed_;    // flush / fetch epoch of the last classification, access
    std::vector<double> error_;                      // eps_O at the last classification
    std::vector<uint8_t> inFi_;                      // within the prefetch frustum at the last one
    std::vector<uint8_t> drawn_;
    std::vector<uint32_t> front_;
    uint64_t flush_ = 0, epoch_ = 0;
    bool blocked_ = false;  // a prefetch found no room: wait for the next frame

    bool loadOne(bool preemptible) override;
    bool makeRoomLocked(uint64_t bytes, const std::function<bool(uint32_t)>& keep) override;
    void onFailedLocked(uint32_t id) override { lru_.remove(id); }
    void onFetchedLocked(uint32_t id) override;
    uint32_t pickLocked(bool& demand);
    bool classifyLocked(uint32_t id, double inherited);
    void accessLocked(uint32_t id);
    bool demandPendingLocked() const;
};

}  // namespace hlod
