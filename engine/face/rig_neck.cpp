#include "face/rig_neck.h"

namespace th::face::rig {

// The head turns about the top of the spine: level with the jaw's hinge, behind it by a quarter of the eye
// separation; the neck below the chin hands over to the body.
NeckRig rigNeck(const NeutralFace& neutral, const FeaturePointMap& points, const JawHinge& jaw) {
  const Eigen::Matrix3Xd& rest = neutral.rest;
  NeckRig neck;
  neck.pivot = Eigen::Vector3d(0.0, jaw.pivot.y() - 0.15 * neutral.es, jaw.pivot.z() - 0.4 * neutral.es);
  const double bottom = rest.row(1).minCoeff();
  const double chinY = neutral.at(points, "2.1").y();
  neck.headShare.resize(static_cast<std::size_t>(rest.cols()));
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    neck.headShare[static_cast<std::size_t>(v)] =
        static_cast<float>(smoothstep(bottom + 0.2 * (chinY - bottom), chinY - 0.05 * neutral.mns, rest(1, v)));
  return neck;
}

}  // namespace th::face::rig
