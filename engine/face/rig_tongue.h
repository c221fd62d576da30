// The tongue's part of the rig (FAPs 43–46 linear, 47 roll; 6.1 the tip, 6.2 the top of its body, 6.3/6.4 its
// left and right borders). ICT draws gums and tongue as one connected surface (M_GumsTongue), so the tongue is
// told apart geometrically, as the part the jaw carries above the fold where its underside meets the floor of
// the mouth. Its fields are direct per-vertex ones (rig.h): the mouth is far inside the skin's lattice, which
// holds only skin. They act before the jaw, so the tongue rides on it.
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "face/feature_points.h"
#include "face/rig.h"

namespace th::face::rig {

// tongue_roll (47): the sides curl up into a U about the mid-line's axis (along z).
struct TongueRoll {
  std::vector<std::pair<int, float>> shares;  // vertex, signed share of the roll angle (+ on the left)
  double axisY = 0.0;                         // height of the mid-line axis the sides roll about
};

// Sets 6.1–6.4 in `points`, adds the fields of 43–46 to `fields` and returns the roll. `jawFollow`: per vertex,
// its share of the jaw's motion. Throws th::Error when the tongue cannot be told apart from the gums.
TongueRoll rigTongue(const NeutralFace& neutral, FeaturePointMap& points, const Eigen::VectorXd& jawFollow,
                     LinearFields& fields);

}  // namespace th::face::rig
