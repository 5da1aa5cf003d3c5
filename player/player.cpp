// The rendering engine of thesis Chapter 4 (Fig. 4.1): initialisation (skeleton, then every
// hlod0 node), and per frame: upload of decoded nodes (bounded), selection (§4.2), priority
// updates and eviction for the loading thread (§4.3), draw, and the two feedback loops of
// §4.2: v_time (estimated vs measured frame time) and the hlod0 share.
#include "player/player.h"

#include "player/camera_path.h"
#include "player/loader.h"
#include "player/front.h"
#include "player/node_source.h"
#include "player/policy.h"
#include "player/selection.h"
#include "player/vm_frame.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace hlod {
namespace {

double median3(double a, double b, double c) { return std::max(std::min(a, b), std::min(std::max(a, b), c)); }

// The model's box (camera_path.h: its hlod0 nodes'; each node lies within its root's), a point at
// the origin for a skeleton without nodes.
Box3f playerModel(const Skeleton& s) {
    const Box3f b = modelBounds(s);
    return b.min.x <= b.max.x ? b : Box3f{};
}

// A camera above the model's box looking down -Z, the whole model in view (start-up timing).
Camera overviewCamera(const Box3f& b) {
    double radius = 0.5 * std::hypot(b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z);
    Camera cam;
    cam.position[0] = 0.5 * (b.min.x + b.max.x);
    cam.position[1] = 0.5 * (b.min.y + b.max.y);
    cam.position[2] = b.max.z + radius / std::tan(cam.vfovDegrees * M_PI / 360.0);
    fitClipPlanes(cam, b);
    return cam;
}

}  // namespace

struct Player::Impl {
    std::shared_ptr<const NodeSource> source;
    const Skeleton& skeleton;
    Constants c;
    Renderer& renderer;
    PlayerOptions options;
    std::unique_ptr<Loader> loader;
    SelectionState selection;
    std::unique_ptr<SelectionPolicy> policy;
    std::vector<uint8_t> resident;
    std::vector<uint64_t> visitedStamp;  // frame number + 1 of the last visit
    std::vector<uint32_t> lastVisited;
    std::vector<DrawItem> front;
    Box3f model;    // playerModel
    Camera camera;  // the last frame's, its clip planes fitted to the model
    uint32_t levels = 1;
    uint32_t startFailures = 0;  // nodes that failed to load at start (incore, preload)
    double overhead = 0, vTime0 = 0, vTime = 0, share = 0;
    double residentCost = 0;  // sum of cost over resident nodes (§4.3 memory estimate)
    uint32_t residentNodes = 0;
    uint64_t frameIndex = 0;
    bool havePrevious = false;
    double previousPosition[3] = {0, 0, 0}, previousTime = 0, velocity[3] = {0, 0, 0};
    bool frontSkips = false;  // PolicyFront::skipsBlocks of the last frame
    double distance = 0;  // camera path length so far, teleports excluded (toggles per metre, §6.5)
    std::vector<uint8_t> failed, waitView;  // failed loads; --on-miss wait: what the selector may draw
    bool haveForward = false, moved = true;
    double previousForward[3] = {0, 0, -1}, forwardTime = 0, angularSpeed = 0;  // vm prefetch frustum
    uint64_t lastDemandBytes = 0, lastPrefetchBytes = 0;

