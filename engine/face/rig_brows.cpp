#include "face/rig_brows.h"

#include <cmath>
#include <limits>

#include "face/mesh.h"

namespace th::face::rig {

BrowGeometry measureBrows(const NeutralFace& neutral, const FeaturePointMap& points, const BezierLattice& lattice) {
  const auto at = [&](std::string_view id) { return neutral.at(points, id); };
  BrowGeometry brows;
  brows.lines = {{{at("4.1"), at("4.3"), at("4.5")}, {at("4.2"), at("4.4"), at("4.6")}}};
  brows.innerX = std::min(std::abs(at("4.1").x()), std::abs(at("4.2").x()));
  const Eigen::Vector3d eyeLeft = at("3.5"), eyeRight = at("3.6");
  brows.eyeLevel = 0.5 * (eyeLeft.y() + eyeRight.y());
  brows.topRow = -std::numeric_limits<double>::infinity();
  for (int c = 0; c < lattice.numControlPoints(); ++c)
    if (!lattice.onBoundary(c)) brows.topRow = std::max(brows.topRow, lattice.controlPoints()(c, 1));
  brows.skinNormals = vertexNormals(neutral.mesh, {"M_Face", "M_BackHead"});
  return brows;
}

std::optional<BrowRaiser> browRaiser(const BrowGeometry& brows, int number) {
  if (number < 31 || number > 36) return std::nullopt;
  return BrowRaiser{.line = brows.lines[static_cast<std::size_t>((number - 31) % 2)],
                    .index = (number - 31) / 2,
                    .outwards = number % 2 == 1 ? 1.0 : -1.0,  // left (odd) brows: +x is outwards
                    .topRow = brows.topRow};
}

double browShare(const BrowRaiser& raiser, double x) {
  const std::array<Eigen::Vector3d, 3>& browLine = raiser.line;
  const double outwards = raiser.outwards;
  const double across = outwards * x;
  const double rise1 = smoothstep(outwards * browLine[0].x(), outwards * browLine[1].x(), across);
  const double rise2 = smoothstep(outwards * browLine[1].x(), outwards * browLine[2].x(), across);
  return raiser.index == 0 ? 1.0 - rise1 : raiser.index == 1 ? rise1 * (1.0 - rise2) : rise2;
}

Eigen::Vector3d browLineAt(const BrowRaiser& raiser, double x) {
  const std::array<Eigen::Vector3d, 3>& browLine = raiser.line;
  const double outwards = raiser.outwards;
  const double across = outwards * x;
  if (across <= outwards * browLine[0].x()) return {x, browLine[0].y(), browLine[0].z()};
  if (across >= outwards * browLine[2].x()) return browLine[2];
  const int i = across < outwards * browLine[1].x() ? 0 : 1;
  const double t = (x - browLine[i].x()) / (browLine[i + 1].x() - browLine[i].x());
  Eigen::Vector3d point = (1.0 - t) * browLine[i] + t * browLine[i + 1];
  point.x() = x;
  return point;
}

FalloffOffset raiserOffset(const BrowRaiser& raiser, const Eigen::Vector3d& controlPoint) {
  const Eigen::Vector3d from = browLineAt(raiser, controlPoint.x());
  FalloffOffset offset{.d = controlPoint - from, .upwards = 1.0};
  if (offset.d.y() > 0.0) {
    // A raised brow takes the forehead with it, fading linearly up to the highest control points that may
    // move. Linear: the forehead between the brow and the top takes the raise up evenly, the least
    // squeezing anywhere for a given raise; a Gaussian (as the other FAPs have) would squeeze it most a
    // little way above the brow and then be cut off by the lattice's fixed top, a step in the field's
    // slope where it meets the boundary.
    offset.upwards = std::max(0.0, 1.0 - offset.d.y() / (raiser.topRow - from.y()));
    offset.d.y() = 0.0;
  }
  return offset;
}

double browHandOverWidth(const BrowGeometry& brows, double sideWidth) {
  // Brows hand over more softly at the middle of the forehead: both brows' fields meet there. The hand-over
  // ends at the inner brow points, so that neither brow's field reaches the other's inner point and raising
  // both moves each by just its own value.
  return std::min(3.0 * sideWidth, brows.innerX);
}

double aboveEyeShare(const BrowGeometry& brows, const NeutralFace& neutral, double pointY, double y) {
  // Brows and the forehead, fading out down the skin above the eye so the upper lid (which turns with the
  // eyelid FAPs) is not pulled up with them.
  return smoothstep(brows.eyeLevel + 0.4 * neutral.irisd, pointY, y);
}

Eigen::Vector3d alongForehead(const BrowGeometry& brows, const NeutralFace& neutral, const Eigen::Vector3d& direction,
                              double pointY, double radius, int vertex) {
  // Above the brow the forehead slides over the skull rather than moving straight up: the field's direction
  // turns into the neutral skin's tangent plane there (keeping its length). Straight up, the forehead, which
  // leans back more the higher it is, would be pushed out of its own surface by the upward motion times the
  // normal's upward tilt, and sink back where the field fades under the lattice's top, a soft bulge. The
  // turn starts at the feature point's height (where the skin is nearly vertical and the point must move
  // along the standard's direction) and is complete one fall-off radius higher.
  const Eigen::Vector3d n = brows.skinNormals.col(vertex);
  const double slide = smoothstep(pointY, pointY + radius, neutral.rest(1, vertex));
  const Eigen::Vector3d tangent = direction - slide * direction.dot(n) * n;
  // Unit length, except where the skin faces up (the top of the head, beyond the field's reach): there
  // the tangent's length goes smoothly to zero instead of the direction turning abruptly.
  return tangent / std::max(tangent.norm(), 0.5);
}

}  // namespace th::face::rig
