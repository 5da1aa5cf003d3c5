// Camera path format (player/CAMERA_PATH.md): round trip, sampling, one-line errors for each
// class of bad input, and the generated paths' speeds and shapes.
#include "player/camera_path.h"
#include "player/selection.h"
#include "tests/support/trees.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <sstream>

using namespace hlod;

namespace {

std::string parseError(const std::string& text) {
    std::istringstream in(text);
    try {
        parseCameraPath(in, "walk.path");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "no error";
}

double dist(const double a[3], const double b[3]) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

TEST(CameraPath, RoundTripsAndSamples) {
    CameraPath p;
    CameraKey a, b;
    b.time = 2;
    b.position[0] = 10;
    b.orientation[1] = std::sin(M_PI / 4);  // 90 degrees about +Y
    b.orientation[3] = std::cos(M_PI / 4);
    b.vfovDegrees = 40;
    p.keys = {a, b};
    std::stringstream s;
    writeCameraPath(s, p);
    CameraPath q = parseCameraPath(s, "mem");
    ASSERT_EQ(q.keys.size(), 2u);
    EXPECT_NEAR(q.keys[1].orientation[1], b.orientation[1], 1e-9);
    Camera mid = sampleCameraPath(q, 1.0);
    EXPECT_NEAR(mid.position[0], 5, 1e-9);
    EXPECT_NEAR(mid.vfovDegrees, 50, 1e-9);
    EXPECT_NEAR(mid.orientation[1], std::sin(M_PI / 8), 1e-6);  // slerp halfway: 45 degrees
    Camera after = sampleCameraPath(q, 99);
    EXPECT_NEAR(after.position[0], 10, 1e-9);
}

TEST(CameraPath, BadInputGivesOneLineNamingFileAndLine) {
    const std::string h = "hlod-camera-path 1\n";
    EXPECT_EQ(parseError(""), "walk.path: empty file (expected 'hlod-camera-path 1')");
    EXPECT_EQ(parseError("ply\n"), "walk.path:1: not a camera path (expected 'hlod-camera-path 1')");
    EXPECT_EQ(parseError("hlod-camera-path 7\n"), "walk.path:1: unsupported camera path version 7");
    EXPECT_EQ(parseError(h), "walk.path: camera path has no keys");
    EXPECT_EQ(parseError(h + "0 0 0 0 0 0 0 1\n"),
              "walk.path:2: expected 9 fields (time px py pz qx qy qz qw vfov), found 8");
    EXPECT_EQ(parseError(h + "0 0 0 nan 0 0 0 1 60\n"), "walk.path:2: bad pz 'nan' (expected a finite number)");
    EXPECT_EQ(parseError(h + "0 0 0 0 0 0 0 2 60\n").rfind("walk.path:2: orientation quaternion is not unit", 0), 0u);
    EXPECT_EQ(parseError(h + "0 0 0 0 0 0 0 1 180\n"), "walk.path:2: vertical field of view must be in [0.001, 180) degrees");
    // 1e-300 degrees: every projected size, and so the benefit, was infinite (stop 50)
    EXPECT_EQ(parseError(h + "0 0 0 0 0 0 0 1 1e-300\n"), "walk.path:2: vertical field of view must be in [0.001, 180) degrees");
    EXPECT_EQ(parseError(h + "0 0 0 0 0 0 0 1 0.001\n"), "no error");
    EXPECT_EQ(parseError(h + "1 0 0 0 0 0 0 1 60\n# c\n1 0 0 0 0 0 0 1 60\n"), "walk.path:4: times must increase strictly");
    EXPECT_THROW(readCameraPath("/nonexistent/walk.path"), std::runtime_error);
}

// Hostile paths (README "Reliability"): NaN/Inf, zero quaternions, decreasing times, absurd
// values and sizes fail at the first offending line, without reading or holding more.
TEST(CameraPath, HostileInputFailsFastWithOneLine) {
    const std::string h = "hlod-camera-path 1\n";
    EXPECT_EQ(parseError(h + "inf 0 0 0 0 0 0 1 60\n"), "walk.path:2: bad time 'inf' (expected a finite number)");
    EXPECT_EQ(parseError(h + "0 0 0 0 0 0 0 1 -nan\n"), "walk.path:2: bad vfov '-nan' (expected a finite number)");
    EXPECT_EQ(parseError(h + "0 0 0 0 0 0 0 0 60\n"), "walk.path:2: orientation quaternion is not unit length (|q| = 0.000000)");
    EXPECT_EQ(parseError(h + "0 0 0 0 1e300 1e300 0 0 60\n"),
              "walk.path:2: orientation quaternion is not unit length (|q| = inf)");
    EXPECT_EQ(parseError(h + "2 0 0 0 0 0 0 1 60\n1 0 0 0 0 0 0 1 60\n"), "walk.path:3: times must increase strictly");
    EXPECT_EQ(parseError(h + "1e9 0 0 0 0 0 0 1 60\n"), "walk.path:2: time 1e9 s is beyond one day (limit 86400 s)");
    EXPECT_EQ(parseError(h + "-10 0 0 0 0 0 0 1 60\n-5 0 0 0 0 0 0 1 60\n"),  // before: 0 frames replayed, status 0
              "walk.path:2: time -10 s is negative (times are seconds from the start of the path)");
    EXPECT_EQ(parseError(h + "0 0 -1e300 0 0 0 0 1 60\n"), "walk.path:2: py -1e300 is beyond 1e15");
    EXPECT_EQ(parseError(h + std::string(5000, ' ') + "\n"), "walk.path:2: line longer than 1024 bytes");
    EXPECT_EQ(parseError(h + std::string(5u << 20, '#')), "walk.path:2: line longer than 1024 bytes");
    EXPECT_EQ(parseError(h + std::string("0 0 0 0 0 0 0 1 60\0 junk\n", 25)),  // a NUL byte does not end the line
              "walk.path:2: expected 9 fields (time px py pz qx qy qz qw vfov), found 10");
}

// A path of 10^9 keys (a stream that never ends) stops at key 1,000,001 (kMaxCameraKeys):
// bounded time and memory.
TEST(CameraPath, TooManyKeysStopsAtTheLimit) {
    struct Endless : std::streambuf {
        std::string line = "hlod-camera-path 1\n";
        uint64_t keys = 0;
        bool started = false;
        int_type underflow() override {
            if (started) {
                if (keys == 1'000'000'000) return traits_type::eof();
                line = std::to_string(keys++) + "e-2 0 0 0 0 0 0 1 60\n";  // 100 keys per second
            }
            started = true;
            setg(line.data(), line.data(), line.data() + line.size());
            return traits_type::to_int_type(line[0]);
        }
    } endless;
    std::istream in(&endless);
    try {
        parseCameraPath(in, "walk.path");
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "walk.path:1000002: more than 1000000 keys (the limit)");
    }
    EXPECT_EQ(endless.keys, 1'000'001u);
}

TEST(CameraPath, GeneratedWalkAndDriveHaveTheirSpeeds) {
    Skeleton s = test::gridSkeleton(4, 4, 2, 16, 50);
    for (auto [kind, speed] : {std::pair{PathKind::Walk, 1.5}, std::pair{PathKind::Drive, 15.0}}) {
        PathOptions o;
        o.kind = kind;
        CameraPath p = generatePath(s, o);
        ASSERT_GT(p.keys.size(), 10u);
        for (size_t i = 1; i < p.keys.size(); ++i) {
            double v = dist(p.keys[i].position, p.keys[i - 1].position) / (p.keys[i].time - p.keys[i - 1].time);
            EXPECT_NEAR(v, speed, speed * 0.05) << i;
            EXPECT_NEAR(p.keys[i].position[2], 11.7, 1e-6);  // eye height above the boxes' tops (z = 10)
        }
    }
}

// On a narrow model (a 1000 x 20 m street) the keys move at the drive's speed around the whole
// ellipse, never faster (a chord is at most its arc; at the tips, 0.14 m in radius, shorter), and
// the lap ends where it began (until stop 51 the first step jumped 182 m and the lap ended 178 m
// short).
TEST(CameraPath, ANarrowRouteKeepsItsSpeedAndClosesItsLap) {
    Skeleton s = test::gridSkeleton(50, 1, 2, 16, 20);
    PathOptions o;
    o.kind = PathKind::Drive;
    const CameraPath p = generatePath(s, o);
    ASSERT_GT(p.keys.size(), 100u);
    size_t atSpeed = 0;
    for (size_t i = 1; i < p.keys.size(); ++i) {
        const double v = dist(p.keys[i].position, p.keys[i - 1].position) / (p.keys[i].time - p.keys[i - 1].time);
        EXPECT_LE(v, 15 * 1.001) << i;
        atSpeed += v > 15 * 0.95;
    }
    EXPECT_GE(double(atSpeed), 0.9 * double(p.keys.size() - 1));
    for (int k = 0; k < 2; ++k) EXPECT_NEAR(p.keys.back().position[k], p.keys.front().position[k], 1e-6) << k;
}

// --look-at-center: walking around an object, the camera (looking down -Z of its orientation)
// faces the model's centre horizontally at every key; without it, it faces along the route.
TEST(CameraPath, LookAtCenterFacesTheModel) {
    Skeleton s = test::gridSkeleton(4, 4, 2, 16, 50);
    Box3f b = modelBounds(s);
    const Eigen::Vector3d center(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y), 0.5 * (b.min.z + b.max.z));
    for (bool look : {true, false}) {
        PathOptions o;
        o.lookAtCenter = look;
        for (const CameraKey& k : generatePath(s, o).keys) {
            const Eigen::Quaterniond q(k.orientation[3], k.orientation[0], k.orientation[1], k.orientation[2]);
            const Eigen::Vector3d forward = q * Eigen::Vector3d(0, 0, -1);
            Eigen::Vector3d toCenter = center - Eigen::Vector3d(k.position[0], k.position[1], k.position[2]);
            toCenter.z() = 0;
            const double cosine = forward.normalized().dot(toCenter.normalized());
            if (look) EXPECT_GT(cosine, 0.9) << k.time;
            else EXPECT_LT(std::abs(cosine), 0.5) << k.time;  // along the ellipse, across the line to the centre
        }
    }
}

TEST(CameraPath, FlyOverSeesTheWholeModelAndErraticJumps) {
    Skeleton s = test::gridSkeleton(4, 4, 2, 16, 50);
    PathOptions o;
    o.kind = PathKind::Fly;
    CameraPath fly = generatePath(s, o);
    Box3f b = modelBounds(s);
    double center[3] = {0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y), 0.5 * (b.min.z + b.max.z)};
    for (const CameraKey& k : fly.keys) EXPECT_GT(dist(k.position, center), 141.0);  // radius / sin(30 deg)
    o.kind = PathKind::Erratic;
    o.duration = 60;
    CameraPath erratic = generatePath(s, o);
    int jumps = 0;
    for (size_t i = 1; i < erratic.keys.size(); ++i)
        if (erratic.keys[i].time - erratic.keys[i - 1].time < 0.01) ++jumps;
    EXPECT_GE(jumps, 10);  // an event every 2-5 s
    EXPECT_THROW(parsePathKind("swim"), std::invalid_argument);
}