    Impl(std::shared_ptr<const NodeSource> src, const Constants& constants, Renderer& r, const PlayerOptions& o)
        : source(std::move(src)),
          skeleton(source->skeleton()),
          c(constants),
          renderer(r),
          options(o),
          // Room is made each frame for what the loader can take before the next frame: the
          // synchronous step's nodes, or what the render thread may upload in one frame.
          loader(makeLoader(o.loader, source,
                            LoaderOptions{o.memoryBudget, o.chunkBytes, 64, 8,
                                          o.threadedLoader ? o.maxUploadsPerFrame : o.syncLoadsPerFrame})),
          selection(skeleton),
          policy(makePolicy(o.policy, o.policyOptions)),
          resident(skeleton.nodes.size(), 0),
          visitedStamp(skeleton.nodes.size(), 0),
          model(playerModel(skeleton)),
          failed(skeleton.nodes.size(), 0),
          waitView(skeleton.nodes.size(), 1) {
        const bool incore = options.loader == LoaderKind::Incore;
        if ((incore || options.preload) && options.memoryBudget > 0) {
            uint64_t total = 0;
            for (const Node& n : skeleton.nodes) total += source->expectedBytes(n.id);
            if (total > options.memoryBudget)
                throw std::invalid_argument(std::string(incore ? "--loader incore" : "--preload") +
                                            " needs every node in memory: " + std::to_string(total) +
                                            " bytes > memory budget " + std::to_string(options.memoryBudget));
        }
        if (options.memoryBudget > 0) {  // §4.3: hlod0 stays resident; a smaller budget loaded nothing (until stop 45)
            uint64_t roots = 0;
            for (uint32_t root : skeleton.roots()) roots += source->expectedBytes(root);
            if (roots > options.memoryBudget)
                throw std::invalid_argument("--memory " + std::to_string(options.memoryBudget) + " is below the " +
                                            std::to_string(roots) + " bytes of the hlod0 nodes, which stay resident (thesis §4.3)");
        }
        for (const Node& n : skeleton.nodes) levels = std::max(levels, n.level + 1);
        for (uint32_t root : selection.roots) {
            renderer.upload(loadRoot(root));
            markResident(root, true);
        }
        if (options.preload || incore) {
            for (const Node& n : skeleton.nodes)
                if (!resident[n.id])
                    if (std::optional<DecodedNode> node = loader->tryLoadPinned(n.id)) {
                        renderer.upload(std::move(*node));
                        markResident(n.id, true);
                    }
            startFailures = reportFailures();  // skipped as in any run (its parent drawn); --strict stops here
        }
        calibrate();
        if (options.threadedLoader) loader->start();
    }

    // The traversal starts from every hlod0 node (§4.2) and none is ever skipped: a root that
    // cannot load ends the run before it starts.
    DecodedNode loadRoot(uint32_t id) {
        try {
            return loader->loadPinned(id);
        } catch (const std::exception& e) {
            throw FormatError(std::string(e.what()) + " (hlod0 node " + std::to_string(id) + ", which is never skipped)");
        }
    }

    // A node that cannot be read or decoded stays unloaded for good: the selection treats it as a
    // child that never arrives (a miss: its parent stays drawn, §4.2) and its subtree is never
    // visited, so never requested. Strict runs stop at the first one instead.
    uint32_t reportFailures() {
        std::vector<LoadFailure> failures = loader->takeFailures();
        for (const LoadFailure& f : failures) {
            if (options.strictLoads) throw FormatError(f.what);
            failed[f.node] = 1;
            waitView[f.node] = 0;
            if (options.onLoadFailure) options.onLoadFailure(f);
        }
        return uint32_t(failures.size());
    }

    void markResident(uint32_t id, bool on) {
        resident[id] = on;
        residentCost += (on ? 1 : -1) * double(skeleton.nodes[id].cost);
        residentNodes += on ? 1 : -1;
    }

    // Fixed overhead "measured by disabling actual rendering" (§4.2 footnote 3), and the first
    // v_time from a frame of all hlod0 nodes; either may be given instead.
    void calibrate() {
        const Camera cam = overviewCamera(model);
        FrameOptions fo = options.frameOptions;
        overhead = options.overheadMs;
        if (overhead < 0) {
            double t[3];
            for (double& x : t) x = renderer.drawFrame(cam, {}, fo);
            overhead = median3(t[0], t[1], t[2]);
        }
        vTime0 = options.initialVTime;
        if (vTime0 <= 0) {
            std::vector<DrawItem> all;
            double cost = 0;
            for (uint32_t r : selection.roots) {
                all.push_back({r, 0});
                cost += skeleton.nodes[r].cost;
            }
            double t[3];
            for (double& x : t) x = renderer.drawFrame(cam, all, fo);
            vTime0 = cost > 0 ? std::max(median3(t[0], t[1], t[2]) - overhead, 0.0) / cost : 0;
            vTime0 = std::max(vTime0, 1e-9);
        }
        vTime = vTime0;
        // The first hlod0 share: the target less the fixed overhead, i.e. the time the nodes may take.
        share = std::max(c.targetTimeMs - overhead, kMinShare * c.targetTimeMs);
    }

