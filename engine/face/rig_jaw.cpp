#include "face/rig_jaw.h"

namespace th::face::rig {

JawRig rigJaw(const NeutralFace& neutral, const FeaturePointMap& points, const Eigen::Matrix3Xd& jawOpen) {
  const Eigen::Matrix3Xd& rest = neutral.rest;
  JawRig jaw;
  const std::vector<int> lowerTeeth = movedVertices(rest, jawOpen, neutral.mesh.verticesOf("M_Teeth"));
  jaw.hinge = fitJawHinge(rest, jawOpen, lowerTeeth);
  jaw.follow = jawFollowWeights(rest, jawOpen, jaw.hinge);
  for (Eigen::Index v = 0; v < jaw.follow.size(); ++v)
    if (jaw.follow[v] > 0.0) jaw.vertices.push_back(static_cast<int>(v));
  double chinShare = 0.0;
  for (int v : points.vertices("2.1")) chinShare += jaw.follow[v];
  jaw.chinFollow = chinShare / static_cast<double>(points.vertices("2.1").size());
  return jaw;
}

}  // namespace th::face::rig
