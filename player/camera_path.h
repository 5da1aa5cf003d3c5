// Camera paths: the text format of player/CAMERA_PATH.md (time, position, orientation
// quaternion, vertical field of view), sampling between keys, and the generated paths of
// `hlod path` (walk, drive, fly, erratic - Funkhouser & Séquin 1993, viewpoint path C) from a database's bounds.
#pragma once

#include "formats/codec.h"
#include "formats/db.h"
#include "player/renderer.h"

#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace hlod {

// The shortest key interval and generated path, seconds: a path file holds times to the microsecond
// (writeCameraPath), so keys closer than that printed alike and the path was refused when played.
inline constexpr double kMinKeyInterval = 1e-3;

// The narrowest vertical field of view a path may hold, degrees (1e-300 made every projected size,
// and so the benefit, infinite until stop 50; a telescope's is ~0.01).
inline constexpr double kMinVfovDegrees = 1e-3;

struct CameraKey {
    double time = 0;                          // seconds, strictly increasing
    double position[3] = {0, 0, 0};
    double orientation[4] = {0, 0, 0, 1};     // unit quaternion x y z w; looks down -Z, up +Y
    double vfovDegrees = 60;
};

struct CameraPath {
    std::vector<CameraKey> keys;
    double duration() const { return keys.empty() ? 0 : keys.back().time; }
};

// Limits of a camera path (player/CAMERA_PATH.md "Limits"): the reader streams line by line and
// holds at most kMaxCameraKeys keys (72 B each, 72 MB) of lines up to kMaxCameraLine bytes, so a
// hostile file fails at the first line past a limit instead of allocating what it claims.
inline constexpr size_t kMaxCameraKeys = 1'000'000;  // 4.6 hours of keys at 60 Hz
inline constexpr size_t kMaxCameraLine = 1024;       // bytes, comments included
inline constexpr double kMaxCameraTime = 86400;      // time in seconds, 0..this: one day of replay
inline constexpr double kMaxCameraCoordinate = 1e15; // |px|, |py|, |pz|

// Throws InputError "NAME:LINE: problem" (bad header, field count, number, time order,
// quaternion, field of view, a limit exceeded) or "NAME: ..." for an unreadable or empty file.
CameraPath parseCameraPath(std::istream& in, const std::string& name);
CameraPath readCameraPath(const std::string& path);
void writeCameraPath(std::ostream& out, const CameraPath& path);
void writeCameraPathFile(const std::string& path, const CameraPath& cameraPath);  // atomic (TextFileWriter)

// Position and field of view interpolated linearly, orientation by slerp; clamped at the ends.
Camera sampleCameraPath(const CameraPath& path, double time, double aspect = 16.0 / 9.0);

// The share of the path's time from its first key to `until` spent moving faster than `speed`
// (units per second); a cut (two keys 1 ms apart) takes its millisecond.
double shareFasterThan(const CameraPath& path, double speed, double until);

// Clip planes that hold the whole `model` box from the camera, whatever its units: far beyond the
// box's farthest corner; near half the depth the box can have in the view from outside it (its
// distance d x the cosine of the frustum's corner angle), else far / 1e4 (a 24-bit depth buffer
// then tells apart ~far / 1,700 at the far end). Until stop 48 play and compare kept 0.1 and 10,000
// database units: a city in millimetres seen from beyond 10 m, or a 20 cm scan seen from closer
// than 10 cm, drew nothing.
void fitClipPlanes(Camera& camera, const Box3f& model);

// Line and Zigzag: the linear and zigzag camera paths of Hernández & Beneš (Robin Hood, §6
// Fig. 2, Table 2), across the model at walking speed (player/CAMERA_PATH.md).
enum class PathKind { Walk, Drive, Fly, Erratic, Line, Zigzag };
PathKind parsePathKind(const std::string& text);  // throws std::invalid_argument