    void updateVelocity(const Camera& camera, double t) {
        if (havePrevious && t > previousTime) {
            double v[3], speed = 0;
            for (int i = 0; i < 3; ++i) {
                v[i] = (camera.position[i] - previousPosition[i]) / (t - previousTime);
                speed += v[i] * v[i];
            }
            // Teleports are not motion: speeds above teleportSpeed are clamped to it. The estimate
            // is smoothed: half the previous velocity, half this frame's.
            double limit = options.teleportSpeed / options.metresPerUnit;
            double scale = std::sqrt(speed) > limit ? limit / std::sqrt(speed) : 1;
            if (scale == 1) distance += std::sqrt(speed) * (t - previousTime);
            for (int i = 0; i < 3; ++i) velocity[i] = 0.5 * velocity[i] + 0.5 * v[i] * scale;
        }
        havePrevious = true;
        previousTime = t;
        std::copy(camera.position, camera.position + 3, previousPosition);
    }

    uint32_t uploadReady() {
        uint32_t loads = 0;
        for (DecodedNode& node : loader->takeReady(options.maxUploadsPerFrame, options.maxUploadBytesPerFrame)) {
            uint32_t id = node.id;
            renderer.upload(std::move(node));
            markResident(id, true);
            ++loads;
        }
        return loads;
    }

    // Uploaded nodes the loader evicted (vm: while loading; thesis: in update).
    uint32_t applyEvictions() {
        std::vector<uint32_t> evicted = loader->takeEvicted();
        for (uint32_t id : evicted) {
            renderer.evict(id);
            markResident(id, false);
        }
        return uint32_t(evicted.size());
    }

    // The viewing direction's angular speed (rad/s, smoothed as the velocity is) and whether the
    // viewpoint changed: the vm loader's prefetch frustum and bin flush (player/LOADERS.md).
    void updateAngularSpeed(const View& view, bool stepped, double t) {
        double dot = 0;
        for (int i = 0; i < 3; ++i) dot += view.forward[i] * previousForward[i];
        double angle = haveForward ? std::acos(std::clamp(dot, -1.0, 1.0)) : 0;
        if (haveForward && t > forwardTime) angularSpeed = 0.5 * angularSpeed + 0.5 * angle / (t - forwardTime);
        moved = !haveForward || angle > 0 || stepped;
        haveForward = true;
        forwardTime = t;
        std::copy(view.forward, view.forward + 3, previousForward);
    }

    // Nodes the selector wanted to draw but could not: the visible (with requireLoadedChildren,
    // every) unloaded children of the nodes drawn for a miss.
    std::vector<uint32_t> wantedChildren(const PolicyFront& sel) const {
        std::vector<uint32_t> wanted;
        for (const DrawnNode& d : sel.drawn) {
            if (d.reason != DrawReason::Miss) continue;
            for (uint32_t c = skeleton.nodes[d.node].firstChild; c != kNone && skeleton.nodes[c].parent == d.node;
                 c = skeleton.nodes[c].nextSibling)
                if (!resident[c] && !failed[c] && (selection.nodes[c].frustumVis >= 1 || options.requireLoadedChildren))
                    wanted.push_back(c);
        }
        return wanted;
    }

    // --on-miss wait (Varadhan & Manocha §4.1 Stage II): the frame waits while the drawn nodes that
    // are not resident are fetched; one that cannot be (no room, failed) gives way to its nearest
    // resident ancestor. Returns the wait: the disk model's time (synchronous) or the measured one.
    double fetchFront(PolicyFront& sel, std::vector<uint32_t>& wanted, FrameStats& s) {
        std::vector<uint32_t> front;
        for (const DrawnNode& d : sel.drawn) {
            front.push_back(d.node);
            if (!resident[d.node]) wanted.push_back(d.node);
        }
        if (wanted.empty()) return 0;
        auto t0 = std::chrono::steady_clock::now();
        FetchResult r = loader->fetchNow(wanted, front, options.disk);
        double measured = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        for (DecodedNode& node : r.nodes) {
            uint32_t id = node.id;
            renderer.upload(std::move(node));
            markResident(id, true);
            ++s.loads;
        }
        s.failedLoads += reportFailures();
        fallBackToResidentAncestors(sel);
        return options.threadedLoader ? measured : r.modelledMs;
    }

    void fallBackToResidentAncestors(PolicyFront& sel) const {
        std::vector<uint8_t> cover(skeleton.nodes.size(), 0);
        std::vector<uint32_t> up;
        for (const DrawnNode& d : sel.drawn) {
            if (resident[d.node]) continue;
            uint32_t a = skeleton.nodes[d.node].parent;
            while (a != kNone && !resident[a]) a = skeleton.nodes[a].parent;
            if (a != kNone && !cover[a]) {
                cover[a] = 1;
                up.push_back(a);
            }
        }
        if (up.empty()) return;
        auto covered = [&](uint32_t id) {
            for (uint32_t p = skeleton.nodes[id].parent; p != kNone; p = skeleton.nodes[p].parent)
                if (cover[p]) return true;
            return false;
        };
        std::vector<DrawnNode> out;
        for (const DrawnNode& d : sel.drawn)
            if (resident[d.node] && !cover[d.node] && !covered(d.node)) out.push_back(d);
        for (uint32_t a : up)
            if (!covered(a)) out.push_back({a, DrawReason::Miss});
        sel.drawn = std::move(out);
    }

