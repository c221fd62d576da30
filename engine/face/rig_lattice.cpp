#include "face/rig_lattice.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "face/fap.h"
#include "face/rig_brows.h"

namespace th::face::rig {
namespace {

// Which part of the mouth a lip FAP belongs to: the upper and lower lip touch at rest, so their fields are
// kept apart by how far the jaw carries a vertex (upper lip ≈ 0.05, lower ≈ 0.9, corners ≈ 0.5).
enum class Lip { kNone, kUpper, kLower, kCorner };
enum class Side { kMiddle, kLeft, kRight };

struct LinearFap {
  int number;
  Lip lip;
  double radius;  // fall-off radius across the face, as a fraction of `unitForRadius`
  Fapu unitForRadius;
};

// The linear FAPs and their fall-off. Radii are fractions of the face's own FAPU distances (×1024), so the
// fields scale with the face: a lip field reaches about a fifth of the mouth's width.
constexpr LinearFap kLinearFaps[] = {
    {4, Lip::kUpper, 0.2, Fapu::kMw},   {5, Lip::kLower, 0.2, Fapu::kMw},   {6, Lip::kCorner, 0.2, Fapu::kMw},
    {7, Lip::kCorner, 0.2, Fapu::kMw},  {8, Lip::kUpper, 0.2, Fapu::kMw},   {9, Lip::kUpper, 0.2, Fapu::kMw},
    {10, Lip::kLower, 0.2, Fapu::kMw},  {11, Lip::kLower, 0.2, Fapu::kMw},  {12, Lip::kCorner, 0.2, Fapu::kMw},
    {13, Lip::kCorner, 0.2, Fapu::kMw}, {16, Lip::kLower, 0.3, Fapu::kMw},  {17, Lip::kUpper, 0.3, Fapu::kMw},
    {18, Lip::kLower, 0.3, Fapu::kMw},  {31, Lip::kNone, 0.25, Fapu::kEs},  {32, Lip::kNone, 0.25, Fapu::kEs},
    {33, Lip::kNone, 0.25, Fapu::kEs},  {34, Lip::kNone, 0.25, Fapu::kEs},  {35, Lip::kNone, 0.25, Fapu::kEs},
    {36, Lip::kNone, 0.25, Fapu::kEs},  {37, Lip::kNone, 0.25, Fapu::kEs},  {38, Lip::kNone, 0.25, Fapu::kEs},
    {39, Lip::kNone, 0.3, Fapu::kEs},   {40, Lip::kNone, 0.3, Fapu::kEs},   {41, Lip::kNone, 0.3, Fapu::kEs},
    {42, Lip::kNone, 0.3, Fapu::kEs},   {51, Lip::kUpper, 0.2, Fapu::kMw},  {52, Lip::kLower, 0.2, Fapu::kMw},
    {53, Lip::kCorner, 0.2, Fapu::kMw}, {54, Lip::kCorner, 0.2, Fapu::kMw}, {55, Lip::kUpper, 0.2, Fapu::kMw},
    {56, Lip::kUpper, 0.2, Fapu::kMw},  {57, Lip::kLower, 0.2, Fapu::kMw},  {58, Lip::kLower, 0.2, Fapu::kMw},
    {59, Lip::kCorner, 0.2, Fapu::kMw}, {60, Lip::kCorner, 0.2, Fapu::kMw}, {61, Lip::kNone, 0.25, Fapu::kEns},
    {62, Lip::kNone, 0.25, Fapu::kEns}, {63, Lip::kNone, 0.25, Fapu::kEns}, {64, Lip::kNone, 0.25, Fapu::kEns},
};

Side sideOf(const FapDefinition& fap) {
  // The standard's names say it: "_l_"/"_lm" on the face's left, "_r_"/"_rm" on its right.
  const std::string_view name = fap.name;
  if (name.find("_l_") != std::string_view::npos || name.ends_with("_l") || name.find("_lm") != std::string_view::npos)
    return Side::kLeft;
  if (name.find("_r_") != std::string_view::npos || name.ends_with("_r") || name.find("_rm") != std::string_view::npos)
    return Side::kRight;
  return Side::kMiddle;
}

// What every lattice field is built with.
struct LatticeRig {
  const NeutralFace& neutral;
  const FeaturePointMap& points;
  const SkinLattice& skin;
  const Eigen::VectorXd& jawFollow;
  const BrowGeometry& brows;
  double sideWidth;  // how softly the left side of the face hands over to the right
  double spacing;    // the lattice's control-point spacing across the face (x and y)
};

// One FAP's field as it is built.
struct LatticeField {
  const LinearFap& linear;
  const FapDefinition& fap;
  Eigen::Vector3d centre;     // its feature point
  Eigen::Vector3d direction;  // the standard's
  double radius;              // of its fall-off across the face
  bool brow;                  // one of the brows' (31–38)
  std::optional<BrowRaiser> raiser;
};

// D_k: a Gaussian fall-off over the control points around the feature point (a little wider in depth, so
// a lip moves front and back together), times the direction. A brow raiser's is measured from its side's brow
// line and fades linearly up the forehead (rig_brows.h).
Eigen::VectorXd controlPointFalloff(const BezierLattice& lattice, const LatticeField& field) {
  const double radius = field.radius;
  const double depthRadius = radius;
  Eigen::VectorXd falloff(lattice.numControlPoints());
  for (Eigen::Index c = 0; c < falloff.size(); ++c) {
    const Eigen::Vector3d controlPoint = lattice.controlPoints().row(c).transpose();
    FalloffOffset offset = field.raiser ? raiserOffset(*field.raiser, controlPoint)
                                        : FalloffOffset{.d = controlPoint - field.centre, .upwards = 1.0};
    Eigen::Vector3d& d = offset.d;
    if (!field.raiser && field.brow && d.y() > 0.0)
      d.y() /= 2.0;  // the squeezers' (37, 38): the skin above a brow follows over a longer distance
    const double g = offset.upwards * std::exp(-(d.x() * d.x() + d.y() * d.y()) / (2 * radius * radius) -
                                               d.z() * d.z() / (2 * depthRadius * depthRadius));
    falloff[c] = g > 1e-4 && !lattice.onBoundary(static_cast<int>(c)) ? g : 0.0;
  }
  return falloff;
}

// The field's motion per unit direction at each embedded vertex, before normalising: B·D_k times the mask that
// keeps it to its own side of the face and its own lip.
std::vector<double> maskedSpread(const LatticeRig& rig, const LatticeField& field) {
  const Embedding& embedding = rig.skin.embedding;
  // B·D_k per unit direction.
  const Eigen::VectorXd spread = embedding.basis * controlPointFalloff(rig.skin.lattice, field);
  const Side side = sideOf(field.fap);
  const double width = field.brow ? browHandOverWidth(rig.brows, rig.sideWidth) : rig.sideWidth;
  const auto mask = [&](int vertex) {
    const Eigen::Vector3d p = rig.neutral.rest.col(vertex);
    double m = 1.0;
    if (side == Side::kLeft) m *= smoothstep(-width, width, p.x());
    if (side == Side::kRight) m *= 1.0 - smoothstep(-width, width, p.x());
    const double carried = rig.jawFollow[vertex];
    if (field.linear.lip == Lip::kUpper) m *= std::clamp((0.7 - carried) / 0.4, 0.0, 1.0);
    if (field.linear.lip == Lip::kLower) m *= std::clamp((carried - 0.3) / 0.4, 0.0, 1.0);
    if (field.brow) m *= aboveEyeShare(rig.brows, rig.neutral, field.centre.y(), p.y());
    if (field.raiser) m *= browShare(*field.raiser, p.x());
    return m;
  };
  std::vector<double> raw(embedding.points.size());
  for (std::size_t i = 0; i < raw.size(); ++i)
    raw[i] = mask(embedding.points[i]) * spread[static_cast<Eigen::Index>(i)];
  return raw;
}

// Normalise on the feature point itself: the mean of its vertices' motion is exactly one FAPU.
double unitScale(const LatticeRig& rig, const LatticeField& field, const std::vector<double>& raw) {
  const std::vector<int>& embedded = rig.skin.embedding.points;
  double atPoint = 0.0;
  const std::vector<int>& pointVertices = rig.points.vertices(field.fap.featurePoint);
  for (int v : pointVertices) {
    const auto found = std::find(embedded.begin(), embedded.end(), v);
    if (found == embedded.end())
      throw Error("face model: feature point " + std::string(field.fap.featurePoint) + " is outside the lattice");
    atPoint += raw[static_cast<std::size_t>(found - embedded.begin())];
  }
  atPoint /= static_cast<double>(pointVertices.size());
  if (!(atPoint > 1e-6))
    throw Error("face model: FAP " + std::to_string(field.fap.number) + "'s field does not reach its feature point");
  return rig.neutral.units.of(field.fap.unit) / atPoint;
}

void addLatticeField(const LatticeRig& rig, const LinearFap& linear, LinearFields& fields) {
  const FapDefinition& fap = fapDefinition(linear.number);
  const double radius = linear.radius * 1024 * rig.neutral.units.of(linear.unitForRadius);
  const LatticeField field{.linear = linear,
                           .fap = fap,
                           .centre = rig.neutral.at(rig.points, fap.featurePoint),
                           .direction = directionOf(fap),
                           .radius = radius,
                           .brow = fap.group == "eyebrow",
                           .raiser = browRaiser(rig.brows, fap.number)};
  // The lattice blends (n + 1)³ control points into each vertex, which widens the Gaussian by about one
  // control-point spacing; 3.5 of the widened radii is where the field has faded (a brow's reaches twice as
  // far upwards, see controlPointFalloff; a raiser's ends sooner, at the lattice's top row, 6–7 cm above the
  // ICT head's brows).
  const double widest = field.brow ? 2.0 * radius : radius;
  fields.reach[static_cast<std::size_t>(fap.number)] = 3.5 * std::hypot(widest, rig.spacing);
  const std::vector<double> raw = maskedSpread(rig, field);
  const double scale = unitScale(rig, field, raw);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const double amount = raw[i] * scale;
    const int vertex = rig.skin.embedding.points[i];
    if (std::abs(amount) > 1e-4 * rig.neutral.units.of(fap.unit)) {
      const Eigen::Vector3d along =
          field.brow ? alongForehead(rig.brows, rig.neutral, field.direction, field.centre.y(), radius, vertex)
                     : field.direction;
      fields.entries[static_cast<std::size_t>(fap.number)].push_back({vertex, (amount * along).cast<float>()});
    }
  }
}

}  // namespace

