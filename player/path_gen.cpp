// Generated camera paths for `hlod path` (thesis Chapter 6 test conditions): a walk-through
// at eye height (~1.5 m/s, §6.2/§6.5), a drive-through ten times faster (§6.5), a fly-over
// with the whole model in view (§6.2), and an erratic walk with sudden 180-degree turns and
// teleports (viewpoint path C of T. A. Funkhouser and C. H. Séquin, "Adaptive Display Algorithm
// for Interactive Frame Rates During Visualization of Complex Virtual Environments", SIGGRAPH
// 1993). Routes are ellipses inset in the bounds. The eye of a city-like walk follows the lowest
// scanned surface under it (SurfaceHeights, when given; else an estimate from the finest node
// boxes), filtered so that it climbs and sinks at most kMaxClimbMps (player/CAMERA_PATH.md
// "Eye height", "Indoors").
#include "player/camera_path.h"

#include "formats/constants.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hlod {
namespace {

using Eigen::Vector3d;

double axis(const Vec3f& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

struct Frame {
    int up, a, b;  // up axis and the two horizontal axes
};

Frame frameFor(int upAxis) { return upAxis == 1 ? Frame{1, 2, 0} : Frame{2, 0, 1}; }

// Orientation looking along `forward` with `up` as close to vertical as possible (camera looks
// down -Z with +Y up).
void lookAlong(const Vector3d& forward, const Vector3d& up, double q[4]) {
    Vector3d f = forward.normalized();
    Vector3d right = f.cross(up).normalized();
    Vector3d trueUp = right.cross(f);
    Eigen::Matrix3d r;
    r.col(0) = right;
    r.col(1) = trueUp;
    r.col(2) = -f;
    Eigen::Quaterniond qq(r);
    qq.normalize();
    q[0] = qq.x();
    q[1] = qq.y();
    q[2] = qq.z();
    q[3] = qq.w();
}

// Ground under a horizontal point without the geometry: the lowest top of the finest-level node
// boxes above it (a terrain patch's top is at or above its surface, a street node's top is near
// street level while facades reach higher), found through a uniform grid of the boxes' footprints.
class GroundIndex {
public:
    GroundIndex(const Skeleton& s, const Frame& f, double fallback) : f_(f), fallback_(fallback) {
        uint32_t deepest = 0;
        for (const Node& n : s.nodes) deepest = std::max(deepest, n.level);
        for (const Node& n : s.nodes)
            if (n.level == deepest) leaves_.push_back(n.bounds);
        lo_[0] = lo_[1] = INFINITY;
        double hi[2] = {-INFINITY, -INFINITY};
        for (const Box3f& b : leaves_)
            for (int i = 0; i < 2; ++i) {
                lo_[i] = std::min(lo_[i], axis(b.min, i == 0 ? f.a : f.b));
                hi[i] = std::max(hi[i], axis(b.max, i == 0 ? f.a : f.b));
            }
        cells_ = std::max<uint32_t>(1, uint32_t(std::sqrt(double(leaves_.size()))));
        for (int i = 0; i < 2; ++i) size_[i] = std::max((hi[i] - lo_[i]) / cells_, 1e-6);
        grid_.resize(size_t(cells_) * cells_);
        for (uint32_t k = 0; k < leaves_.size(); ++k) {
            const Box3f& b = leaves_[k];
            auto [x0, y0] = cell(axis(b.min, f.a), axis(b.min, f.b));
            auto [x1, y1] = cell(axis(b.max, f.a), axis(b.max, f.b));
            for (uint32_t y = y0; y <= y1; ++y)
                for (uint32_t x = x0; x <= x1; ++x) grid_[size_t(y) * cells_ + x].push_back(k);
        }
    }

    double at(double x, double y) const {
        if (leaves_.empty()) return fallback_;
        auto [cx, cy] = cell(x, y);
        double ground = INFINITY;
        for (uint32_t k : grid_[size_t(cy) * cells_ + cx]) {
            const Box3f& b = leaves_[k];
            if (x >= axis(b.min, f_.a) && x <= axis(b.max, f_.a) && y >= axis(b.min, f_.b) && y <= axis(b.max, f_.b))
                ground = std::min(ground, axis(b.max, f_.up));
        }
        return std::isfinite(ground) ? ground : fallback_;
    }

private:
    Frame f_;
    double fallback_;
    std::vector<Box3f> leaves_;
    std::vector<std::vector<uint32_t>> grid_;
    uint32_t cells_ = 1;
    double lo_[2] = {0, 0}, size_[2] = {1, 1};

    std::pair<uint32_t, uint32_t> cell(double x, double y) const {
        auto clampCell = [&](double v, int i) {
            return uint32_t(std::clamp((v - lo_[i]) / size_[i], 0.0, double(cells_ - 1)));
        };
        return {clampCell(x, 0), clampCell(y, 1)};
    }
};

struct Route {
    Vector3d center, ea, eb, up;  // ellipse: center + cos t * ea + sin t * eb
    Vector3d at(double t) const { return center + std::cos(t) * ea + std::sin(t) * eb; }
    Vector3d tangent(double t) const { return -std::sin(t) * ea + std::cos(t) * eb; }
};

// The route by arc length: keys kParts apart in t, their chords summed, so a key moves the
// plan's speed wherever the ellipse runs (a step of speed x dt / |tangent(t)| from one key's t
// jumped 182 units in 0.5 s where a 1000 x 20 street's ellipse turns, and the lap did not close,
// until stop 51).
class ArcLength {
public:
    explicit ArcLength(const Route& r) : s_(kParts + 1) {
        for (size_t i = 1; i <= kParts; ++i) s_[i] = s_[i - 1] + (r.at(tOf(i)) - r.at(tOf(i - 1))).norm();
    }
    double length() const { return s_.back(); }
    double at(double t) const {  // the arc length at t
        const double u = std::fmod(std::fmod(t, 2 * M_PI) + 2 * M_PI, 2 * M_PI) / (2 * M_PI) * kParts;
        const size_t i = std::min(static_cast<size_t>(u), kParts - 1);
        return s_[i] + (u - double(i)) * (s_[i + 1] - s_[i]);
    }
    double t(double s) const {  // the t at arc length s (any lap)
        const double L = length();
        if (!(L > 0)) return 0;
        const double w = std::fmod(std::fmod(s, L) + L, L);
        const size_t i = std::min(static_cast<size_t>(std::upper_bound(s_.begin(), s_.end(), w) - s_.begin()), kParts) - 1;
        const double part = s_[i + 1] - s_[i];
        return tOf(i) + (part > 0 ? (w - s_[i]) / part : 0) * (2 * M_PI / kParts);
    }

private:
    static constexpr size_t kParts = 4096;
    static double tOf(size_t i) { return 2 * M_PI * double(i) / kParts; }
    std::vector<double> s_;  // arc length at tOf(i)
};

Vector3d unit(int i) { return Vector3d::Unit(i); }

// The ground the eye follows along one continuous stretch of keys (no teleport in it): the
// median over +-kGroundMedianSeconds (a key or two that stand out are dropped), then the largest
// height curve at or below it whose slope is at most `rate` units per second (forward and
// backward passes of s_i = min(g_i, s_j + rate |t_i - t_j|)): the eye never climbs or sinks
// faster than `rate`, and never rises above the filtered ground, so a roof the route crosses
// (it goes through buildings) or a ceiling-high box is not climbed unless it lasts.
void smoothGround(const std::vector<double>& times, std::vector<double>& ground, double rate) {
    const size_t n = ground.size();
    std::vector<double> median(n);
    for (size_t i = 0, lo = 0, hi = 0; i < n; ++i) {
        while (times[i] - times[lo] > kGroundMedianSeconds) ++lo;
        while (hi + 1 < n && times[hi + 1] - times[i] <= kGroundMedianSeconds) ++hi;
        std::vector<double> window(ground.begin() + static_cast<std::ptrdiff_t>(lo), ground.begin() + static_cast<std::ptrdiff_t>(hi + 1));
        std::nth_element(window.begin(), window.begin() + static_cast<std::ptrdiff_t>(window.size() / 2), window.end());
        median[i] = window[window.size() / 2];
    }
    for (size_t i = 1; i < n; ++i) median[i] = std::min(median[i], median[i - 1] + rate * (times[i] - times[i - 1]));
    for (size_t i = n - 1; i-- > 0;) median[i] = std::min(median[i], median[i + 1] + rate * (times[i + 1] - times[i]));
    ground = std::move(median);
}

CameraKey key(double time, const Vector3d& p, const Vector3d& forward, const Vector3d& up) {
    CameraKey k;
    k.time = time;
    for (int i = 0; i < 3; ++i) k.position[i] = p[i];
    lookAlong(forward, up, k.orientation);
    return k;
}

// A path the reader takes back (camera_path.h): within kMaxCameraTime, and at most kMaxCameraKeys
// keys (an erratic path adds one key per turn or teleport, every 2 s at most).
double checkedDuration(double duration, double keyInterval) {
    std::ostringstream s;
    s << "a path of " << duration << " s";
    if (!(duration <= kMaxCameraTime))
        throw std::invalid_argument(s.str() + " is longer than one day (" + std::to_string(int(kMaxCameraTime)) +
                                    " s): give --duration or a higher --speed");
    if (duration / keyInterval + duration / 2 + 2 > double(kMaxCameraKeys)) {
        s << " with a key every " << keyInterval << " s has more than " << kMaxCameraKeys << " keys: raise --key-interval";
        throw std::invalid_argument(s.str());
    }
    return duration;
}

// Key times: every keyInterval from 0, and the last at `duration` itself, so that a lap ends where
// it began whatever the interval (a 0.7 s interval cut a 60 s lap at 59.5 s, and one longer than
// the lap left a single key, a camera that never moved, until stop 50). Times are i x keyInterval,
// not a running sum; a remainder below kMinKeyInterval moves the last key instead.
std::vector<double> keyTimes(double duration, double keyInterval) {
    std::vector<double> times;
    for (double i = 0; i * keyInterval < duration - kMinKeyInterval; ++i) times.push_back(i * keyInterval);
    times.push_back(duration);
    if (times.size() == 1 && duration > 0) times.insert(times.begin(), 0.0);
    return times;
}

}  // namespace

size_t countCrossings(const CameraPath& path, const SurfaceHeights& surfaces) {
    size_t crossings = 0;
    for (size_t k = 1; k < path.keys.size(); ++k)
        if (path.keys[k].time - path.keys[k - 1].time >= 0.01 && surfaces.crosses(path.keys[k - 1].position, path.keys[k].position))
            ++crossings;
    return crossings;
}

PathKind parsePathKind(const std::string& text) {
    if (text == "walk") return PathKind::Walk;
    if (text == "drive") return PathKind::Drive;
    if (text == "fly") return PathKind::Fly;
    if (text == "erratic") return PathKind::Erratic;
    if (text == "line") return PathKind::Line;
    if (text == "zigzag") return PathKind::Zigzag;
    throw std::invalid_argument("unknown path kind '" + text + "' (walk, drive, fly, erratic, line or zigzag)");
}

Box3f modelBounds(const Skeleton& skeleton) {
    Box3f b{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (const Node& n : skeleton.nodes) {
        if (n.parent != kNone) continue;
        b.min = {std::min(b.min.x, n.bounds.min.x), std::min(b.min.y, n.bounds.min.y), std::min(b.min.z, n.bounds.min.z)};
        b.max = {std::max(b.max.x, n.bounds.max.x), std::max(b.max.y, n.bounds.max.y), std::max(b.max.z, n.bounds.max.z)};
    }
    return b;
}

double parseUnits(const std::string& text) {
    if (text == "m") return 1;
    if (text == "cm") return 0.01;
    if (text == "mm") return 0.001;
    if (text == "km") return 1000;
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !(v > 0) || !std::isfinite(v))
        throw std::invalid_argument("--units '" + text + "': m, cm, mm, km or a positive number of metres");
    return v;
}

// Speeds and eye height by the scale rule of player/CAMERA_PATH.md.
PathPlan planPath(const Skeleton& skeleton, const PathOptions& o) {
    if (!(o.metresPerUnit > 0)) throw std::invalid_argument("metres per unit must be positive");
    Frame f = frameFor(o.upAxis);
    Box3f b = modelBounds(skeleton);
    PathPlan plan;
    plan.horizontalExtent = std::max(axis(b.max, f.a) - axis(b.min, f.a), axis(b.max, f.b) - axis(b.min, f.b));
    plan.verticalExtent = axis(b.max, f.up) - axis(b.min, f.up);
    const double m = o.metresPerUnit;
    plan.object = plan.horizontalExtent * m < kCityMinExtentM || plan.horizontalExtent < kCityMinFlatness * plan.verticalExtent;
    const double factor = o.kind == PathKind::Drive ? kDriveFactor : 1;
    if (o.speed > 0) {
        plan.speed = o.speed / m;
    } else if (o.kind == PathKind::Fly) {
        plan.speed = 0;  // a lap per 60 s (or --duration)
    } else if (plan.object) {
        double ea = 0.35 * std::max(axis(b.max, f.a) - axis(b.min, f.a), 1e-9);
        double eb = 0.35 * std::max(axis(b.max, f.b) - axis(b.min, f.b), 1e-9);
        Route r{Vector3d::Zero(), unit(f.a) * ea, unit(f.b) * eb, unit(f.up)};
        plan.speed = factor * ArcLength(r).length() / kObjectLapSeconds;
    } else {
        plan.speed = factor * kWalkSpeedMps / m;
    }
    if (o.eyeHeight >= 0) plan.eyeHeight = o.eyeHeight / m;
    else plan.eyeHeight = plan.object ? 0.5 * plan.verticalExtent : kEyeHeightM / m;
    return plan;
}

CameraPath generatePath(const Skeleton& skeleton, const PathOptions& o, const SurfaceHeights* surfaces) {
    if (skeleton.nodes.empty()) throw std::invalid_argument("the database has no nodes");
    if (o.upAxis != 1 && o.upAxis != 2) throw std::invalid_argument("up axis must be y or z");
    if (!(o.keyInterval > 0) || !(o.duration >= 0) || !(o.speed >= 0) || !std::isfinite(o.keyInterval + o.duration + o.speed) ||
        !std::isfinite(o.eyeHeight))
        throw std::invalid_argument("durations, speeds and the eye height must be finite, durations and speeds positive");
    if (o.keyInterval < kMinKeyInterval || (o.duration > 0 && o.duration < kMinKeyInterval))
        throw std::invalid_argument("the key interval and a given duration must be at least " + formatConstant(kMinKeyInterval) + " s");
    const PathPlan plan = planPath(skeleton, o);
    Frame f = frameFor(o.upAxis);
    Box3f b = modelBounds(skeleton);
    Vector3d lo(b.min.x, b.min.y, b.min.z), hi(b.max.x, b.max.y, b.max.z);
    Vector3d center = 0.5 * (lo + hi), up = unit(f.up);
    double extentA = hi[f.a] - lo[f.a], extentB = hi[f.b] - lo[f.b];
    // The route of a city is at least a metre across; an object's follows its own extent.
    double minRoute = plan.object ? 1e-9 : 1.0 / o.metresPerUnit;
    Route route{center, unit(f.a) * 0.35 * std::max(extentA, minRoute), unit(f.b) * 0.35 * std::max(extentB, minRoute), up};
    CameraPath path;

    if (o.kind == PathKind::Fly) {
        double radius = 0.5 * (hi - lo).norm();
        double distance = radius / std::sin(30.0 * M_PI / 180.0);  // whole sphere within a 60-degree view
        double duration = checkedDuration(o.duration > 0 ? o.duration : 60, o.keyInterval);
        for (double t : keyTimes(duration, o.keyInterval)) {
            double angle = 2 * M_PI * t / duration * (plan.speed > 0 ? plan.speed * duration / (2 * M_PI * distance) : 1);
            Vector3d horizontal = std::cos(angle) * unit(f.a) + std::sin(angle) * unit(f.b);
            Vector3d p = center + distance * (std::cos(M_PI / 4) * horizontal + std::sin(M_PI / 4) * up);
            path.keys.push_back(key(t, p, center - p, up));
        }
        return path;
    }

    GroundIndex ground(skeleton, f, lo[f.up]);
    // An object's ground is its bottom. A city's is the lowest surface under the eye, or where
    // there is none (a gap in the scan, a street between block meshes) the model's bottom, as the
    // box estimate's fallback; without surfaces, the box estimate.
    auto groundAt = [&](const Vector3d& p) {
        if (plan.object) return double(lo[f.up]);
        if (!surfaces) return ground.at(p[f.a], p[f.b]);
        const double surface = surfaces->lowest(p[f.a], p[f.b]);
        return std::isnan(surface) ? double(lo[f.up]) : surface;
    };
    std::vector<double> heights;       // ground under each key
    std::vector<size_t> stretches{0};  // first key of each stretch between teleports
    // The eye over each stretch's filtered ground (smoothGround).
    auto settle = [&] {
        stretches.push_back(path.keys.size());
        for (size_t s = 0; s + 1 < stretches.size(); ++s) {
            std::vector<double> times, stretch(heights.begin() + static_cast<std::ptrdiff_t>(stretches[s]),
                                               heights.begin() + static_cast<std::ptrdiff_t>(stretches[s + 1]));
            for (size_t k = stretches[s]; k < stretches[s + 1]; ++k) times.push_back(path.keys[k].time);
            if (!plan.object) smoothGround(times, stretch, kMaxClimbMps / o.metresPerUnit);
            for (size_t k = stretches[s]; k < stretches[s + 1]; ++k)
                path.keys[k].position[f.up] = stretch[k - stretches[s]] + plan.eyeHeight;
        }
        return path;
    };
    if (o.kind == PathKind::Line || o.kind == PathKind::Zigzag) {
        // Waypoints inset 15 % in the bounds: a line from one corner to the opposite one; a zigzag
        // of four legs between the two long sides, so that the view turns sharply three times.
        auto at = [&](double u, double v) {
            return Vector3d(center + unit(f.a) * (u - 0.5) * 0.7 * std::max(extentA, minRoute) +
                            unit(f.b) * (v - 0.5) * 0.7 * std::max(extentB, minRoute));
        };
        std::vector<Vector3d> points = o.kind == PathKind::Line
                                           ? std::vector<Vector3d>{at(0, 0), at(1, 1)}
                                           : std::vector<Vector3d>{at(0, 0), at(0.25, 1), at(0.5, 0), at(0.75, 1), at(1, 0)};
        double length = 0;
        for (size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
        double duration = checkedDuration(o.duration > 0 ? o.duration : length / plan.speed, o.keyInterval);
        for (double t : keyTimes(duration, o.keyInterval)) {
            double s = std::min(t * plan.speed, length);
            size_t leg = 1;
            for (; leg + 1 < points.size() && s > (points[leg] - points[leg - 1]).norm(); ++leg) s -= (points[leg] - points[leg - 1]).norm();
            Vector3d dir = points[leg] - points[leg - 1];
            Vector3d p = points[leg - 1] + dir.normalized() * std::min(s, dir.norm());
            heights.push_back(groundAt(p));
            path.keys.push_back(key(t, p, o.lookAtCenter ? Vector3d(center - p) : dir, up));
        }
        return settle();
    }
    const ArcLength arc(route);
    double duration = checkedDuration(o.duration > 0 ? o.duration : arc.length() / plan.speed, o.keyInterval);
    std::mt19937 rng(o.seed);
    std::uniform_real_distribution<double> gap(2.0, 5.0), angle(0, 2 * M_PI), coin(0, 1);
    double s = 0, direction = 1, nextEvent = gap(rng);  // s: arc length travelled, in this lap's direction
    auto place = [&](double t, double th, double dir) {
        Vector3d p = route.at(th);
        heights.push_back(groundAt(p));
        path.keys.push_back(key(t, p, o.lookAtCenter ? Vector3d(center - p) : Vector3d(dir * route.tangent(th)), up));
    };
    const std::vector<double> times = keyTimes(duration, o.keyInterval);
    for (size_t k = 0; k < times.size(); ++k) {
        const bool last = k + 1 == times.size();
        const double t = times[k], next = last ? t : times[k + 1];
        place(t, arc.t(s), direction);
        if (o.kind == PathKind::Erratic && !last && next > nextEvent) {  // the path ends with its lap
            if (coin(rng) < 0.5) {
                direction = -direction;  // sudden 180-degree turn
            } else {
                s = arc.at(angle(rng));  // teleport: a new stretch, whose eye height starts afresh
                stretches.push_back(path.keys.size());
            }
            place(t + 0.5 * std::min(next - t, 2e-3), arc.t(s), direction);  // just after the key: at most 1 ms, half-way at most
            nextEvent += gap(rng);
        }
        s += direction * plan.speed * (next - t);
    }
    return settle();
}

}  // namespace hlod
