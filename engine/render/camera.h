// The camera: an orbit around a target (yaw, pitch, distance: what the viewer's mouse drives) with a
// perspective projection, and a default that frames a head seen from the front, slightly above.
//
//   th::render::OrbitCamera camera = th::render::frameHead(mesh.positions, 640.0 / 480.0);
//   camera.yawDegrees = 35;                               // a 3/4 view: the camera moves to the face's left
//   (+x) Eigen::Matrix4f viewProjection = camera.projection(640.0f / 480.0f) * camera.view();
//
// World space is the mesh's: +y up, +z towards the viewer of the neutral face (ICT FaceKit, centimetres).
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>

namespace th::render {

struct OrbitCamera {
  Eigen::Vector3f target = Eigen::Vector3f::Zero();
  float yawDegrees = 0.0f;    // about +y; 0 looks along -z (at the face), positive moves the camera towards +x
  float pitchDegrees = 0.0f;  // positive lifts the camera above the target, looking down
  float distance = 60.0f;     // from the target, in mesh units
  float fovYDegrees = 24.0f;  // vertical field of view; a long lens flatters a face (little perspective bulge)
  float nearPlane = 1.0f;
  float farPlane = 1000.0f;

  Eigen::Vector3f eye() const;
  Eigen::Matrix4f view() const;                    // world -> camera (OpenGL: camera looks along -z, +y up)
  Eigen::Matrix4f projection(float aspect) const;  // camera -> clip, aspect = width / height
};

// Right-handed look-at and perspective, as gluLookAt / gluPerspective (fovY in radians).
Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up);
Eigen::Matrix4f perspective(float fovYRadians, float aspect, float nearPlane, float farPlane);

// A portrait framing of a head whose positions follow the ICT FaceKit conventions: the top of the head and
// the upper neck in view, the face slightly above the centre, seen from 8 degrees above; the distance fits
// both the height and, for narrow images, the width. Uses only the bounding box, so it works for any head of
// that kind.
OrbitCamera frameHead(const Eigen::Matrix3Xd& positions, double aspect);

}  // namespace th::render
