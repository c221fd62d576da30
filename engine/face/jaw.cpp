#include "face/jaw.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace th::face {

JawHinge fitJawHinge(const Eigen::Matrix3Xd& neutral, const Eigen::Matrix3Xd& open,
                     const std::vector<int>& rigidVertices) {
  const auto n = static_cast<Eigen::Index>(rigidVertices.size());
  if (n < 3) throw Error("jaw hinge: fewer than 3 vertices move with the jaw");
  Eigen::Matrix3Xd from(3, n), to(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    from.col(i) = neutral.col(rigidVertices[static_cast<std::size_t>(i)]);
    to.col(i) = open.col(rigidVertices[static_cast<std::size_t>(i)]);
  }
  const Eigen::Vector3d fromCentre = from.rowwise().mean();
  const Eigen::Vector3d toCentre = to.rowwise().mean();
  const Eigen::Matrix3d covariance = (to.colwise() - toCentre) * (from.colwise() - fromCentre).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  // A reflection is never a jaw motion; flip the weakest direction instead (Kabsch's sign fix).
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) correction(2, 2) = -1;
  const Eigen::Matrix3d rotation = svd.matrixU() * correction * svd.matrixV().transpose();
  const Eigen::Vector3d translation = toCentre - rotation * fromCentre;

  const Eigen::AngleAxisd angleAxis(rotation);
  if (angleAxis.angle() < 0.5 * std::numbers::pi / 180.0)
    throw Error("jaw hinge: the jaw-open shape does not rotate the jaw");
  JawHinge hinge;
  hinge.axis = angleAxis.axis();
  hinge.shapeAngle = angleAxis.angle();
  hinge.slide = std::abs(hinge.axis.dot(translation));

  // Points c on the axis satisfy (I − R)c = t − (t·a)a. (I − R) is singular along a, so solve in the plane
  // normal to it with the pseudo-inverse, then slide along a to the level of the teeth.
  const Eigen::Vector3d inPlane = translation - hinge.axis.dot(translation) * hinge.axis;
  const Eigen::Vector3d onAxis =
      (Eigen::Matrix3d::Identity() - rotation).completeOrthogonalDecomposition().solve(inPlane);
  hinge.pivot = onAxis + hinge.axis.dot(fromCentre - onAxis) * hinge.axis;

  double squared = 0.0;
  for (Eigen::Index i = 0; i < n; ++i)
    squared += (hinge.rotate(from.col(i), hinge.shapeAngle) - to.col(i)).squaredNorm();
  hinge.rmsResidual = std::sqrt(squared / static_cast<double>(n));
  return hinge;
}

std::vector<int> movedVertices(const Eigen::Matrix3Xd& neutral, const Eigen::Matrix3Xd& open,
                               const std::vector<int>& candidates, double fraction) {
  double largest = 0.0;
  for (int v : candidates) largest = std::max(largest, (open.col(v) - neutral.col(v)).norm());
  std::vector<int> moved;
  for (int v : candidates)
    if ((open.col(v) - neutral.col(v)).norm() > fraction * largest && largest > 0.0) moved.push_back(v);
  return moved;
}

}  // namespace th::face

namespace th::face {

Eigen::VectorXd jawFollowWeights(const Eigen::Matrix3Xd& neutral, const Eigen::Matrix3Xd& open, const JawHinge& hinge) {
  Eigen::VectorXd weights(neutral.cols());
  for (Eigen::Index v = 0; v < neutral.cols(); ++v) {
    const Eigen::Vector3d rigid = hinge.rotate(neutral.col(v), hinge.shapeAngle) - neutral.col(v);
    const double squared = rigid.squaredNorm();
    // On the axis nothing moves, and nothing can be read from the shape either.
    weights[v] = squared > 1e-18 ? std::clamp((open.col(v) - neutral.col(v)).dot(rigid) / squared, 0.0, 1.0) : 0.0;
  }
  return weights;
}

}  // namespace th::face