namespace {

// Mean speed of a generated path, in units per second.
double meanSpeed(const CameraPath& p) {
    double length = 0;
    for (size_t i = 1; i < p.keys.size(); ++i) length += dist(p.keys[i].position, p.keys[i - 1].position);
    return length / p.duration();
}

}  // namespace

// player/CAMERA_PATH.md "Scale": an object (a statue in millimetres, a banana in metres) is walked
// around in one lap of 60 s at mid-height, so its speed scales with its extent; a city keeps
// 1.5 m/s and a 1.7 m eye, converted to its units by --units.
TEST(CameraPath, PathSpeedScalesWithExtent) {
    auto object = [](float size) {
        Skeleton s;
        test::addNode(s, kNone, Box3f{{0, 0, 0}, {size, 0.6f * size, 1.7f * size}}, 512);
        test::linkSkeleton(s);
        return s;
    };
    double speedPerSize[2];
    int i = 0;
    for (float size : {0.3f, 1600.0f}) {
        Skeleton s = object(size);
        PathOptions o;
        o.lookAtCenter = true;
        ASSERT_TRUE(planPath(s, o).object) << size;
        CameraPath p = generatePath(s, o);
        EXPECT_NEAR(p.duration(), kObjectLapSeconds, o.keyInterval) << size;
        for (const CameraKey& k : p.keys) EXPECT_NEAR(k.position[2], 0.85 * size, 1e-3 * size);  // mid-height
        speedPerSize[i++] = meanSpeed(p) / size;
        o.kind = PathKind::Drive;  // ten times the walk: a lap in 6 s
        EXPECT_NEAR(generatePath(s, o).duration(), kObjectLapSeconds / kDriveFactor, o.keyInterval) << size;
    }
    EXPECT_NEAR(speedPerSize[0], speedPerSize[1], 0.01 * speedPerSize[0]);
    // A key interval that does not divide the lap still ends it; one longer than the lap gives its
    // two ends (59.5 s and a single still key until stop 50).
    for (double interval : {0.7, 40.0, 1e9}) {
        PathOptions o;
        o.lookAtCenter = true;
        o.keyInterval = interval;
        const CameraPath p = generatePath(object(1), o);
        EXPECT_NEAR(p.duration(), kObjectLapSeconds, 1e-9) << interval;  // the lap's length over its speed
        EXPECT_EQ(p.keys.size(), size_t(std::ceil(kObjectLapSeconds / interval)) + 1) << interval;
        EXPECT_NEAR(p.keys[1].time, std::min(interval, kObjectLapSeconds), 1e-12) << interval;
        o.kind = PathKind::Erratic;  // its turns and teleports add keys, never past the lap (20.001 s of 20)
        o.duration = 20;
        EXPECT_EQ(generatePath(object(1), o).duration(), 20) << interval;
    }
    // Keys closer than a millisecond, or a path shorter, printed alike at the file's microseconds
    // and were refused when played (stop 50): refused when generated.
    PathOptions tight;
    tight.keyInterval = 1e-4;
    EXPECT_THROW(generatePath(object(1), tight), std::invalid_argument);
    tight.keyInterval = 0.5;
    tight.duration = 1e-7;
    EXPECT_THROW(generatePath(object(1), tight), std::invalid_argument);

    Skeleton city = test::gridSkeleton(4, 4, 2, 16, 50);  // 200 x 200 x 10 m
    PathOptions o;
    EXPECT_FALSE(planPath(city, o).object);
    EXPECT_NEAR(meanSpeed(generatePath(city, o)), kWalkSpeedMps, 0.05 * kWalkSpeedMps);
    o.metresPerUnit = 0.001;  // the same numbers read as millimetres: a 20 cm model, an object
    EXPECT_TRUE(planPath(city, o).object);
    Skeleton cityMm = test::gridSkeleton(4, 4, 2, 16, 50000);  // 200 m in millimetres
    PathPlan mm = planPath(cityMm, o);
    EXPECT_FALSE(mm.object);
    EXPECT_NEAR(mm.speed, 1500, 1e-9);
    EXPECT_NEAR(mm.eyeHeight, 1700, 1e-9);
}