    void updateLoader(const std::vector<uint32_t>& visited, std::span<const DrawItem> drawn,
                          std::span<const uint32_t> wanted, const Camera& camera, const Projection& projection) {
        uint64_t stamp = frameIndex + 1;
        std::vector<PriorityUpdate> updates;
        updates.reserve(visited.size());
        for (uint32_t id : visited) {
            visitedStamp[id] = stamp;
            if (skeleton.nodes[id].level > 0) updates.push_back({id, selection.nodes[id].priority});
        }
        std::vector<uint32_t> forget;
        for (uint32_t id : lastVisited)
            if (visitedStamp[id] != stamp && skeleton.nodes[id].level > 0) forget.push_back(id);
        // Pinned: every node on the front's path (hlod0, the refined ancestors, the drawn nodes).
        // Evicting a refined node would leave its visible child unloaded next frame and the
        // front would collapse to the parent.
        auto pinned = [&](uint32_t id) {
            return skeleton.nodes[id].level == 0 || selection.role(id) != DrawState::None;
        };
        std::vector<uint32_t> front;
        for (const DrawItem& d : drawn) front.push_back(d.node);
        LoadRequest request{updates, forget, front, wanted, pinned, nullptr};
        if (options.loader == LoaderKind::Vm)
            request.vm = makeVmFrame({skeleton, selection, visited, options.policy, options.policyOptions, options.vm, camera,
                                      projection, vTime, angularSpeed, options.lookaheadSeconds, moved});
        loader->update(request);
        lastVisited = visited;
    }

    // Triangles full detail would draw for a visible node: its visible children's, recursively; a
    // leaf's or a node's with no visible child, its own (what the `none` policy draws).
    template <class Visible>
    uint64_t fullDetailTriangles(uint32_t id, const Visible& visible) const {
        uint64_t sum = 0;
        bool anyVisible = false;
        for (uint32_t ch = skeleton.nodes[id].firstChild; ch != kNone && skeleton.nodes[ch].parent == id;
             ch = skeleton.nodes[ch].nextSibling)
            if (visible(ch)) {
                anyVisible = true;
                sum += fullDetailTriangles(ch, visible);
            }
        return anyVisible ? sum : skeleton.nodes[id].triangles();
    }

    FrameStats frame(const Camera& requested, double timeSeconds) {
        camera = requested;
        fitClipPlanes(camera, model);
        FrameStats s;
        s.frame = frameIndex;
        s.timeSeconds = timeSeconds;
        s.targetMs = c.targetTimeMs;
        s.hlod0ShareMs = share;
        if (!options.threadedLoader) loader->step(options.syncLoadsPerFrame);
        s.failedLoads = reportFailures() + std::exchange(startFailures, 0);  // the first frame counts the start's
        s.evictions = applyEvictions();
        s.loads = uploadReady();

        const bool stepped = !std::equal(camera.position, camera.position + 3, previousPosition);
        updateVelocity(camera, timeSeconds);
        View view = makeView(camera, velocity, options.lookaheadSeconds);
        updateAngularSpeed(view, stepped, timeSeconds);
        Evaluate evaluate = [&](uint32_t id) {
            const Node& n = skeleton.nodes[id];
            double fv = frustumVis(view, n.bounds);
            return NodeEval{nodePriority(n, view, c, fv), fv};
        };
        Projection projection = makeProjection(camera, options.viewportHeight);
        const bool wait = options.onMiss == OnMiss::Wait;
        PolicyFrame pf{skeleton, c, camera, view, projection, evaluate, wait ? waitView : resident, frameIndex,
                       c.targetTimeMs, overhead, vTime, share, options.requireLoadedChildren,
                       options.initialHystSwitches * c.hystSwitch};
        auto t0 = std::chrono::steady_clock::now();
        PolicyFront sel = policy->select(pf, selection);
        std::vector<uint32_t> wanted;
        auto t1 = std::chrono::steady_clock::now();
        if (wait)
            s.waitMs = fetchFront(sel, wanted, s);
        else
            wanted = wantedChildren(sel);
        auto t2 = std::chrono::steady_clock::now();
        FrontAccount account = accountFront(skeleton, selection, sel.drawn);
        s.selectionMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t2 + (t1 - t0)).count();
        updateLoader(sel.visited, account.items, wanted, camera, projection);

