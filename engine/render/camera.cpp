#include "render/camera.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace th::render {
namespace {

float radians(float degrees) {
  return degrees * std::numbers::pi_v<float> / 180.0f;
}

}  // namespace

Eigen::Vector3f OrbitCamera::eye() const {
  const float yaw = radians(yawDegrees);
  const float pitch = radians(pitchDegrees);
  const Eigen::Vector3f offset(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
  return target + distance * offset;
}

Eigen::Matrix4f OrbitCamera::view() const {
  return lookAt(eye(), target, Eigen::Vector3f::UnitY());
}

Eigen::Matrix4f OrbitCamera::projection(float aspect) const {
  return perspective(radians(fovYDegrees), aspect, nearPlane, farPlane);
}

Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up) {
  const Eigen::Vector3f forward = (target - eye).normalized();
  Eigen::Vector3f side = forward.cross(up);
  // Looking straight up or down: any side vector will do, take one that is perpendicular.
  if (side.squaredNorm() < 1e-12f) side = forward.cross(Eigen::Vector3f::UnitZ());
  side.normalize();
  const Eigen::Vector3f trueUp = side.cross(forward);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = side.transpose();
  m.block<1, 3>(1, 0) = trueUp.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m(0, 3) = -side.dot(eye);
  m(1, 3) = -trueUp.dot(eye);
  m(2, 3) = forward.dot(eye);
  return m;
}

Eigen::Matrix4f perspective(float fovYRadians, float aspect, float nearPlane, float farPlane) {
  const float f = 1.0f / std::tan(fovYRadians / 2.0f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
  m(2, 3) = 2.0f * farPlane * nearPlane / (nearPlane - farPlane);
  m(3, 2) = -1.0f;
  return m;
}

OrbitCamera frameHead(const Eigen::Matrix3Xd& positions, double aspect) {
  OrbitCamera camera;
  if (positions.cols() == 0) return camera;
  const Eigen::Vector3d low = positions.rowwise().minCoeff();
  const Eigen::Vector3d high = positions.rowwise().maxCoeff();
  const double width = high.x() - low.x();
  // From just above the crown down to the upper neck: the chin lies about 0.95 head widths (ears included)
  // below the crown, and the margins keep the crown and the neck's cut away from the edges.
  const double top = high.y() + 0.06 * width;
  const double bottom = std::max(low.y(), high.y() - 1.08 * width);
  const double halfHeight = 0.5 * (top - bottom);
  const double halfWidth = 0.5 * 1.15 * width;
  camera.target =
      Eigen::Vector3d(0.5 * (low.x() + high.x()), 0.5 * (top + bottom), 0.5 * (low.z() + high.z())).cast<float>();
  camera.pitchDegrees = 8.0f;
  const double tanHalf = std::tan(radians(camera.fovYDegrees) / 2.0f);
  const double fit = std::max(halfHeight, halfWidth / std::max(aspect, 1e-3));
  // The fit is measured at the target's depth (the head's middle); the face, in front of it, comes out a
  // little larger, which the margins absorb.
  camera.distance = static_cast<float>(fit / tanHalf);
  camera.nearPlane = std::max(0.1f, camera.distance * 0.1f);
  camera.farPlane = camera.distance * 10.0f;
  return camera;
}

}  // namespace th::render