TEST(CameraPath, UnitsParse) {
    EXPECT_EQ(parseUnits("m"), 1);
    EXPECT_EQ(parseUnits("mm"), 0.001);
    EXPECT_EQ(parseUnits("cm"), 0.01);
    EXPECT_EQ(parseUnits("0.3048"), 0.3048);
    for (const char* bad : {"", "inch", "-1", "0", "2m", "nan"}) EXPECT_THROW(parseUnits(bad), std::invalid_argument) << bad;
}

namespace {

// A rough scanned ground: 40 x 40 flat patches of 5 m (finest-level boxes 0.3 m thick) whose
// tops are random in [0, 2.6] m, under one 200 x 200 m hlod0 node.
Skeleton roughGround(std::vector<float>& tops) {
    Skeleton s;
    const uint32_t root = test::addNode(s, kNone, Box3f{{0, 0, -0.3f}, {200, 200, 2.6f}}, 512);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> top(0, 2.6f);
    for (int j = 0; j < 40; ++j)
        for (int i = 0; i < 40; ++i) {
            tops.push_back(top(rng));
            test::addNode(s, root, Box3f{{5.0f * i, 5.0f * j, tops.back() - 0.3f}, {5.0f * i + 5, 5.0f * j + 5, tops.back()}}, 64);
        }
    test::linkSkeleton(s);
    return s;
}

}  // namespace

