// Camera path text format (player/CAMERA_PATH.md): parsing with one-line errors, writing,
// and sampling (linear position and field of view, slerp orientation).
#include "player/camera_path.h"

#include "formats/constants.h"
#include "formats/errors.h"
#include "formats/temp_files.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hlod {
namespace {

constexpr const char* kMagic = "hlod-camera-path";

[[noreturn]] void fail(const std::string& name, size_t line, const std::string& what) {
    throw InputError(name + ":" + std::to_string(line) + ": " + what);
}

std::vector<std::string> fields(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> out;
    for (std::string f; in >> f;) out.push_back(f);
    return out;
}

double number(const std::string& text, const std::string& name, size_t line, const char* field) {
    double v = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
        fail(name, line, std::string("bad ") + field + " '" + text + "' (expected a finite number)");
    return v;
}

CameraKey parseKey(const std::vector<std::string>& f, const std::string& name, size_t line) {
    if (f.size() != 9)
        fail(name, line, "expected 9 fields (time px py pz qx qy qz qw vfov), found " + std::to_string(f.size()));
    static const char* names[9] = {"time", "px", "py", "pz", "qx", "qy", "qz", "qw", "vfov"};
    double v[9];
    for (int i = 0; i < 9; ++i) v[i] = number(f[i], name, line, names[i]);
    CameraKey k;
    k.time = v[0];
    if (std::abs(k.time) > kMaxCameraTime) fail(name, line, "time " + f[0] + " s is beyond one day (limit 86400 s)");
    if (k.time < 0) fail(name, line, "time " + f[0] + " s is negative (times are seconds from the start of the path)");
    std::copy(v + 1, v + 4, k.position);
    for (int i = 1; i < 4; ++i)
        if (std::abs(v[i]) > kMaxCameraCoordinate) fail(name, line, std::string(names[i]) + " " + f[i] + " is beyond 1e15");
    double norm = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (!(std::abs(norm - 1) <= 0.01))
        fail(name, line, "orientation quaternion is not unit length (|q| = " + std::to_string(norm) + ")");
    for (int i = 0; i < 4; ++i) k.orientation[i] = v[4 + i] / norm;
    k.vfovDegrees = v[8];
    if (!(k.vfovDegrees >= kMinVfovDegrees && k.vfovDegrees < 180))
        fail(name, line, "vertical field of view must be in [" + formatConstant(kMinVfovDegrees) + ", 180) degrees");
    return k;
}

}  // namespace

CameraPath parseCameraPath(std::istream& in, const std::string& name) {
    CameraPath path;
    bool header = false;
    size_t lineNo = 0;
    char buffer[kMaxCameraLine + 1];
    while (in.getline(buffer, sizeof buffer)) {
        std::string line(buffer, static_cast<size_t>(in.gcount()) - (in.eof() ? 0 : 1));  // without the newline
        ++lineNo;
        if (auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        auto f = fields(line);
        if (f.empty()) continue;
        if (!header) {
            if (f.size() != 2 || f[0] != kMagic) fail(name, lineNo, "not a camera path (expected 'hlod-camera-path 1')");
            if (f[1] != "1") fail(name, lineNo, "unsupported camera path version " + f[1]);
            header = true;
            continue;
        }
        CameraKey k = parseKey(f, name, lineNo);
        if (!path.keys.empty() && !(k.time > path.keys.back().time)) fail(name, lineNo, "times must increase strictly");
        if (path.keys.size() == kMaxCameraKeys) fail(name, lineNo, "more than 1000000 keys (the limit)");
        path.keys.push_back(k);
    }
    if (in.bad()) throw InputError(name + ": read error");
    if (in.fail() && !in.eof()) fail(name, lineNo + 1, "line longer than 1024 bytes");
    if (!header) throw InputError(name + ": empty file (expected 'hlod-camera-path 1')");
    if (path.keys.empty()) throw InputError(name + ": camera path has no keys");
    return path;
}

CameraPath readCameraPath(const std::string& path) {
    std::ifstream in = openTextInput(path, "camera path");
    return parseCameraPath(in, path);
}

void writeCameraPath(std::ostream& out, const CameraPath& path) {
    out << kMagic << " 1\n# time_s px py pz qx qy qz qw vfov_deg\n";
    char buf[512];
    for (const CameraKey& k : path.keys) {
        std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f %.4f\n", k.time, k.position[0],
                      k.position[1], k.position[2], k.orientation[0], k.orientation[1], k.orientation[2],
                      k.orientation[3], k.vfovDegrees);
        out << buf;
    }
}