        // The feedback loops see the drawing time: a wait for the disk is not the front's cost.
        const double drawMs = renderer.drawFrame(camera, account.items, options.frameOptions);
        // Evictions of this frame's fetch and update leave the renderer after the draw: a loading
        // thread may have evicted a node of this front before update() protected it.
        s.evictions += applyEvictions();
        s.actualMs = drawMs + s.waitMs;
        s.estimateNoFeedbackMs = overhead + vTime0 * account.drawnCost;
        s.estimateMs = overhead + vTime * account.drawnCost;
        vTime = nextVTime(vTime, drawMs, overhead, account.drawnCost, options.vTimeGain);
        share = nextHlod0Share(share, c.targetTimeMs, drawMs, sel.refused, options.shareLoop);
        policy->observe(FrameOutcome{drawMs, s.estimateMs, c.targetTimeMs, account.drawnCost, vTime});

        s.vTime = vTime;
        s.nodesPerLevel.assign(levels, 0);
        s.trianglesPerLevel.assign(levels, 0);
        auto visible = [&](uint32_t id) { return frustumVis(view, skeleton.nodes[id].bounds) >= 1; };
        for (const DrawItem& d : account.items) {
            ++s.nodesPerLevel[d.level];
            s.trianglesPerLevel[d.level] += skeleton.nodes[d.node].triangles();
            if (visible(d.node)) s.visibleTriangles += fullDetailTriangles(d.node, visible);
        }
        s.upToggles = account.upToggles;
        s.downToggles = account.downToggles;
        s.reversals = account.reversals;
        s.misses = sel.misses;
        s.refused = sel.refused;
        s.residentNodes = residentNodes;
        LoaderCounters k = loader->counters();
        s.residentBytes = k.residentBytes;
        s.demandBytes = k.demandBytes - lastDemandBytes;
        s.prefetchBytes = k.prefetchBytes - lastPrefetchBytes;
        lastDemandBytes = k.demandBytes;
        lastPrefetchBytes = k.prefetchBytes;
        s.wantedMissing = uint32_t(wanted.size());
        for (const DrawItem& d : account.items) s.frontBytes += source->expectedBytes(d.node);
        s.memoryEstimateBytes = c.memory * residentCost;
        s.memoryEstimatePct = options.memoryBudget ? 100 * s.memoryEstimateBytes / double(options.memoryBudget) : NAN;
        s.distance = distance;
        s.stallMs = loader->takeLongestWaitMs();
        s.policy = policy->name();
        s.benefit = frontBenefit(skeleton, account.items, projection, visible);
        s.optimisationMs = sel.optimisationMs >= 0 ? sel.optimisationMs : s.selectionMs;
        s.iterations = sel.iterations;
        frontSkips = sel.skipsBlocks;
        s.leftoverMs = s.targetMs - s.estimateMs;
        front = std::move(account.items);
        ++frameIndex;
        return s;
    }
};

Player::Player(const Database& db, const Constants& constants, Renderer& renderer, const PlayerOptions& options)
    : Player(databaseSource(db), constants, renderer, options) {}

Player::Player(std::shared_ptr<const NodeSource> source, const Constants& constants, Renderer& renderer,
               const PlayerOptions& options)
    : impl_(std::make_unique<Impl>(std::move(source), constants, renderer, options)) {}

Player::~Player() = default;

FrameStats Player::frame(const Camera& camera, double timeSeconds) { return impl_->frame(camera, timeSeconds); }
const Skeleton& Player::skeleton() const { return impl_->skeleton; }
const Camera& Player::camera() const { return impl_->camera; }
std::span<const DrawItem> Player::front() const { return impl_->front; }
uint32_t Player::levelCount() const { return impl_->levels; }
double Player::vTime() const { return impl_->vTime; }
double Player::overheadMs() const { return impl_->overhead; }
double Player::hlod0ShareMs() const { return impl_->share; }
bool Player::resident(uint32_t node) const { return impl_->resident[node]; }
bool Player::frontSkipsBlocks() const { return impl_->frontSkips; }

}  // namespace hlod