// player/CAMERA_PATH.md "Eye height": over a ground whose estimate jumps by up to 2.6 m from one
// patch to the next, the eye of a walk moves at most kMaxClimbMps x 0.5 s = 0.25 m between keys.
TEST(CameraPath, WalkKeepsASteadyEyeHeightOverRoughGround) {
    std::vector<float> tops;
    const Skeleton s = roughGround(tops);
    for (PathKind kind : {PathKind::Walk, PathKind::Drive, PathKind::Erratic}) {
        PathOptions o;
        o.kind = kind;  // one lap of the route
        const CameraPath p = generatePath(s, o);
        ASSERT_FALSE(planPath(s, o).object);
        double rawJump = 0, eyeJump = 0;
        auto topUnder = [&](const CameraKey& k) {
            const int i = std::clamp(int(k.position[0] / 5), 0, 39), j = std::clamp(int(k.position[1] / 5), 0, 39);
            return double(tops[size_t(j) * 40 + size_t(i)]);
        };
        for (size_t k = 1; k < p.keys.size(); ++k) {
            const double dt = p.keys[k].time - p.keys[k - 1].time;
            if (dt < 0.01) continue;  // an erratic teleport or turn (its extra key 1 ms later)
            ASSERT_LE(dt, o.keyInterval + 1e-9);
            rawJump = std::max(rawJump, std::abs(topUnder(p.keys[k]) - topUnder(p.keys[k - 1])));
            eyeJump = std::max(eyeJump, std::abs(p.keys[k].position[2] - p.keys[k - 1].position[2]) / dt * o.keyInterval);
        }
        EXPECT_GT(rawJump, 2.0);                                      // the ground estimate is rough
        EXPECT_LE(eyeJump, kMaxClimbMps * o.keyInterval + 1e-9);     // the eye is not: <= 0.25 m per 0.5 s
        for (const CameraKey& k : p.keys) {
            EXPECT_GE(k.position[2], kEyeHeightM);  // above the lowest patch
            EXPECT_LE(k.position[2], 2.6 + kEyeHeightM);  // not above the highest
        }
    }
}

