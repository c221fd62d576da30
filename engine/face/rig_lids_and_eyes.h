// The eyes' part of the rig: eyelids (FAPs 19–22), eyeballs (23–28) and pupils (29, 30). A sphere is fitted to
// each sclera; the ball (sclera and iris) turns rigidly about its centre, and the lids turn about the same
// centre, so a lid slides over the eye instead of cutting into it. Each lid vertex takes a share of its lid's
// angle, 1 along the lid's margin (a parabola through the eye's corners and the lid's middle) and fading out
// above it (the upper lid) or below it (the lower). The pupils' size is the renderer's (FaceModel::pupilScale).
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <array>
#include <utility>
#include <vector>

#include "face/feature_points.h"
#include "face/rig.h"

namespace th::face::rig {

struct EyeRig {
  Eigen::Vector3d centre;
  double radius = 0.0;
  std::vector<int> ball;                                  // vertices that turn with the eyeball
  std::vector<std::pair<int, float>> upperLid, lowerLid;  // vertex, share of the lid's angle
};

// 0 the face's left eye (+x), 1 its right. Throws th::Error if the mesh's eyes lack sclera or iris materials.
std::array<EyeRig, 2> rigEyes(const NeutralFace& neutral, const FeaturePointMap& points);

// The pupil's radius at rest, mesh units.
double pupilRadius(const NeutralFace& neutral);

}  // namespace th::face::rig
