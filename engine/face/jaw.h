// The jaw as a hinge: its axis and pivot, found from a mesh's jaw-open blend shape by a rigid fit.
//
//   th::face::JawHinge hinge = th::face::fitJawHinge(neutral.positions, jawOpen, lowerTeeth);
//   Eigen::Vector3d chinNow = hinge.rotate(chin, 5.0 * std::numbers::pi / 180);   // 5° open
//
// The lower teeth ride on the mandible, so between the neutral mesh and the jaw-open shape they move
// rigidly: the rotation that best maps them (Kabsch, least squares) gives the hinge's axis and angle, and the
// translation gives a point on the axis, (I − R)·c = t (solved in the plane normal to the axis, then moved
// along it to the teeth's centroid, so the pivot lies level with the jaw). Any slide of the condyle in the shape
// (a translation along the axis) is what the hinge cannot show; `slide` reports it.
// Thread contract: values.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace th::face {

struct JawHinge {
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();  // a point on the axis, mesh units
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit; a positive angle about it opens the jaw
  double shapeAngle = 0.0;                          // radians by which the fitted shape opens it
  double slide = 0.0;                               // |translation along the axis| in the fit, mesh units
  double rmsResidual = 0.0;                         // of the rigid fit over the teeth, mesh units

  Eigen::Vector3d rotate(const Eigen::Vector3d& point, double angle) const {
    return pivot + Eigen::AngleAxisd(angle, axis) * (point - pivot);
  }
};

// `rigidVertices`: vertices that move with the mandible (the lower teeth); at least 3, not collinear, and
// moved by the shape. The fit's angle is positive, so a positive angle about `axis` opens as the shape does.
// Throws th::Error if the shape does not rotate them (angle < 0.5°).
JawHinge fitJawHinge(const Eigen::Matrix3Xd& neutral, const Eigen::Matrix3Xd& open,
                     const std::vector<int>& rigidVertices);

// The vertices of `candidates` that the shape moves by more than `fraction` of the largest move among them:
// of the teeth, the lower set (the upper teeth stay put when the jaw opens).
std::vector<int> movedVertices(const Eigen::Matrix3Xd& neutral, const Eigen::Matrix3Xd& open,
                               const std::vector<int>& candidates, double fraction = 0.25);

}  // namespace th::face

namespace th::face {

// How far each vertex follows the mandible, read from the jaw-open shape: the share of the hinge's rigid
// displacement r that the vertex's displacement d in the shape makes, w = clamp(d·r / r·r, 0, 1). The lower
// teeth get 1, the chin and lower lip about 0.9, the lip corners about 0.5, the upper lip about 0.05, the
// forehead 0. The face's FAP 3 turns every vertex by its share of the hinge rotation, and the map from jaw angle
// to lip FAPs (animation/fap_mapping.h) counts as lip FAPs only what the lips do beyond that, so the two agree.
Eigen::VectorXd jawFollowWeights(const Eigen::Matrix3Xd& neutral, const Eigen::Matrix3Xd& open, const JawHinge& hinge);

}  // namespace th::face
