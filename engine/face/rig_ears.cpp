#include "face/rig_ears.h"

#include <Eigen/Dense>
#include <cmath>
#include <utility>
#include <vector>

#include "core/error.h"

namespace th::face::rig {
namespace {

// One ear (auricle) of the head: per-vertex weights (1 on the auricle, fading to 0 where it joins the side of
// the head) and its feature points.
struct Ear {
  std::vector<std::pair<int, double>> weights;  // vertex, share of the ear's motion (> 0)
  int top = -1;                                 // 10.1/10.2: the highest vertex of the auricle
  int outer = -1;  // 10.3/10.4: the auricle's outermost vertex (the back of the helix's rim)
};

// `side` +1 for the face's left (+x), −1 for its right. `low`, `high`: the heights between which the ear is
// looked for (the chin and the brows); `es`: the eye separation (the scale of every distance here).
Ear findEar(const Eigen::Matrix3Xd& rest, const std::vector<int>& skin, double side, double low, double high,
            double es) {
  Ear ear;
  // The outermost skin point between chin and brow height: nothing else on the head's side stands out as far
  // as the auricle (the shoulders, which do, are lower).
  for (int v : skin)
    if (rest(1, v) > low && rest(1, v) < high && (ear.outer < 0 || side * rest(0, v) > side * rest(0, ear.outer)))
      ear.outer = v;
  if (ear.outer < 0 || side * rest(0, ear.outer) <= 0.0) throw Error("face model: no ear on the head's side");
  const Eigen::Vector3d outer = rest.col(ear.outer);
  // The side of the head around it, as a height field across the head (outward distance over y and z): a
  // quadratic fitted to the skin within 0.8 ES of the outer point (on that side, facing out: farther out than
  // 0.6 of the outer point, so the back of the head and the face's front stay out), by trimmed least squares:
  // fit, drop what stands more than 0.05 ES (3 mm) out of the fit (the auricle), refit, until nothing changes.
  std::vector<int> disk;
  for (int v : skin)
    if (side * rest(0, v) > 0.6 * side * outer.x() &&
        std::hypot(rest(1, v) - outer.y(), rest(2, v) - outer.z()) < 0.8 * es)
      disk.push_back(v);
  const auto terms = [&](int v) {
    const double dy = (rest(1, v) - outer.y()) / es, dz = (rest(2, v) - outer.z()) / es;
    return Eigen::Matrix<double, 6, 1>(1.0, dy, dz, dy * dy, dy * dz, dz * dz);
  };
  Eigen::Matrix<double, 6, 1> head = Eigen::Matrix<double, 6, 1>::Zero();
  const auto protrusion = [&](int v) { return side * rest(0, v) - terms(v).dot(head); };
  std::vector<int> kept = disk;
  for (int round = 0; round < 20; ++round) {
    if (kept.size() < 12) throw Error("face model: too little skin around the ear to fit the side of the head");
    Eigen::MatrixXd a(static_cast<Eigen::Index>(kept.size()), 6);
    Eigen::VectorXd b(static_cast<Eigen::Index>(kept.size()));
    for (std::size_t i = 0; i < kept.size(); ++i) {
      a.row(static_cast<Eigen::Index>(i)) = terms(kept[i]).transpose();
      b[static_cast<Eigen::Index>(i)] = side * rest(0, kept[i]);
    }
    head = a.colPivHouseholderQr().solve(b);
    std::vector<int> next;
    for (int v : disk)
      if (protrusion(v) < 0.05 * es) next.push_back(v);
    if (next == kept) break;
    kept = std::move(next);
  }
  // The auricle: what stands out of the head's side. Its weight rises from 0 at 0.02 ES (1.3 mm, the fit's
  // scatter on the head) out to 1 at 0.12 ES (8 mm), so the rim, the helix and the lobe (1–2.4 cm out) move
  // whole and the concha's floor and the crease where the auricle joins the head hand over smoothly; and it
  // fades out beyond 0.45–0.6 ES from the auricle's centre (its size: 5.5 cm tall), so nothing on the side of
  // the head, the face or the neck moves.
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double count = 0.0;
  for (int v : disk)
    if (protrusion(v) > 0.08 * es) centre += Eigen::Vector2d(rest(1, v), rest(2, v)), count += 1.0;
  if (count < 10.0) throw Error("face model: the ear does not stand out of the side of the head");
  centre /= count;
  for (int v : disk) {
    const double across = std::hypot(rest(1, v) - centre.x(), rest(2, v) - centre.y());
    const double w = smoothstep(0.02 * es, 0.12 * es, protrusion(v)) * (1.0 - smoothstep(0.45 * es, 0.6 * es, across));
    if (w <= 1e-6) continue;
    ear.weights.emplace_back(v, w);
    if (w >= 1.0 && (ear.top < 0 || rest(1, v) > rest(1, ear.top))) ear.top = v;
  }
  if (ear.top < 0) throw Error("face model: no vertex of the ear moves with it fully");
  return ear;
}

}  // namespace

// The ICT head's auricles are part of M_Face, so they lie inside the lattice, but in its outermost cells, next
// to its fixed boundary (control points ~0.5 cm apart; the auricle stands 1–1.5 cm off the side of the head): a
// control-point Gaussian cannot move the auricle without the side of the head beside it, the per-vertex mask
// would do all the work. So they are direct per-vertex fields: `findEar` fits the side of the head around the
// ear's outermost point and weighs each vertex by how far it stands out of it (1 on the auricle, 0 on the head),
// so raising or pulling an ear moves the auricle as a whole.
void addEarFields(const NeutralFace& neutral, FeaturePointMap& points, LinearFields& fields) {
  const double low = neutral.at(points, "2.1").y();
  const double high = std::max(neutral.at(points, "4.5").y(), neutral.at(points, "4.6").y());
  for (const bool left : {true, false}) {
    const Ear ear = findEar(neutral.rest, neutral.skin, left ? 1.0 : -1.0, low, high, neutral.es);
    points.set(left ? "10.1" : "10.2", {ear.top});
    points.set(left ? "10.3" : "10.4", {ear.outer});
    addDirectField(neutral, points, left ? 65 : 66, ear.weights, fields);
    addDirectField(neutral, points, left ? 67 : 68, ear.weights, fields);
  }
}

}  // namespace th::face::rig
