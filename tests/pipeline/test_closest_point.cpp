// The triangle hierarchy of pipeline/closest_point.h: the input index kept per leaf triangle, the
// ray query (hit, miss, nearest hit, facing filter, maxT, empty hierarchy) and, on random
// triangles, both queries against a search of every triangle alone.
#include "pipeline/closest_point.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

using namespace hlod;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Soup {
    std::vector<float> positions;
    std::vector<uint32_t> indices;
    void add(std::initializer_list<float> corners) {  // 9 floats: a, b, c
        const uint32_t base = static_cast<uint32_t>(positions.size() / 3);
        positions.insert(positions.end(), corners);
        indices.insert(indices.end(), {base, base + 1, base + 2});
    }
};

// The unit right triangle in the plane z, normal +z (or -z when flipped).
void addFloor(Soup& s, float z, float x = 0, bool flipped = false) {
    if (flipped) s.add({x, 0, z, x, 1, z, x + 1, 0, z});
    else s.add({x, 0, z, x + 1, 0, z, x, 1, z});
}

const double kDown[3] = {0, 0, -1}, kUp[3] = {0, 0, 1};

}  // namespace

TEST(ClosestPoint, LeafTrianglesKeepTheirInputIndex) {
    Soup s;
    for (int i = 0; i < 40; ++i) {
        addFloor(s, float(i % 7), float(i));
        if (i == 5) s.add({0, 0, 0, 1, 1, 1, 2, 2, 2});  // zero area: input 6, left out
    }
    const TriangleBvh bvh = buildTriangleBvh(s.positions, s.indices);
    ASSERT_EQ(bvh.input.size(), 40u);
    std::vector<uint32_t> seen = bvh.input;
    std::sort(seen.begin(), seen.end());
    for (uint32_t i = 0; i < 40; ++i) EXPECT_EQ(seen[i], i < 6 ? i : i + 1);
    for (uint32_t leaf = 0; leaf < 40; ++leaf)
        for (int k = 0; k < 9; ++k)
            EXPECT_EQ(bvh.triangles[leaf].corners[k], s.positions[3 * s.indices[3 * bvh.input[leaf] + k / 3] + k % 3]);
}

TEST(ClosestPoint, RayHitsAndMisses) {
    Soup s;
    addFloor(s, 0);
    const TriangleBvh bvh = buildTriangleBvh(s.positions, s.indices);
    uint32_t hit = 77;
    const double above[3] = {0.25, 0.25, 2};
    EXPECT_DOUBLE_EQ(firstHit(bvh, above, kDown, kInf, kUp, hit), 2);
    EXPECT_EQ(hit, 0u);
    hit = 77;
    EXPECT_EQ(firstHit(bvh, above, kUp, kInf, kUp, hit), kInf);  // the triangle is behind the ray
    const double beside[3] = {0.75, 0.75, 2};                    // above the plane, outside the triangle
    EXPECT_EQ(firstHit(bvh, beside, kDown, kInf, kUp, hit), kInf);
    const double from[3] = {0.5, -1, 2};  // through (0.5, 0, 0), on the edge y = 0
    const double length = std::sqrt(5.0), direction[3] = {0, 1 / length, -2 / length};
    EXPECT_NEAR(firstHit(bvh, from, direction, kInf, kUp, hit), length, 1e-12);  // an edge counts
    EXPECT_EQ(hit, 0u);
    hit = 77;
    const double onPlane[3] = {-1, 0.25, 0}, along[3] = {1, 0, 0};  // in the triangle's plane: no hit
    EXPECT_EQ(firstHit(bvh, onPlane, along, kInf, kUp, hit), kInf);
    EXPECT_EQ(hit, 77u);
}

