// Varadhan & Manocha 2002 §4: fetch of the front's missing nodes (§4.1 Stage II), prioritized
// prefetching (§4.2: expanded frustum and AngPr, §4.2.2; error bins, §4.2.3 Fig. 5; PREFETCH loads
// PAR(O) and CHD(O)), blockwise preemptible loading (§4.2.3, last paragraph) and the LRU
// replacement of §4.3 (Fig. 7). Our nodes have one object-rep each (an HLOD node), so PAR(N[0])
// is the parent node and CHD(N[0]) its children.
#include "player/loader_vm.h"

#include "player/priority_queue.h"

#include <algorithm>
#include <cmath>

namespace hlod {

double angleToLineOfSight(const Node& node, const double eye[3], const double forward[3]) {
    const Box3f& b = node.bounds;
    double c[3] = {0.5 * (b.min.x + b.max.x) - eye[0], 0.5 * (b.min.y + b.max.y) - eye[1], 0.5 * (b.min.z + b.max.z) - eye[2]};
    double r = 0.5 * std::hypot(b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z);
    double d = std::hypot(c[0], c[1], c[2]);
    if (d <= r) return 0;
    double cosine = std::clamp((c[0] * forward[0] + c[1] * forward[1] + c[2] * forward[2]) / d, -1.0, 1.0);
    return std::max(std::acos(cosine) - std::asin(r / d), 0.0);
}

VmLoader::VmLoader(std::shared_ptr<const NodeSource> source, const LoaderOptions& options, bool prefetch)
    : Loader(std::move(source), options),
      prefetch_(prefetch),
      lru_(uint32_t(source_->skeleton().nodes.size())),
      bins_(10, 12, 1),
      classified_(source_->skeleton().nodes.size(), 0),
      accessed_(source_->skeleton().nodes.size(), 0),
      error_(source_->skeleton().nodes.size(), 0),
      inFi_(source_->skeleton().nodes.size(), 0),
      drawn_(source_->skeleton().nodes.size(), 0) {}

VmLoader::~VmLoader() { joinThread(); }

void VmLoader::accessLocked(uint32_t id) {
    lru_.access(id);
    accessed_[id] = epoch_;
}

void VmLoader::onFetchedLocked(uint32_t id) { accessLocked(id); }

// CLASSIFY(O) of §4.2.3 with the integrated priority; a node outside the prefetch frustum F_I
// (theta > theta1) or beyond the last bin is not prefetched. A node the selector did not evaluate
// inherits the error of the node whose PAR/CHD it is (player/LOADERS.md). Returns whether the node
// lies in F_I.
bool VmLoader::classifyLocked(uint32_t id, double inherited) {
    if (!vm_) return false;
    if (classified_[id] == flush_) return inFi_[id] != 0;
    classified_[id] = flush_;
    const Node& n = source_->skeleton().nodes[id];
    double error = inherited;
    if (auto it = vm_->errors.find(id); it != vm_->errors.end())
        error = it->second;
    else if (vm_->nativeErrors)
        error = projectedErrorPx(n, vm_->projection);
    double theta = angleToLineOfSight(n, vm_->eye, vm_->forward);
    inFi_[id] = theta <= vm_->theta1;
    if (!inFi_[id]) return false;
    double p = integratedPriority(error, vm_->tolerance, angularPriority(theta, vm_->theta0, vm_->theta1));
    error_[id] = error;
    bins_.push(id, p);
    return true;
}

void VmLoader::update(const LoadRequest& request) {
    {
        auto lock = lockTimed();
        ++epoch_;
        for (uint32_t id : front_) drawn_[id] = 0;
        front_.assign(request.front.begin(), request.front.end());
        for (uint32_t id : front_) drawn_[id] = 1;
        markWantedLocked(request.wanted);
        // The fetch command (§4.1): StartTail, then every front node is accessed (L_I) and the
        // missing ones (L_O) are fetched first, in order.
        lru_.markStartTail();
        for (uint32_t id : front_)
            if (lru_.contains(id)) accessLocked(id);
        demand_.assign(request.wanted.begin(), request.wanted.end());
        blocked_ = false;
        if (prefetch_ && request.vm && (request.vm->moved || !vm_)) {
            // "P_I flushes the bins and classifies the front only when the view-point changes."
            vm_ = request.vm;
            bins_ = VmBins(vm_->tolerance, vm_->delta, vm_->binWidth);
            expand_.clear();
            ++flush_;
            for (uint32_t id : front_) classifyLocked(id, 0);
            for (uint32_t id : vm_->outside) classifyLocked(id, 0);
        }
        dirty_ = true;
    }
    wake_.notify_one();
}

bool VmLoader::demandPendingLocked() const {
    for (uint32_t id : demand_)
        if (state_[id] == Residency::Unloaded) return true;
    return false;
}

// The next node to load: the first wanted one still missing, else (vm) the next of PAR(O) and
// CHD(O) of the popped nodes that is not in memory (those in memory are accessed, §4.3); a popped
// node outside the render frustum that is not in memory comes first itself.
uint32_t VmLoader::pickLocked(bool& demand) {
    auto fits = [&](uint32_t id, bool isDemand) {
        if (options_.memoryBudget == 0) return true;
        // A prefetch spares the nodes accessed in this fetch and the previous one (LOADERS.md, choice 9).
        auto keep = [&](uint32_t c) { return !isDemand && accessed_[c] + 1 >= epoch_; };
        return makeRoomLocked(source_->expectedBytes(id), keep);
    };
    while (!demand_.empty()) {
        uint32_t id = demand_.front();
        demand_.pop_front();
        if (state_[id] != Residency::Unloaded) continue;
        if (!fits(id, true)) continue;  // no room even without prefetched nodes: the parent stays drawn
        demand = true;
        return id;
    }
    demand = false;
    if (!prefetch_ || blocked_) return kNoNode;
    const Skeleton& s = source_->skeleton();
    for (;;) {
        if (expand_.empty()) {
            uint32_t o = bins_.pop();
            if (o == kNoNode) return kNoNode;
            double error = error_[o];
            if (state_[o] == Residency::Unloaded) expand_.push_back({o, error});  // outside F_R: O itself first
            if (s.nodes[o].parent != kNone) expand_.push_back({s.nodes[o].parent, error});
            for (uint32_t c = s.nodes[o].firstChild; c != kNone && s.nodes[c].parent == o; c = s.nodes[c].nextSibling)
                expand_.push_back({c, error});
            if (expand_.empty()) continue;  // a resident hlod0 leaf: nothing around it to fetch
        }
        auto [id, error] = expand_.front();
        expand_.pop_front();
        // PAR(O) and CHD(O) outside F_I are not loaded (LOADERS.md): F_I bounds the prefetch.
        if (!classifyLocked(id, error)) continue;
        if (s.nodes[id].level == 0 || state_[id] == Residency::Failed || state_[id] == Residency::Loading) continue;
        if (state_[id] != Residency::Unloaded) {
            accessLocked(id);
            continue;
        }
        if (!fits(id, false)) {
            blocked_ = true;
            expand_.push_front({id, error});
            return kNoNode;
        }
        return id;
    }
}

bool VmLoader::loadOne(bool preemptible) {
    uint32_t id;
    uint64_t reserved;
    bool demand;
    {
        std::lock_guard lock(mutex_);
        if (stop_ || ready_.size() >= options_.maxReady) return false;
        id = pickLocked(demand);
        if (id == kNoNode) return false;
        reserved = source_->expectedBytes(id);
        state_[id] = Residency::Loading;
        counters_.residentBytes += reserved;
    }
    uint64_t size = source_->nodeSize(id);
    std::vector<uint8_t> data(size);
    try {
        for (uint64_t done = 0; done < size;) {
            uint64_t n = std::min(options_.chunkBytes, size - done);
            source_->readChunk(id, done, std::span(data).subspan(done, n));
            done += n;
            if (!preemptible || demand || done == size) continue;
            // "P_I loads an object-rep in terms of blocks, and checks with P_R after it has
            // loaded each block": a new demand preempts the prefetch (its bytes are dropped).
            std::lock_guard lock(mutex_);
            if (!stop_ && !demandPendingLocked()) continue;
            state_[id] = Residency::Unloaded;
            counters_.residentBytes -= reserved;
            ++counters_.preemptions;
            expand_.push_front({id, error_[id]});
            return true;
        }
        DecodedNode node = source_->decode(id, data);
        std::lock_guard lock(mutex_);
        counters_.residentBytes = counters_.residentBytes - reserved + node.bytes();
        countLoadLocked(id, size, node.bytes());
        state_[id] = Residency::Ready;
        ready_.push_back(std::move(node));
        accessLocked(id);
    } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        counters_.residentBytes -= reserved;
        failLocked(id, e.what());
    }
    return true;
}

// §4.3 step 3: victims from the head of the InMemoryList, skipping the nodes drawn this frame
// (hlod0 is never in the list), those `keep` protects, and those not uploaded yet (choice 13).
bool VmLoader::makeRoomLocked(uint64_t bytes, const std::function<bool(uint32_t)>& keep) {
    for (uint32_t c = lru_.head(); c != kNoNode && counters_.residentBytes + bytes > options_.memoryBudget;) {
        uint32_t next = lru_.next(c);
        if (!drawn_[c] && !keep(c) && state_[c] == Residency::Resident) {
            evictLocked(c);
            lru_.remove(c);
        }
        c = next;
    }
    return counters_.residentBytes + bytes <= options_.memoryBudget;
}

}  // namespace hlod
