// The jaw's part of the rig (FAPs 3, 14, 15): the hinge fitted to the lower teeth's motion in the jaw-open shape,
// and how far each vertex follows it (jaw.h). A rotation, because a jaw turns: a linear field would stretch the
// teeth. The shares also tell the lips apart for the lip FAPs' fields (rig_lattice.h) and the tongue from the
// gums (rig_tongue.h).
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "face/feature_points.h"
#include "face/jaw.h"
#include "face/rig.h"

namespace th::face::rig {

struct JawRig {
  JawHinge hinge;
  Eigen::VectorXd follow;     // per vertex: its share of the jaw's motion (jawFollowWeights)
  std::vector<int> vertices;  // vertices with a share > 0
  double chinFollow = 1.0;    // the chin point's (2.1) share, by which the thrust and shift are scaled up
};

// `jawOpen`: the jaw-open blend shape (3 x V). Throws th::Error if it does not turn the lower teeth.
JawRig rigJaw(const NeutralFace& neutral, const FeaturePointMap& points, const Eigen::Matrix3Xd& jawOpen);

}  // namespace th::face::rig
