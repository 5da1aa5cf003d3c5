// Free 6-DOF navigation for `hlod view` (thesis Ch. 6: "move around in all 6 degrees of freedom
// without any restrictions ... standing still or navigating at arbitrary speeds"). Translation
// and rotation are in the camera's own frame, so there is no up vector to constrain roll.
#include "player/gl/gl_renderer.h"

#include <Eigen/Geometry>

namespace hlod {

void navigate(Camera& camera, const NavigationInput& input) {
    const Eigen::Quaterniond q(camera.orientation[3], camera.orientation[0], camera.orientation[1], camera.orientation[2]);
    const Eigen::Vector3d local(input.move[0], input.move[1], input.move[2]);
    const Eigen::Vector3d step = q.normalized() * local * (input.speed * input.dt);
    for (int i = 0; i < 3; ++i) camera.position[i] += step[i];
    if (input.yaw == 0 && input.pitch == 0 && input.roll == 0) return;
    const Eigen::Quaterniond turn = Eigen::AngleAxisd(input.yaw, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(input.pitch, Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(input.roll, Eigen::Vector3d::UnitZ());
    if (input.yaw == 0 && input.pitch == 0 && input.roll == 0) return;
    const Eigen::Quaterniond turned = (q * turn).normalized();
    camera.orientation[0] = turned.x();
    camera.orientation[1] = turned.y();
    camera.orientation[2] = turned.z();
    camera.orientation[3] = turned.w();
}

}  // namespace hlod