SkinLattice embedSkin(const NeutralFace& neutral, const BezierLatticeOptions& options) {
  const auto positionsOf = [&](const std::vector<int>& vertices) {
    Eigen::Matrix3Xd positions(3, static_cast<Eigen::Index>(vertices.size()));
    for (std::size_t i = 0; i < vertices.size(); ++i)
      positions.col(static_cast<Eigen::Index>(i)) = neutral.rest.col(vertices[i]);
    return positions;
  };
  SkinLattice skin;
  skin.lattice = BezierLattice::enclosing(positionsOf(neutral.face), 0.1 * neutral.mw, options);
  skin.embedding = skin.lattice.embed(positionsOf(neutral.skin));
  for (int& index : skin.embedding.points) index = neutral.skin[static_cast<std::size_t>(index)];  // mesh vertices
  return skin;
}

void addLatticeFields(const NeutralFace& neutral, const FeaturePointMap& points, const SkinLattice& skin,
                      const Eigen::VectorXd& jawFollow, const BezierLatticeOptions& options, LinearFields& fields) {
  double spacing = 0.0;
  const Eigen::MatrixX3d& controlPoints = skin.lattice.controlPoints();
  const Eigen::Vector3d extent = controlPoints.colwise().maxCoeff() - controlPoints.colwise().minCoeff();
  for (int d = 0; d < 2; ++d)
    spacing = std::max(spacing, extent[d] / (options.degree * options.volumes[static_cast<std::size_t>(d)]));
  const BrowGeometry brows = measureBrows(neutral, points, skin.lattice);
  const LatticeRig rig{.neutral = neutral,
                       .points = points,
                       .skin = skin,
                       .jawFollow = jawFollow,
                       .brows = brows,
                       .sideWidth = 0.1 * neutral.mw,
                       .spacing = spacing};
  for (const LinearFap& linear : kLinearFaps) addLatticeField(rig, linear, fields);
}

}  // namespace th::face::rig
