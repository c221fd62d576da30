// The feature points the landmarks do not give, placed on the neutral skin from those that they do: 2.10, the
// chin boss (depress_chin, FAP 18, moves it), and the cheeks 5.1–5.4 (puff_cheek and lift_cheek, 39–42). The
// ears' and the tongue's points are placed by those parts (rig_ears.h, rig_tongue.h), which find them.
// Thread contract: pure functions.
#pragma once

#include "face/feature_points.h"
#include "face/rig.h"

namespace th::face::rig {

// Sets 2.10 and 5.1–5.4 in `points`. Throws th::Error when the skin has no vertex where one should be.
void placeDerivedPoints(const NeutralFace& neutral, FeaturePointMap& points);

}  // namespace th::face::rig