void writeCameraPathFile(const std::string& path, const CameraPath& cameraPath) {
    TextFileWriter file(path, "camera path");
    writeCameraPath(file.stream(), cameraPath);
    file.commit();
}

Camera sampleCameraPath(const CameraPath& path, double time, double aspect) {
    Camera cam;
    cam.aspect = aspect;
    if (path.keys.empty()) return cam;
    auto after = std::upper_bound(path.keys.begin(), path.keys.end(), time,
                                  [](double t, const CameraKey& k) { return t < k.time; });
    const CameraKey& a = after == path.keys.begin() ? *after : *(after - 1);
    const CameraKey& b = after == path.keys.end() ? a : *after;
    double u = b.time > a.time ? std::clamp((time - a.time) / (b.time - a.time), 0.0, 1.0) : 0.0;
    for (int i = 0; i < 3; ++i) cam.position[i] = a.position[i] + u * (b.position[i] - a.position[i]);
    Eigen::Quaterniond qa(a.orientation[3], a.orientation[0], a.orientation[1], a.orientation[2]);
    Eigen::Quaterniond qb(b.orientation[3], b.orientation[0], b.orientation[1], b.orientation[2]);
    Eigen::Quaterniond q = qa.slerp(u, qb).normalized();
    cam.orientation[0] = q.x();
    cam.orientation[1] = q.y();
    cam.orientation[2] = q.z();
    cam.orientation[3] = q.w();
    cam.vfovDegrees = a.vfovDegrees + u * (b.vfovDegrees - a.vfovDegrees);
    return cam;
}

double shareFasterThan(const CameraPath& path, double speed, double until) {
    double fast = 0, all = 0;
    for (size_t k = 1; k < path.keys.size() && path.keys[k - 1].time < until; ++k) {
        const CameraKey &a = path.keys[k - 1], &b = path.keys[k];
        const double span = std::min(b.time, until) - a.time;
        const double length = std::hypot(b.position[0] - a.position[0], b.position[1] - a.position[1], b.position[2] - a.position[2]);
        all += span;
        if (b.time > a.time && length > speed * (b.time - a.time)) fast += span;
    }
    return all > 0 ? fast / all : 0;
}

void fitClipPlanes(Camera& camera, const Box3f& model) {
    const float lo[3] = {model.min.x, model.min.y, model.min.z}, hi[3] = {model.max.x, model.max.y, model.max.z};
    double far2 = 0, outside2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double e = camera.position[i], farthest = std::max(std::abs(e - lo[i]), std::abs(e - hi[i]));
        const double outside = e < lo[i] ? lo[i] - e : e > hi[i] ? e - hi[i] : 0;
        far2 += farthest * farthest, outside2 += outside * outside;
    }
    camera.farPlane = std::max(1.01 * std::sqrt(far2), 1e-6);
    // A point of the box at distance >= d seen at angle t off the axis is t's cosine x d deep; t is
    // at most the frustum's corner angle.
    const double corner = std::tan(camera.vfovDegrees * M_PI / 360.0) * std::hypot(1.0, camera.aspect);
    const double depth = std::sqrt(outside2) / std::hypot(1.0, corner);  // d x cos(corner angle)
    camera.nearPlane = std::max(0.5 * depth, camera.farPlane * 1e-4);
}

}  // namespace hlod
