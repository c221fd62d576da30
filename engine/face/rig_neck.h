// The neck's part of the rig (head turn, FAPs 48–50): the head turns rigidly about a pivot at the top of the
// spine, and the turn is blended into the neck (each vertex's head share), so the base of the neck stays with
// the body.
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "face/feature_points.h"
#include "face/jaw.h"
#include "face/rig.h"

namespace th::face::rig {

struct NeckRig {
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();  // what the head turns about
  std::vector<float> headShare;                     // per vertex, 0..1: how much of the head's turn it follows
};

NeckRig rigNeck(const NeutralFace& neutral, const FeaturePointMap& points, const JawHinge& jaw);

}  // namespace th::face::rig
