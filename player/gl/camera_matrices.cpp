// Camera matrices (OpenGL conventions, as player/renderer.h's Camera: the camera looks down its
// -Z axis with +Y up; orientation is the camera-to-world rotation). View = inverse of the
// camera's pose, computed in double precision; projection = the usual symmetric frustum.
#include "player/gl/gl_detail.h"

#include <Eigen/Geometry>

#include <cmath>

namespace hlod::gl {
namespace {

Mat4 toMat4(const Eigen::Matrix4d& m) {
    Mat4 out{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) out[static_cast<size_t>(4 * c + r)] = static_cast<float>(m(r, c));
    return out;
}

}  // namespace

Mat4 viewMatrix(const Camera& camera) {
    const Eigen::Quaterniond q(camera.orientation[3], camera.orientation[0], camera.orientation[1], camera.orientation[2]);
    const Eigen::Matrix3d rotation = q.normalized().toRotationMatrix().transpose();
    const Eigen::Vector3d position(camera.position[0], camera.position[1], camera.position[2]);
    Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
    view.topLeftCorner<3, 3>() = rotation;
    view.topRightCorner<3, 1>() = -rotation * position;
    return toMat4(view);
}

Mat4 projectionMatrix(const Camera& camera) {
    const double f = 1.0 / std::tan(camera.vfovDegrees * M_PI / 360.0);
    const double n = camera.nearPlane, far = camera.farPlane;
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    p(0, 0) = f / camera.aspect;
    p(1, 1) = f;
    p(2, 2) = (far + n) / (n - far);
    p(2, 3) = 2 * far * n / (n - far);
    p(3, 2) = -1;
    return toMat4(p);
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 out{};
    Eigen::Map<Eigen::Matrix4f>(out.data()) = Eigen::Map<const Eigen::Matrix4f>(a.data()) * Eigen::Map<const Eigen::Matrix4f>(b.data());
    return out;
}

}  // namespace hlod::gl