struct PathOptions {
    PathKind kind = PathKind::Walk;
    double duration = 0;       // seconds; 0: one lap of the route; else at least kMinKeyInterval
    double speed = 0;          // m/s; 0: by kind and scale (planPath)
    double eyeHeight = -1;     // metres above the ground (walk, drive, erratic); < 0: by scale (planPath)
    double metresPerUnit = 1;  // what one database unit is (--units); 1: metres
    double keyInterval = 0.5;  // seconds between keys, at least kMinKeyInterval
    uint32_t seed = 1;         // erratic turns and teleports
    int upAxis = 2;            // 2: Z up (default), 1: Y up
    bool lookAtCenter = false; // walk, drive, erratic: look at the model's centre instead of ahead
                               // (an object scan walked around, rather than a city walked through)
};

// A scene is city-like (a city, a street, a terrain: walked through at metre speeds) when its
// horizontal extent is at least kCityMinExtentM metres and kCityMinFlatness times its height;
// anything else is an object, walked around in kObjectLapSeconds (player/CAMERA_PATH.md).
inline constexpr double kCityMinExtentM = 20, kCityMinFlatness = 4, kObjectLapSeconds = 60;
inline constexpr double kWalkSpeedMps = 1.5, kDriveFactor = 10, kEyeHeightM = 1.7;
// The eye of a city-like walk, drive, erratic, line or zigzag path climbs and sinks at most kMaxClimbMps (a
// brisk stair climb: 2 steps of 17 cm a second), over the ground's median within
// +-kGroundMedianSeconds (player/CAMERA_PATH.md "Eye height"): at most 0.25 m per 0.5 s key.
inline constexpr double kMaxClimbMps = 0.5, kGroundMedianSeconds = 1.0;

// What a generated path will do, in database units.
struct PathPlan {
    bool object = false;           // not city-like: speeds and eye height follow the extent
    double horizontalExtent = 0;   // larger horizontal side of the hlod0 bounds (units)
    double verticalExtent = 0;     // height of the hlod0 bounds (units)
    double speed = 0;              // units per second (walk, drive, erratic; fly: 0 = a lap per 60 s)
    double eyeHeight = 0;          // units above the ground estimate (city) or the model's bottom (object)
};
PathPlan planPath(const Skeleton& skeleton, const PathOptions& options);

// Parses --units: m, cm, mm, km, or a positive number of metres per unit. Throws std::invalid_argument.
double parseUnits(const std::string& text);

// path_ground.cpp: the scanned surfaces under a walk, from decoded triangles (`hlod path` adds a
// cut of the database, player/CAMERA_PATH.md "Eye height"). Queries index the triangles on first
// use (not thread-safe until then).
class SurfaceHeights {
public:
    explicit SurfaceHeights(int upAxis = 2);  // 1: y up, 2: z up
    void add(const MeshData& mesh);
    size_t triangles() const { return triangles_.size(); }
    // Height along the up axis of the lowest surface above or below the horizontal point (x, y)
    // (x along the first horizontal axis: x for z up, z for y up; y along the other); NaN where
    // no triangle is (a hole in the scan, or off the model).
    double lowest(double x, double y) const;
    // Whether the segment from -> to (database frame) passes through a triangle.
    bool crosses(const double from[3], const double to[3]) const;

private:
    struct Triangle {
        float p[3][3];
    };
    int up_, a_, b_;
    std::vector<Triangle> triangles_;
    mutable std::vector<std::vector<uint32_t>> grid_;  // triangles by horizontal cell
    mutable uint32_t cells_ = 1;
    mutable double lo_[2] = {0, 0}, size_[2] = {1, 1};
    void index() const;
    std::pair<uint32_t, uint32_t> cell(double x, double y) const;
};

// The bounds of all hlod0 nodes.
Box3f modelBounds(const Skeleton& skeleton);
// A city-like path (any kind but fly) keeps its eye above the lowest surface under it when
// `surfaces` is given (the model's bottom where there is none), else above the node-box
// estimate (player/CAMERA_PATH.md "Eye height").
CameraPath generatePath(const Skeleton& skeleton, const PathOptions& options, const SurfaceHeights* surfaces = nullptr);
// Key pairs (0.01 s or more apart) whose straight segment passes through a surface: where the
// route goes through a wall (it does not avoid them).
size_t countCrossings(const CameraPath& path, const SurfaceHeights& surfaces);

}  // namespace hlod