TEST(ClosestPoint, RayTakesTheNearestHitAndOnlyFacingTriangles) {
    Soup s;
    for (int z = 0; z < 30; ++z) addFloor(s, float(z), 0, z % 2 == 1);  // odd levels face down
    for (int i = 1; i < 30; ++i) addFloor(s, 0, float(2 * i));          // more triangles: several levels of boxes
    const TriangleBvh bvh = buildTriangleBvh(s.positions, s.indices);
    const double from[3] = {0.25, 0.25, 12.5};
    uint32_t hit = 0;
    EXPECT_DOUBLE_EQ(firstHit(bvh, from, kDown, kInf, kUp, hit), 0.5);  // z = 12, facing up
    EXPECT_EQ(bvh.input[hit], 12u);
    EXPECT_DOUBLE_EQ(firstHit(bvh, from, kDown, kInf, kDown, hit), 1.5);  // z = 11, facing down
    EXPECT_EQ(bvh.input[hit], 11u);
    EXPECT_DOUBLE_EQ(firstHit(bvh, from, kUp, kInf, kDown, hit), 0.5);  // z = 13 above
    EXPECT_EQ(bvh.input[hit], 13u);
    const double sideways[3] = {1, 0, 0};
    EXPECT_EQ(firstHit(bvh, from, kDown, kInf, sideways, hit), kInf);  // no triangle faces +x
}

TEST(ClosestPoint, RayStopsBeforeMaxT) {
    Soup s;
    addFloor(s, 0);
    addFloor(s, -3);
    const TriangleBvh bvh = buildTriangleBvh(s.positions, s.indices);
    const double from[3] = {0.25, 0.25, 2};
    uint32_t hit = 77;
    EXPECT_EQ(firstHit(bvh, from, kDown, 1.5, kUp, hit), kInf);
    EXPECT_EQ(firstHit(bvh, from, kDown, 2, kUp, hit), kInf);  // t < maxT only
    EXPECT_EQ(hit, 77u);
    EXPECT_DOUBLE_EQ(firstHit(bvh, from, kDown, 2.5, kUp, hit), 2);
    EXPECT_EQ(bvh.input[hit], 0u);
}

TEST(ClosestPoint, EmptyHierarchyAnswersNothing) {
    Soup s;
    s.add({0, 0, 0, 1, 0, 0, 2, 0, 0});  // zero area only
    for (const TriangleBvh& bvh : {buildTriangleBvh({}, {}), buildTriangleBvh(s.positions, s.indices)}) {
        EXPECT_TRUE(bvh.empty());
        uint32_t hit = 77;
        const double from[3] = {0.5, 0, 1};
        EXPECT_EQ(firstHit(bvh, from, kDown, kInf, kUp, hit), kInf);
        EXPECT_EQ(squaredDistance(bvh, from, hit), kInf);
        EXPECT_EQ(hit, 77u);
    }
}

// Random triangles: each query of the hierarchy equals the best of the same query against every
// triangle in a hierarchy of its own (so the traversal and its pruning lose nothing, whatever the
// distance query's hint).
TEST(ClosestPoint, QueriesEqualEveryTriangleAlone) {
    std::mt19937 random(14);
    std::uniform_real_distribution<float> coordinate(-10, 10), offset(-1.5f, 1.5f);
    Soup s;
    std::vector<TriangleBvh> alone;
    for (int t = 0; t < 600; ++t) {
        const float cx = coordinate(random), cy = coordinate(random), cz = coordinate(random);
        Soup one;
        one.add({cx + offset(random), cy + offset(random), cz + offset(random), cx + offset(random), cy + offset(random),
                 cz + offset(random), cx + offset(random), cy + offset(random), cz + offset(random)});
        s.positions.insert(s.positions.end(), one.positions.begin(), one.positions.end());
        s.indices.insert(s.indices.end(), {3u * t, 3u * t + 1, 3u * t + 2});
        alone.push_back(buildTriangleBvh(one.positions, one.indices));
    }
    const TriangleBvh bvh = buildTriangleBvh(s.positions, s.indices);
    ASSERT_EQ(bvh.input.size(), 600u);
    std::normal_distribution<double> gaussian;
    int hits = 0;
    for (int q = 0; q < 400; ++q) {
        const double from[3] = {coordinate(random), coordinate(random), coordinate(random)};
        double direction[3] = {gaussian(random), gaussian(random), gaussian(random)};
        const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2]);
        for (double& d : direction) d /= length;
        const double facing[3] = {gaussian(random), gaussian(random), gaussian(random)};
        const double maxT = q % 2 ? kInf : 8.0;
        double bestT = kInf, bestD = kInf;
        for (const TriangleBvh& one : alone) {
            uint32_t ignored = 0;
            bestT = std::min(bestT, firstHit(one, from, direction, maxT, facing, ignored));
            bestD = std::min(bestD, squaredDistance(one, from, ignored));
        }
        uint32_t hit = 0, nearest = q % 3 ? (37 * q) % 600 : UINT32_MAX;  // a hint anywhere (climbing from it), or none
        const double t = firstHit(bvh, from, direction, maxT, facing, hit);
        EXPECT_EQ(t, bestT) << "ray " << q;
        if (t < kInf) {
            ++hits;
            uint32_t ignored = 0;  // the triangle named is the one hit at t
            EXPECT_EQ(firstHit(alone[bvh.input[hit]], from, direction, maxT, facing, ignored), t);
        }
        EXPECT_EQ(squaredDistance(bvh, from, nearest), bestD) << "point " << q;
        uint32_t ignored = 0;
        EXPECT_EQ(squaredDistance(alone[bvh.input[nearest]], from, ignored), bestD);
    }
    EXPECT_GT(hits, 40);  // the rays do meet triangles
}

