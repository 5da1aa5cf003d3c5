// 6-DOF navigation of `hlod view` (thesis Ch. 6: all six degrees of freedom, any speed,
// standing still allowed).
#include "player/gl/gl_renderer.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hlod {
namespace {

TEST(Navigation, NoInputStandsStill) {
    Camera camera;
    camera.position[0] = 1.5;
    camera.orientation[0] = 0.3;
    camera.orientation[3] = std::sqrt(1 - 0.09);
    const Camera before = camera;
    NavigationInput input;
    input.dt = 0.5;
    navigate(camera, input);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(camera.position[i], before.position[i]);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(camera.orientation[i], before.orientation[i]);
}

TEST(Navigation, ForwardIsMinusZAndScalesWithSpeed) {
    Camera camera;
    NavigationInput input;
    input.move[2] = -1;  // forward
    input.speed = 250;   // any speed
    input.dt = 0.1;
    navigate(camera, input);
    EXPECT_NEAR(camera.position[0], 0, 1e-12);
    EXPECT_NEAR(camera.position[2], -25, 1e-9);
}

TEST(Navigation, YawTurnsTheDirectionOfTravel) {
    Camera camera;
    NavigationInput turn;
    turn.yaw = M_PI / 2;  // left
    navigate(camera, turn);
    NavigationInput forward;
    forward.move[2] = -1;
    forward.dt = 1;
    navigate(camera, forward);
    EXPECT_NEAR(camera.position[0], -1, 1e-9);
    EXPECT_NEAR(camera.position[2], 0, 1e-9);
}

TEST(Navigation, RollAndPitchAreFreeAndOrientationStaysUnit) {
    Camera camera;
    NavigationInput input;
    input.pitch = M_PI / 2;  // look straight up: no gimbal limit
    input.roll = 0.7;
    navigate(camera, input);
    NavigationInput up;
    up.move[2] = -1;
    up.dt = 2;
    navigate(camera, up);
    EXPECT_NEAR(camera.position[1], 2, 1e-9);
    double norm = 0;
    for (double q : camera.orientation) norm += q * q;
    EXPECT_NEAR(norm, 1, 1e-12);
}

TEST(Navigation, StrafeAndRiseFollowTheCameraAxes) {
    Camera camera;
    NavigationInput input;
    input.move[0] = 1;
    input.move[1] = 1;
    input.dt = 1;
    navigate(camera, input);
    EXPECT_NEAR(camera.position[0], 1, 1e-12);
    EXPECT_NEAR(camera.position[1], 1, 1e-12);
}

}  // namespace
}  // namespace hlod
