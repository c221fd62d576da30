// The brows' fields (FAPs 31–38, the "eyebrow" group) differ from the other linear FAPs' (rig_lattice.h) in
// what they carry with them: the forehead above.
// - A brow raiser's (31–36) fall-off is measured from its side's brow line (through the inner, middle and outer
//   brow points; from the outer point on, outwards as from a point) rather than from its own point, and the three
//   raisers of a side share it out by a partition of unity across the face (`browShare`): each is 1 at its own
//   point and 0 at its neighbours'. Separate Gaussians about each point overlap instead, so raising the whole
//   brow by v moved it by up to 1.56 v (the middle point got its neighbours' fields as well), and the forehead
//   above had to be squeezed up to 3 cm into the few centimetres below the lattice's top.
// - A raised brow takes the forehead with it, fading linearly up to the lattice's top row (`raiserOffset`).
// - Above the brow the forehead slides over the skull rather than moving straight up (`alongForehead`).
// - The two brows' fields hand over softly at the middle of the forehead and fade out above the eye, so the
//   upper lid is not pulled up with them.
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "face/bezier_volume.h"
#include "face/feature_points.h"
#include "face/rig.h"

namespace th::face::rig {

// Where the brows lie on the neutral face, measured once for all brow FAPs.
struct BrowGeometry {
  // The brow raisers (31–36): each side's inner, middle and outer brow points, in that order (x grows outwards
  // on the left, the face's +x, and shrinks on the right).
  std::array<std::array<Eigen::Vector3d, 3>, 2> lines;
  double innerX = 0.0;    // the nearer inner brow point's (4.1, 4.2) distance from the mid-line
  double eyeLevel = 0.0;  // the pupils' (3.5, 3.6) mean height
  // The highest control points that may move (the row below the lattice's top surface, which must stay).
  double topRow = 0.0;
  Eigen::Matrix3Xd skinNormals;  // per vertex: the neutral skin's outward normal (zero off the skin)
};

BrowGeometry measureBrows(const NeutralFace& neutral, const FeaturePointMap& points, const BezierLattice& lattice);

// One brow raiser: its side's brow line and its own point on it.
struct BrowRaiser {
  std::array<Eigen::Vector3d, 3> line;  // inner, middle and outer brow points of its side
  int index = 0;                        // its own point: 0 inner, 1 middle, 2 outer
  double outwards = 1.0;                // +1 on the left (odd FAPs), where +x is outwards; −1 on the right
  double topRow = 0.0;                  // BrowGeometry::topRow
};

// The raiser of FAP `number`, none for FAPs other than 31–36.
std::optional<BrowRaiser> browRaiser(const BrowGeometry& brows, int number);

// A raiser's share of its side's brow at x across the face: 1 at its own point, 0 at its neighbours'.
double browShare(const BrowRaiser& raiser, double x);

// The brow line's point at x (its ends beyond).
Eigen::Vector3d browLineAt(const BrowRaiser& raiser, double x);

// Where a control point lies from a field's centre, for its fall-off, and how much of the raise it takes
// because of its height (1 but for the forehead above a raised brow).
struct FalloffOffset {
  Eigen::Vector3d d;
  double upwards = 1.0;
};

// A control point's offset from the raiser's brow line, flat above the line, where the raise fades linearly
// with height instead.
FalloffOffset raiserOffset(const BrowRaiser& raiser, const Eigen::Vector3d& controlPoint);

// How softly a brow's field hands over to the other side's at the middle of the forehead, given how softly the
// other FAPs' fields do (`sideWidth`).
double browHandOverWidth(const BrowGeometry& brows, double sideWidth);

// A brow's field's share at height y: 0 from 0.4 IRISD above the pupils down, 1 from the brow's own point
// (at `pointY`) up.
double aboveEyeShare(const BrowGeometry& brows, const NeutralFace& neutral, double pointY, double y);

// The direction a brow FAP moves a vertex: the standard's `direction` at the brow's point (at `pointY`), turning
// into the neutral skin's tangent plane up to one fall-off `radius` above it.
Eigen::Vector3d alongForehead(const BrowGeometry& brows, const NeutralFace& neutral, const Eigen::Vector3d& direction,
                              double pointY, double radius, int vertex);

}  // namespace th::face::rig