namespace {

// Appends the quad a, b, c, d (two triangles) to `m`.
void quad(MeshData& m, std::array<float, 3> a, std::array<float, 3> b, std::array<float, 3> c, std::array<float, 3> d) {
    const uint32_t base = uint32_t(m.vertexCount());
    for (const auto& p : {a, b, c, d}) m.positions.insert(m.positions.end(), p.begin(), p.end());
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// A 30 x 20 x 3 m room: floor, ceiling, four walls, and with `divided` a wall across it at x = 15.
MeshData room(bool divided) {
    MeshData m;
    quad(m, {0, 0, 0}, {30, 0, 0}, {30, 20, 0}, {0, 20, 0});
    quad(m, {0, 0, 3}, {30, 0, 3}, {30, 20, 3}, {0, 20, 3});
    quad(m, {0, 0, 0}, {30, 0, 0}, {30, 0, 3}, {0, 0, 3});
    quad(m, {0, 20, 0}, {30, 20, 0}, {30, 20, 3}, {0, 20, 3});
    quad(m, {0, 0, 0}, {0, 20, 0}, {0, 20, 3}, {0, 0, 3});
    quad(m, {30, 0, 0}, {30, 20, 0}, {30, 20, 3}, {30, 0, 3});
    if (divided) quad(m, {15, 0, 0}, {15, 20, 0}, {15, 20, 3}, {15, 0, 3});
    return m;
}

}  // namespace

// player/CAMERA_PATH.md "Indoors": in a 30 x 20 x 3 m room whose finest nodes are strips from
// floor to ceiling (as the plane cuts leave a room), the walk over the room's surfaces keeps the
// eye 1.7 m above the floor, under the ceiling, inside the walls, and passes through no surface;
// from the node boxes alone the ground estimate is the ceiling (the eye 1.7 m above the roof).
// A wall across the room is walked through, and counted.
TEST(CameraPath, WalkInABoxRoomStaysInside) {
    Skeleton s;
    const uint32_t root = test::addNode(s, kNone, Box3f{{0, 0, 0}, {30, 20, 3}}, 512);
    for (int i = 0; i < 6; ++i) test::addNode(s, root, Box3f{{5.0f * i, 0, 0}, {5.0f * i + 5, 20, 3}}, 64);
    test::linkSkeleton(s);
    SurfaceHeights surfaces;
    surfaces.add(room(false));
    for (PathKind kind : {PathKind::Walk, PathKind::Erratic}) {
        PathOptions o;
        o.kind = kind;
        ASSERT_FALSE(planPath(s, o).object);  // city-like: the ground rule applies
        for (const CameraKey& k : generatePath(s, o).keys) EXPECT_NEAR(k.position[2], 3 + kEyeHeightM, 1e-6);
        const CameraPath p = generatePath(s, o, &surfaces);
        ASSERT_GT(p.keys.size(), 50u);
        for (const CameraKey& k : p.keys) {
            EXPECT_GT(k.position[0], 0.1 * 30);
            EXPECT_LT(k.position[0], 0.9 * 30);
            EXPECT_GT(k.position[1], 0.1 * 20);
            EXPECT_LT(k.position[1], 0.9 * 20);
            EXPECT_NEAR(k.position[2], kEyeHeightM, 1e-5);  // on the floor, under the 3 m ceiling
        }
        EXPECT_EQ(countCrossings(p, surfaces), 0u);
    }
    SurfaceHeights divided;
    divided.add(room(true));
    PathOptions o;
    EXPECT_EQ(countCrossings(generatePath(s, o, &divided), divided), 2u);  // the ellipse crosses x = 15 twice a lap
}

// Over scanned surfaces that step by up to 2.6 m from one 5 m patch to the next (and with holes),
// the eye still moves at most 0.25 m per 0.5 s and stays above the lowest patch.
TEST(CameraPath, WalkOverRoughSurfacesKeepsASteadyEyeHeight) {
    std::vector<float> tops;
    const Skeleton s = roughGround(tops);
    SurfaceHeights surfaces;
    MeshData m;
    for (int j = 0; j < 40; ++j)
        for (int i = 0; i < 40; ++i) {
            if ((i * 7 + j * 3) % 11 == 0) continue;  // a hole in the scan
            const float x = 5.0f * i, y = 5.0f * j, z = tops[size_t(j) * 40 + size_t(i)];
            quad(m, {x, y, z}, {x + 5, y, z}, {x + 5, y + 5, z}, {x, y + 5, z});
        }
    surfaces.add(m);
    PathOptions o;
    const CameraPath p = generatePath(s, o, &surfaces);
    double jump = 0;
    for (size_t k = 1; k < p.keys.size(); ++k) jump = std::max(jump, std::abs(p.keys[k].position[2] - p.keys[k - 1].position[2]));
    EXPECT_LE(jump, kMaxClimbMps * o.keyInterval + 1e-9);
    for (const CameraKey& k : p.keys) {
        EXPECT_GE(k.position[2], -0.3 + kEyeHeightM - 1e-6);  // a hole: the model's bottom (its root box's)
        EXPECT_LE(k.position[2], 2.6 + kEyeHeightM);
    }
    EXPECT_TRUE(std::isnan(surfaces.lowest(-10, -10)));
    EXPECT_NEAR(surfaces.lowest(2.5, 7.5), tops[40], 1e-5);
}

// Robin Hood's path kinds (Table 2): `line` keeps one heading at walking speed; `zigzag` turns
// sharply exactly three times.
TEST(CameraPath, LineAndZigzagHaveStraightLegs) {
    Skeleton s = test::gridSkeleton(4, 4, 2, 16, 50);
    for (PathKind kind : {PathKind::Line, PathKind::Zigzag}) {
        PathOptions o;
        o.kind = kind;
        CameraPath path = generatePath(s, o);
        ASSERT_GT(path.keys.size(), 10u);
        int turns = 0;
        for (size_t i = 1; i < path.keys.size(); ++i) {
            const double* a = path.keys[i - 1].orientation;
            const double* b = path.keys[i].orientation;
            double dot = std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
            turns += dot < 0.99;
            if (dot < 0.99 || i + 1 == path.keys.size()) continue;  // a corner cuts the chord; the end is clamped
            double dx = path.keys[i].position[0] - path.keys[i - 1].position[0];
            double dy = path.keys[i].position[1] - path.keys[i - 1].position[1];
            EXPECT_NEAR(std::hypot(dx, dy) / (path.keys[i].time - path.keys[i - 1].time), 1.5, 1e-6);
        }
        EXPECT_EQ(turns, kind == PathKind::Line ? 0 : 3);
    }
    EXPECT_EQ(parsePathKind("zigzag"), PathKind::Zigzag);
}

// The clip planes hold the whole model whatever its units (play kept 0.1 and 10,000 database
// units until stop 48: a city in millimetres seen from 10.1 m, or a 20 cm scan seen from 19 mm,
// drew nothing): the far plane beyond the farthest corner, the near one within the least depth the
// box can have in the view from outside it, far / 1e4 inside it.
TEST(CameraPath, ClipPlanesHoldTheModelWhateverItsUnits) {
    const double still[3] = {0, 0, 0};
    for (const double scale : {1e-3, 1.0, 1e3, 1e6}) {
        SCOPED_TRACE(scale);
        const Box3f model{{0, 0, 0}, {float(100 * scale), float(100 * scale), float(20 * scale)}};
        Camera camera;  // looks down -Z from above the box's centre, 10 box heights up
        camera.position[0] = camera.position[1] = 50 * scale;
        camera.position[2] = 220 * scale;
        fitClipPlanes(camera, model);
        EXPECT_GT(camera.nearPlane, 50 * scale);  // a fraction of the 200 to the box's top
        EXPECT_LE(camera.nearPlane, 100 * scale);
        EXPECT_GE(camera.farPlane, std::hypot(50, 50, 220) * scale);
        EXPECT_EQ(frustumVis(makeView(camera, still, 0), model), 1.0);
        camera.position[2] = 10 * scale;  // inside the box
        fitClipPlanes(camera, model);
        EXPECT_DOUBLE_EQ(camera.nearPlane, camera.farPlane * 1e-4);
        const Box3f close{{float(49 * scale), float(49 * scale), float(9.99 * scale)}, {float(51 * scale), float(51 * scale), float(9.999 * scale)}};
        EXPECT_EQ(frustumVis(makeView(camera, still, 0), close), 1.0) << "a part 1/1000 of the box's height below the eye";
    }
    // A wide view: a box 5 units aside and 1 ahead (78.7 degrees off the axis, inside a 150-degree
    // view's frustum) is 1 deep, though 5.1 away: half its distance would clip it.
    Camera wide;
    wide.vfovDegrees = 150;
    fitClipPlanes(wide, Box3f{{5, 0, -2}, {6, 1, -1}});
    EXPECT_LT(wide.nearPlane, 1.0);
    EXPECT_GT(wide.nearPlane, 0.0);
    // On a face of the box, and a box of no size: finite planes, near before far.
    for (const Box3f& box : {Box3f{{0, 0, -1}, {1, 1, 0}}, Box3f{{3, 3, 3}, {3, 3, 3}}, Box3f{{0, 0, 0}, {0, 0, 0}}}) {
        Camera on;
        fitClipPlanes(on, box);
        EXPECT_TRUE(std::isfinite(on.nearPlane) && std::isfinite(on.farPlane));
        EXPECT_GT(on.nearPlane, 0.0);
        EXPECT_LT(on.nearPlane, on.farPlane);
    }
}