// `enough`: a search ends at the first triangle within it. Its answer is then that triangle's
// distance, between the exact one and `enough`, and exact when the exact one is larger; the largest
// distance of a point set is exact when larger than `enough`.
TEST(ClosestPoint, EnoughEndsTheSearchWithinItAndLeavesLargerDistancesExact) {
    std::mt19937 random(52);
    std::uniform_real_distribution<float> coordinate(-10, 10), offset(-1.5f, 1.5f);
    Soup s;
    for (int t = 0; t < 600; ++t) {
        const float cx = coordinate(random), cy = coordinate(random), cz = coordinate(random);
        s.add({cx + offset(random), cy + offset(random), cz + offset(random), cx + offset(random), cy + offset(random),
               cz + offset(random), cx + offset(random), cy + offset(random), cz + offset(random)});
    }
    const TriangleBvh bvh = buildTriangleBvh(s.positions, s.indices);
    constexpr double kEnough2 = 0.25;
    int early = 0;
    std::vector<std::array<double, 3>> points;
    for (int q = 0; q < 400; ++q) {
        const double from[3] = {coordinate(random), coordinate(random), coordinate(random)};
        points.push_back({from[0], from[1], from[2]});
        uint32_t exactHint = UINT32_MAX, hint = (37 * q) % 600, ignored = 0;
        const double exact = squaredDistance(bvh, from, exactHint), d = squaredDistance(bvh, from, hint, kEnough2);
        if (exact > kEnough2) {
            EXPECT_EQ(d, exact) << "point " << q;
        } else {
            EXPECT_LE(d, kEnough2) << "point " << q;
            EXPECT_GE(d, exact) << "point " << q;
            early += d != exact;
        }
        Soup one;  // the triangle named is the one at d
        const float* c = bvh.triangles[hint].corners;
        one.add({c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]});
        EXPECT_EQ(squaredDistance(buildTriangleBvh(one.positions, one.indices), from, ignored), d);
    }
    EXPECT_GT(early, 0);  // some searches did end early
    double sum = 0;
    std::vector<std::array<double, 3>> copy = points;
    const double largest = largestDistance(bvh, copy, sum);
    ASSERT_GT(largest, 1.0);
    copy = points;
    EXPECT_EQ(largestDistance(bvh, copy, sum, 0.5 * largest), largest);
    copy = points;
    const double loose = largestDistance(bvh, copy, sum, 2 * largest);  // every search may end early
    EXPECT_GE(loose, largest);  // an early answer is never below the exact one
    EXPECT_LE(loose, 2 * largest);
}
