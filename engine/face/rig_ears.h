// The ears' part of the rig (FAPs 65–68; points 10.1/10.2 the top of each auricle, its highest fully moving
// vertex; 10.3/10.4 its outermost point, the back of the helix's rim): direct per-vertex fields (rig.h), not
// through the skin's lattice, which is too coarse where the auricles lie to move one without the side of the
// head. The side of the head around the ear is fitted as a quadratic height field (trimmed least squares, so the
// ear itself is left out); a vertex's weight grows with how far it stands out of it, 1 on the auricle and 0 on
// the head, so raising or pulling moves the whole auricle, fading into the crease where it joins the head; the
// face and the other ear do not move.
// Thread contract: pure functions.
#pragma once

#include "face/feature_points.h"
#include "face/rig.h"

namespace th::face::rig {

// Sets 10.1–10.4 in `points` and adds the fields of 65–68 to `fields`. Throws th::Error when an ear cannot be
// told apart from the side of the head.
void addEarFields(const NeutralFace& neutral, FeaturePointMap& points, LinearFields& fields);

}  // namespace th::face::rig
