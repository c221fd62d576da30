#include "face/face_model.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.h"
#include "face/fap.h"

namespace th::face {
namespace {

double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

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

Eigen::Vector3d directionOf(const FapDefinition& fap) { return {fap.direction[0], fap.direction[1], fap.direction[2]}; }

// Least-squares sphere through points (algebraic fit: |p|² = 2c·p + (r² − |c|²) is linear in c and r² − |c|²).
std::pair<Eigen::Vector3d, double> fitSphere(const Eigen::Matrix3Xd& positions, const std::vector<int>& vertices) {
  Eigen::MatrixXd a(static_cast<Eigen::Index>(vertices.size()), 4);
  Eigen::VectorXd b(static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3d p = positions.col(vertices[i]);
    a.row(static_cast<Eigen::Index>(i)) << 2 * p.x(), 2 * p.y(), 2 * p.z(), 1.0;
    b[static_cast<Eigen::Index>(i)] = p.squaredNorm();
  }
  const Eigen::Vector4d solution = a.colPivHouseholderQr().solve(b);
  const Eigen::Vector3d centre = solution.head<3>();
  return {centre, std::sqrt(solution[3] + centre.squaredNorm())};
}

// The skin vertex nearest to (x, y) seen from the front: the front-most among those close in x and y.
int frontVertexNear(const Eigen::Matrix3Xd& positions, const std::vector<int>& skin, double x, double y, double tolerance) {
  int best = -1;
  double bestScore = std::numeric_limits<double>::infinity();
  for (int v : skin) {
    const double distance = std::hypot(positions(0, v) - x, positions(1, v) - y);
    if (distance > tolerance) continue;
    const double score = distance - 0.01 * positions(2, v);  // prefer the front surface among near ones
    if (score < bestScore) bestScore = score, best = v;
  }
  if (best < 0) throw Error("face model: no skin vertex near a feature point the standard needs");
  return best;
}

// Neighbours of each vertex over the triangles drawn with one material.
std::vector<std::vector<int>> neighboursIn(const Mesh& mesh, std::string_view material) {
  const int wanted = mesh.materialIndex(material);
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(mesh.numVertices()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.triangleMaterial[t] != wanted) continue;
    const auto& tri = mesh.triangles[t];
    for (std::size_t i = 0; i < 3; ++i) {
      const int a = tri[i], b = tri[(i + 1) % 3];
      neighbours[static_cast<std::size_t>(a)].push_back(b);
      neighbours[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  return neighbours;
}

// One ear (auricle) of the head: per-vertex weights (1 on the auricle, fading to 0 where it joins the side of
// the head) and its feature points. See FaceModel::build for how it is found.
struct Ear {
  std::vector<std::pair<int, double>> weights;  // vertex, share of the ear's motion (> 0)
  int top = -1;     // 10.1/10.2: the highest vertex of the auricle
  int outer = -1;   // 10.3/10.4: the auricle's outermost vertex (the back of the helix's rim)
};

// `side` +1 for the face's left (+x), −1 for its right. `low`, `high`: the heights between which the ear is
// looked for (the chin and the brows); `es`: the eye separation (the scale of every distance here).
Ear findEar(const Eigen::Matrix3Xd& rest, const std::vector<int>& skin, double side, double low, double high, double es) {
  Ear ear;
  // The outermost skin point between chin and brow height: nothing else on the head's side stands out as far
  // as the auricle (the shoulders, which do, are lower).
  for (int v : skin)
    if (rest(1, v) > low && rest(1, v) < high && (ear.outer < 0 || side * rest(0, v) > side * rest(0, ear.outer))) ear.outer = v;
  if (ear.outer < 0 || side * rest(0, ear.outer) <= 0.0) throw Error("face model: no ear on the head's side");
  const Eigen::Vector3d outer = rest.col(ear.outer);
  // The side of the head around it, as a height field across the head (outward distance over y and z): a
  // quadratic fitted to the skin within 0.8 ES of the outer point (on that side, facing out: farther out than
  // 0.6 of the outer point, so the back of the head and the face's front stay out), by trimmed least squares:
  // fit, drop what stands more than 0.05 ES (3 mm) out of the fit (the auricle), refit, until nothing changes.
  std::vector<int> disk;
  for (int v : skin)
    if (side * rest(0, v) > 0.6 * side * outer.x() && std::hypot(rest(1, v) - outer.y(), rest(2, v) - outer.z()) < 0.8 * es)
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
  // whole and the concha's floor and the crease where the auricle joins the head hand over smoothly; and it fades out beyond 0.45–0.6 ES from the auricle's centre
  // (its size: 5.5 cm tall), so nothing on the side of the head, the face or the neck moves.
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

// The tongue, told apart from the gums it shares M_GumsTongue with (see FaceModel::build).
struct TongueBody {
  std::vector<int> vertices;
  double level = 0.0;      // the height above which it is told apart from the floor of the mouth
  double back = 0.0;       // z where it leaves the part of the mouth the jaw carries (its root)
  int tip = -1, top = -1, leftBorder = -1, rightBorder = -1;  // 6.1, 6.2, 6.3, 6.4
};

TongueBody findTongue(const Mesh& mesh, const Eigen::VectorXd& jawFollow, double mw, double mns) {
  const Eigen::Matrix3Xd& rest = mesh.positions;
  const std::vector<int> mouth = mesh.verticesOf("M_GumsTongue");
  if (mouth.empty()) throw Error("face model: the mesh has no M_GumsTongue material");
  const std::vector<std::vector<int>> neighbours = neighboursIn(mesh, "M_GumsTongue");
  const auto carried = [&](int v) { return jawFollow[v] > 0.5; };
  const double midline = 0.02 * mw;  // 1 mm: the mesh is mirrored, its mid-line vertices have x = 0
  TongueBody tongue;
  // The top of the tongue: the highest mid-line vertex that the jaw carries (above it are only the palate and
  // the upper gums, which stay with the skull).
  for (int v : mouth)
    if (carried(v) && std::abs(rest(0, v)) < midline && (tongue.top < 0 || rest(1, v) > rest(1, tongue.top))) tongue.top = v;
  if (tongue.top < 0) throw Error("face model: no part of M_GumsTongue moves with the jaw");
  // The lower gums' front: the front-most vertex the jaw carries (in front of the tongue's tip, between the
  // lower lip and the roots of the lower incisors). The tongue's sides rest against the lower teeth, so nearness
  // to the teeth does not tell tongue from gum; being connected to this point above the fold does.
  int gumFront = -1;
  for (int v : mouth)
    if (carried(v) && (gumFront < 0 || rest(2, v) > rest(2, gumFront))) gumFront = v;
  // Grow from the top over carried vertices no lower than a level; lower the level step by step as long as
  // the region does not reach the gums. It stops where the tongue's underside folds into the floor of the
  // mouth, through which the gums would be reached.
  const auto grow = [&](double level, bool& touchesGums) {
    std::vector<char> in(static_cast<std::size_t>(rest.cols()), 0);
    std::vector<int> region{tongue.top}, stack{tongue.top};
    in[static_cast<std::size_t>(tongue.top)] = 1;
    touchesGums = false;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int n : neighbours[static_cast<std::size_t>(v)]) {
        if (in[static_cast<std::size_t>(n)] || !carried(n) || rest(1, n) < level) continue;
        in[static_cast<std::size_t>(n)] = 1;
        if (n == gumFront) touchesGums = true;
        region.push_back(n);
        stack.push_back(n);
      }
    }
    return region;
  };
  const double step = 0.01 * mns;
  for (double level = rest(1, tongue.top) - step; level > rest(1, tongue.top) - mns; level -= step) {
    bool touchesGums = false;
    std::vector<int> region = grow(level, touchesGums);
    if (touchesGums) break;
    tongue.vertices = std::move(region);
    tongue.level = level;
  }
  if (tongue.vertices.size() < 20) throw Error("face model: the tongue cannot be told apart from the gums");
  // Its root: the front-most of its vertices that border on mouth the jaw does not carry (the throat).
  tongue.back = std::numeric_limits<double>::infinity();
  for (int v : tongue.vertices) tongue.back = std::min(tongue.back, rest(2, v));
  for (int v : tongue.vertices)
    for (int n : neighbours[static_cast<std::size_t>(v)])
      if (!carried(n)) tongue.back = std::max(tongue.back, rest(2, v));
  for (int v : tongue.vertices) {
    if (std::abs(rest(0, v)) < midline && (tongue.tip < 0 || rest(2, v) > rest(2, tongue.tip))) tongue.tip = v;
    if (tongue.leftBorder < 0 || rest(0, v) > rest(0, tongue.leftBorder)) tongue.leftBorder = v;
    if (tongue.rightBorder < 0 || rest(0, v) < rest(0, tongue.rightBorder)) tongue.rightBorder = v;
  }
  return tongue;
}

}  // namespace

Eigen::Matrix3d headRotation(double pitch, double yaw, double roll) {
  // As the head model's angles: R = Ry(yaw)·Rx(pitch)·Rz(roll); FAP 48 positive pitches down about +x, 49 yaws
  // to the face's left about +y, 50 rolls to its right about +z (face/fap.cpp).
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

FaceModel FaceModel::buildDefault() { return build(loadIctFace(ictFaceDirectory())); }

FaceModel FaceModel::build(const FaceAssets& assets, const FaceModelOptions& options) {
  FaceModel model;
  model.mesh_ = assets.neutral;
  model.points_ = assets.points;
  model.landmarks_ = assets.landmarks;
  const Eigen::Matrix3Xd& rest = model.mesh_.positions;
  model.units_ = measureFapUnits(model.points_, rest);
  const FapUnits& u = model.units_;
  const double mw = u.mw * 1024, mns = u.mns * 1024, es = u.es * 1024, irisd = u.irisd * 1024;
  const std::vector<int> face = model.mesh_.verticesOf("M_Face");
  if (face.empty()) throw Error("face model: the mesh has no M_Face material (the skin)");
  // All the skin: the face and the rest of the head (which meets it at the temples, forehead and neck).
  std::vector<int> skin = face;
  for (int v : model.mesh_.verticesOf("M_BackHead")) skin.push_back(v);
  std::sort(skin.begin(), skin.end());
  skin.erase(std::unique(skin.begin(), skin.end()), skin.end());

  // Feature points the landmarks do not give, placed from those that they do.
  const auto at = [&](std::string_view id) { return model.points_.position(rest, id); };
  {
    const Eigen::Vector3d lowerLip = at("8.2"), chin = at("2.1");
    int boss = -1;  // 2.10, the chin boss: the front-most midline point between the lower lip and the chin
    for (int v : skin)
      if (std::abs(rest(0, v)) < 0.03 * mw && rest(1, v) < lowerLip.y() && rest(1, v) > chin.y() &&
          (boss < 0 || rest(2, v) > rest(2, boss)))
        boss = v;
    if (boss < 0) throw Error("face model: no chin between the lower lip and the chin point");
    model.points_.set("2.10", {boss});
    for (const auto& [side, eyeCorner, mouthCorner] :
         {std::tuple{"l", "3.7", "8.3"}, std::tuple{"r", "3.8", "8.4"}}) {
      const Eigen::Vector3d eye = at(eyeCorner), mouth = at(mouthCorner);
      const bool left = std::string_view(side) == "l";
      // 5.3/5.4: the cheekbone, below the eye's outer corner; 5.1/5.2: the cheek beside the mouth corner.
      model.points_.set(left ? "5.3" : "5.4",
                        {frontVertexNear(rest, skin, 0.9 * eye.x(), eye.y() - 0.35 * (eye.y() - mouth.y()), 0.1 * mw)});
      model.points_.set(left ? "5.1" : "5.2",
                        {frontVertexNear(rest, skin, eye.x(), mouth.y() + 0.2 * (eye.y() - mouth.y()), 0.1 * mw)});
    }
  }

  // The jaw.
  const std::vector<int> lowerTeeth = movedVertices(rest, assets.jawOpen, model.mesh_.verticesOf("M_Teeth"));
  model.jaw_ = fitJawHinge(rest, assets.jawOpen, lowerTeeth);
  model.jawFollow_ = jawFollowWeights(rest, assets.jawOpen, model.jaw_);
  for (Eigen::Index v = 0; v < model.jawFollow_.size(); ++v)
    if (model.jawFollow_[v] > 0.0) model.jawVertices_.push_back(static_cast<int>(v));
  double chinShare = 0.0;
  for (int v : model.points_.vertices("2.1")) chinShare += model.jawFollow_[v];
  model.chinFollow_ = chinShare / static_cast<double>(model.points_.vertices("2.1").size());

  // The Bézier lattice around the face, and the linear FAP fields through it. All skin inside the lattice is
  // embedded; the fields vanish on the lattice's surface, so skin outside it (the back of the head) meets the
  // moving skin inside without a crack.
  const auto positionsOf = [&](const std::vector<int>& vertices) {
    Eigen::Matrix3Xd positions(3, static_cast<Eigen::Index>(vertices.size()));
    for (std::size_t i = 0; i < vertices.size(); ++i) positions.col(static_cast<Eigen::Index>(i)) = rest.col(vertices[i]);
    return positions;
  };
  model.lattice_ = BezierLattice::enclosing(positionsOf(face), 0.1 * mw, options.lattice);
  model.embedding_ = model.lattice_.embed(positionsOf(skin));
  for (int& index : model.embedding_.points) index = skin[static_cast<std::size_t>(index)];  // mesh vertex numbers
  const Eigen::Vector3d eyeLeft = at("3.5"), eyeRight = at("3.6");
  const double eyeLevel = 0.5 * (eyeLeft.y() + eyeRight.y());
  const double sideWidth = 0.1 * mw;  // how softly the left side of the face hands over to the right
  double spacing = 0.0;  // the lattice's control-point spacing across the face (x and y)
  {
    const Eigen::Vector3d extent = model.lattice_.controlPoints().colwise().maxCoeff() - model.lattice_.controlPoints().colwise().minCoeff();
    for (int d = 0; d < 2; ++d)
      spacing = std::max(spacing, extent[d] / (options.lattice.degree * options.lattice.volumes[static_cast<std::size_t>(d)]));
  }
  const Eigen::Matrix3Xd skinNormals = vertexNormals(model.mesh_, {"M_Face", "M_BackHead"});
  // The brow raisers (31–36): each side's inner, middle and outer brow points, in that order (x grows outwards
  // on the left, the face's +x, and shrinks on the right).
  const std::array<std::array<Eigen::Vector3d, 3>, 2> browLines{{{at("4.1"), at("4.3"), at("4.5")}, {at("4.2"), at("4.4"), at("4.6")}}};
  const double innerBrowX = std::min(std::abs(at("4.1").x()), std::abs(at("4.2").x()));
  // The highest control points that may move (the row below the lattice's top surface, which must stay).
  double topRow = -std::numeric_limits<double>::infinity();
  for (int c = 0; c < model.lattice_.numControlPoints(); ++c)
    if (!model.lattice_.onBoundary(c)) topRow = std::max(topRow, model.lattice_.controlPoints()(c, 1));
  for (const LinearFap& linear : kLinearFaps) {
    const FapDefinition& fap = fapDefinition(linear.number);
    const Eigen::Vector3d centre = at(fap.featurePoint);
    const Eigen::Vector3d direction = directionOf(fap);
    const double radius = linear.radius * 1024 * u.of(linear.unitForRadius);
    const double depthRadius = radius;
    // The lattice blends (n + 1)³ control points into each vertex, which widens the Gaussian by about one
    // control-point spacing; 3.5 of the widened radii is where the field has faded (a brow's reaches twice as
    // far upwards, see below; a raiser's ends sooner, at the lattice's top row, 6–7 cm above the ICT head's brows).
    const double widest = fap.group == "eyebrow" ? 2.0 * radius : radius;
    model.reach_[static_cast<std::size_t>(fap.number)] = 3.5 * std::hypot(widest, spacing);
    // D_k: a Gaussian fall-off over the control points around the feature point (a little wider in depth, so
    // a lip moves front and back together), times the direction.
    //
    // A brow raiser's fall-off is measured from its side's brow line (through the inner, middle and outer brow
    // points; from the outer point on, outwards as from a point) rather than from its own point, and the three
    // raisers of a side share it out by a partition of unity across the face (`browShare`): each is 1 at its
    // own point and 0 at its neighbours'. Separate Gaussians about each point overlap instead, so raising the
    // whole brow by v moved it by up to 1.56 v (the middle point got its neighbours' fields as well), and
    // the forehead above had to be squeezed up to 3 cm into the few centimetres below the lattice's top.
    const bool raiser = fap.number >= 31 && fap.number <= 36;
    const std::array<Eigen::Vector3d, 3>& browLine = browLines[raiser ? static_cast<std::size_t>((fap.number - 31) % 2) : 0];
    const int browIndex = raiser ? (fap.number - 31) / 2 : 0;  // 0 inner, 1 middle, 2 outer
    const double outwards = fap.number % 2 == 1 ? 1.0 : -1.0;  // left (odd) brows: +x is outwards
    const auto browShare = [&](double x) {
      const double across = outwards * x;
      const double rise1 = smoothstep(outwards * browLine[0].x(), outwards * browLine[1].x(), across);
      const double rise2 = smoothstep(outwards * browLine[1].x(), outwards * browLine[2].x(), across);
      return browIndex == 0 ? 1.0 - rise1 : browIndex == 1 ? rise1 * (1.0 - rise2) : rise2;
    };
    const auto browLineAt = [&](double x) -> Eigen::Vector3d {  // the brow line's point at x (its ends beyond)
      const double across = outwards * x;
      if (across <= outwards * browLine[0].x()) return {x, browLine[0].y(), browLine[0].z()};
      if (across >= outwards * browLine[2].x()) return browLine[2];
      const int i = across < outwards * browLine[1].x() ? 0 : 1;
      const double t = (x - browLine[i].x()) / (browLine[i + 1].x() - browLine[i].x());
      Eigen::Vector3d point = (1.0 - t) * browLine[i] + t * browLine[i + 1];
      point.x() = x;
      return point;
    };
    Eigen::VectorXd falloff(model.lattice_.numControlPoints());
    for (Eigen::Index c = 0; c < falloff.size(); ++c) {
      const Eigen::Vector3d controlPoint = model.lattice_.controlPoints().row(c).transpose();
      const Eigen::Vector3d from = raiser ? browLineAt(controlPoint.x()) : centre;
      Eigen::Vector3d d = controlPoint - from;
      double upwards = 1.0;
      if (raiser && d.y() > 0.0) {
        // A raised brow takes the forehead with it, fading linearly up to the highest control points that may
        // move. Linear: the forehead between the brow and the top takes the raise up evenly, the least
        // squeezing anywhere for a given raise; a Gaussian (as the other FAPs have) would squeeze it most a
        // little way above the brow and then be cut off by the lattice's fixed top, a step in the field's
        // slope where it meets the boundary.
        upwards = std::max(0.0, 1.0 - d.y() / (topRow - from.y()));
        d.y() = 0.0;
      } else if (fap.group == "eyebrow" && d.y() > 0.0) {
        d.y() /= 2.0;  // the squeezers' (37, 38): the skin above a brow follows over a longer distance
      }
      const double g = upwards * std::exp(-(d.x() * d.x() + d.y() * d.y()) / (2 * radius * radius) - d.z() * d.z() / (2 * depthRadius * depthRadius));
      falloff[c] = g > 1e-4 && !model.lattice_.onBoundary(static_cast<int>(c)) ? g : 0.0;
    }
    const Eigen::VectorXd spread = model.embedding_.basis * falloff;  // B·D_k per unit direction
    const Side side = sideOf(fap);
    const auto mask = [&](int vertex) {
      const Eigen::Vector3d p = rest.col(vertex);
      double m = 1.0;
      // Brows hand over more softly at the middle of the forehead: both brows' fields meet there. The hand-over
      // ends at the inner brow points, so that neither brow's field reaches the other's inner point and raising
      // both moves each by just its own value.
      const double width = fap.group == "eyebrow" ? std::min(3.0 * sideWidth, innerBrowX) : sideWidth;
      if (side == Side::kLeft) m *= smoothstep(-width, width, p.x());
      if (side == Side::kRight) m *= 1.0 - smoothstep(-width, width, p.x());
      const double carried = model.jawFollow_[vertex];
      if (linear.lip == Lip::kUpper) m *= std::clamp((0.7 - carried) / 0.4, 0.0, 1.0);
      if (linear.lip == Lip::kLower) m *= std::clamp((carried - 0.3) / 0.4, 0.0, 1.0);
      // Brows and the forehead, fading out down the skin above the eye so the upper lid (which turns with the
      // eyelid FAPs) is not pulled up with them.
      if (fap.group == "eyebrow") m *= smoothstep(eyeLevel + 0.4 * irisd, centre.y(), p.y());
      if (raiser) m *= browShare(p.x());
      return m;
    };
    std::vector<double> raw(model.embedding_.points.size());
    for (std::size_t i = 0; i < raw.size(); ++i) raw[i] = mask(model.embedding_.points[i]) * spread[static_cast<Eigen::Index>(i)];
    // Normalise on the feature point itself: the mean of its vertices' motion is exactly one FAPU.
    double atPoint = 0.0;
    const std::vector<int>& pointVertices = model.points_.vertices(fap.featurePoint);
    for (int v : pointVertices) {
      const auto found = std::find(model.embedding_.points.begin(), model.embedding_.points.end(), v);
      if (found == model.embedding_.points.end()) throw Error("face model: feature point " + std::string(fap.featurePoint) + " is outside the lattice");
      atPoint += raw[static_cast<std::size_t>(found - model.embedding_.points.begin())];
    }
    atPoint /= static_cast<double>(pointVertices.size());
    if (!(atPoint > 1e-6)) throw Error("face model: FAP " + std::to_string(fap.number) + "'s field does not reach its feature point");
    const double scale = u.of(fap.unit) / atPoint;
    // Above the brow the forehead slides over the skull rather than moving straight up: the field's direction
    // turns into the neutral skin's tangent plane there (keeping its length). Straight up, the forehead, which
    // leans back more the higher it is, would be pushed out of its own surface by the upward motion times the
    // normal's upward tilt, and sink back where the field fades under the lattice's top, a soft bulge. The
    // turn starts at the feature point's height (where the skin is nearly vertical and the point must move
    // along the standard's direction) and is complete one fall-off radius higher.
    const auto along = [&](int vertex) -> Eigen::Vector3d {
      if (fap.group != "eyebrow") return direction;
      const Eigen::Vector3d n = skinNormals.col(vertex);
      const double slide = smoothstep(centre.y(), centre.y() + radius, rest(1, vertex));
      const Eigen::Vector3d tangent = direction - slide * direction.dot(n) * n;
      // Unit length, except where the skin faces up (the top of the head, beyond the field's reach): there
      // the tangent's length goes smoothly to zero instead of the direction turning abruptly.
      return tangent / std::max(tangent.norm(), 0.5);
    };
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const double amount = raw[i] * scale;
      const int vertex = model.embedding_.points[i];
      if (std::abs(amount) > 1e-4 * u.of(fap.unit))
        model.linear_[static_cast<std::size_t>(fap.number)].push_back({vertex, (amount * along(vertex)).cast<float>()});
    }
  }

  // Fields given straight per vertex (not through the lattice): a weight per vertex times the FAP's direction,
  // normalised so the feature point moves by exactly value × FAPU. `reach` is as far from the feature point as
  // a moved vertex lies.
  const auto directField = [&](int number, const std::vector<std::pair<int, double>>& weights) {
    const FapDefinition& fap = fapDefinition(number);
    const Eigen::Vector3d centre = at(fap.featurePoint);
    double atPoint = 0.0;
    const std::vector<int>& pointVertices = model.points_.vertices(fap.featurePoint);
    for (int p : pointVertices)
      for (const auto& [v, w] : weights)
        if (v == p) atPoint += w;
    atPoint /= static_cast<double>(pointVertices.size());
    if (!(atPoint > 0.5)) throw Error("face model: FAP " + std::to_string(number) + "'s field does not carry its feature point");
    const Eigen::Vector3d unit = u.of(fap.unit) / atPoint * directionOf(fap);
    double reach = 0.0;
    for (const auto& [v, w] : weights) {
      model.linear_[static_cast<std::size_t>(number)].push_back({v, (w * unit).cast<float>()});
      reach = std::max(reach, (rest.col(v) - centre).norm());
    }
    model.reach_[static_cast<std::size_t>(number)] = reach;
  };

  // The ears (65–68). The ICT head's auricles are part of M_Face, so they lie inside the lattice, but in its
  // outermost cells, next to its fixed boundary (control points ~0.5 cm apart; the auricle stands 1–1.5 cm off
  // the side of the head): a control-point Gaussian cannot move the auricle without the side of the head
  // beside it, the per-vertex mask would do all the work. So they are direct per-vertex fields: `findEar`
  // fits the side of the head around the ear's outermost point and weighs each vertex by how far it stands
  // out of it (1 on the auricle, 0 on the head), so raising or pulling an ear moves the auricle as a whole.
  {
    const double low = at("2.1").y(), high = std::max(at("4.5").y(), at("4.6").y());
    for (const bool left : {true, false}) {
      const Ear ear = findEar(rest, skin, left ? 1.0 : -1.0, low, high, es);
      model.points_.set(left ? "10.1" : "10.2", {ear.top});
      model.points_.set(left ? "10.3" : "10.4", {ear.outer});
      directField(left ? 65 : 66, ear.weights);
      directField(left ? 67 : 68, ear.weights);
    }
  }

  // The tongue (43–47). ICT draws gums and tongue as one material, one connected surface (the tongue's
  // underside folds into the floor of the mouth, which runs into the lower gums), so `findTongue` tells it
  // apart by geometry: what the jaw carries above the fold, grown from the top of the tongue. Its fields are
  // direct per-vertex ones (the mouth is far inside the skin's lattice, which holds only skin), applied before
  // the jaw turns, so the tongue rides on the jaw. Each fades to 0 down to the fold (`level`) and back to the
  // root, where the tongue meets the throat, which stays.
  {
    const TongueBody tongue = findTongue(model.mesh_, model.jawFollow_, mw, mns);
    model.points_.set("6.1", {tongue.tip});
    model.points_.set("6.2", {tongue.top});
    model.points_.set("6.3", {tongue.leftBorder});
    model.points_.set("6.4", {tongue.rightBorder});
    const double tipZ = rest(2, tongue.tip), length = tipZ - tongue.back;
    if (!(length > 0.0)) throw Error("face model: the tongue's tip is not in front of its root");
    const double fold = 0.15 * mns;  // the fade above the fold, 3 mm
    std::vector<std::pair<int, double>> tip, body;
    for (int v : tongue.vertices) {
      const double lift = smoothstep(tongue.level, tongue.level + fold, rest(1, v));
      const double z = rest(2, v);
      // The tip's FAPs (43–45) move the front third whole and fade out over the middle; raise_tongue (46) lifts
      // the body and tip, fading out over the back 40 %.
      const double wTip = lift * smoothstep(tipZ - 0.7 * length, tipZ - 0.3 * length, z);
      const double wBody = lift * smoothstep(tongue.back, tongue.back + 0.4 * length, z);
      if (wTip > 1e-6) tip.emplace_back(v, wTip);
      if (wBody > 1e-6) body.emplace_back(v, wBody);
    }
    for (int fap : {43, 44, 45}) directField(fap, tip);
    directField(46, body);
    // tongue_roll (47): the sides curl up into a U, each vertex turning about the mid-line's axis (along z, at
    // the height of the tongue's top) by its share of the angle: 0 on the mid-line, growing to 1 at the
    // borders (6.3, 6.4), times the body's fade. The border points turn by exactly the angle.
    model.tongueAxisY_ = rest(1, tongue.top);
    const double halfWidth = 0.5 * (rest(0, tongue.leftBorder) - rest(0, tongue.rightBorder));
    const auto bodyShare = [&](int v) {
      return smoothstep(tongue.level, tongue.level + fold, rest(1, v)) * smoothstep(tongue.back, tongue.back + 0.4 * length, rest(2, v));
    };
    const double atBorders = std::min(bodyShare(tongue.leftBorder), bodyShare(tongue.rightBorder));
    if (!(atBorders > 0.2)) throw Error("face model: the tongue's borders lie too near its root to roll");
    for (int v : tongue.vertices) {
      const double x = rest(0, v);
      const double share = std::min(1.0, smoothstep(0.0, halfWidth, std::abs(x)) * bodyShare(v) / atBorders);
      if (share > 1e-6) model.tongueRoll_.emplace_back(v, static_cast<float>(x > 0.0 ? share : -share));
    }
  }

  // Eyes: a sphere fitted to each sclera; the ball (sclera and iris) turns rigidly about its centre, and the
  // lids turn about the same centre.
  for (int e = 0; e < 2; ++e) {
    const bool left = e == 0;
    Eye& eye = model.eyes_[static_cast<std::size_t>(e)];
    const std::vector<int> sclera = model.mesh_.verticesOf(left ? "M_ScleraLeft" : "M_ScleraRight");
    const std::vector<int> iris = model.mesh_.verticesOf(left ? "M_IrisLeft" : "M_IrisRight");
    if (sclera.size() < 10 || iris.empty()) throw Error("face model: the mesh's eyes need sclera and iris materials");
    std::tie(eye.centre, eye.radius) = fitSphere(rest, sclera);
    eye.ball = sclera;
    eye.ball.insert(eye.ball.end(), iris.begin(), iris.end());
    const Eigen::Vector3d outer = at(left ? "3.7" : "3.8"), inner = at(left ? "3.11" : "3.12");
    const Eigen::Vector3d upper = at(left ? "3.1" : "3.2"), lower = at(left ? "3.3" : "3.4");
    const double middleX = 0.5 * (outer.x() + inner.x()), halfWidth = 0.5 * std::abs(outer.x() - inner.x());
    const double cornerY = 0.5 * (outer.y() + inner.y());
    std::vector<int> lidVertices = skin;
    const std::vector<int> lashes = model.mesh_.verticesOf("M_EyeLashes");
    lidVertices.insert(lidVertices.end(), lashes.begin(), lashes.end());
    for (int v : lidVertices) {
      const Eigen::Vector3d p = rest.col(v);
      if ((p.x() > 0) != left) continue;
      const double across = std::abs(p.x() - middleX) / halfWidth;
      const double horizontal = 1.0 - smoothstep(0.85, 1.35, across);
      if (horizontal <= 0.0) continue;
      // Each lid's margin, a parabola through the corners and the lid's middle.
      const double shape = 1.0 - std::min(1.0, across * across);
      if (p.y() >= cornerY) {
        const double margin = cornerY + (upper.y() - cornerY) * shape;
        const double w = horizontal * (1.0 - smoothstep(margin + 0.3 * irisd, margin + 1.2 * irisd, p.y()));
        if (w > 1e-3) eye.upperLid.emplace_back(v, static_cast<float>(w));
      } else {
        const double margin = cornerY + (lower.y() - cornerY) * shape;
        const double w = horizontal * (1.0 - smoothstep(margin - 0.3 * irisd, margin - 1.0 * irisd, p.y()));
        if (w > 1e-3) eye.lowerLid.emplace_back(v, static_cast<float>(w));
      }
    }
  }
  model.pupilRadius_ = 0.25 * irisd;

  // The head turns about the top of the spine: level with the jaw's hinge, behind it by a quarter of the eye
  // separation; the neck below the chin hands over to the body.
  model.neckPivot_ = Eigen::Vector3d(0.0, model.jaw_.pivot.y() - 0.15 * es, model.jaw_.pivot.z() - 0.4 * es);
  const double bottom = rest.row(1).minCoeff();
  const double chinY = at("2.1").y();
  model.headShare_.resize(static_cast<std::size_t>(rest.cols()));
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    model.headShare_[static_cast<std::size_t>(v)] =
        static_cast<float>(smoothstep(bottom + 0.2 * (chinY - bottom), chinY - 0.05 * mns, rest(1, v)));
  return model;
}

std::vector<int> FaceModel::innerLipVertices() const {
  std::vector<int> vertices;
  for (const char* id : {"2.2", "2.3", "2.4", "2.5", "2.6", "2.7", "2.8", "2.9"})
    for (int v : points_.vertices(id)) vertices.push_back(v);
  return vertices;
}

std::vector<int> FaceModel::eyeLidVertices(int side) const {
  std::vector<int> vertices;
  const auto ids = side == 0 ? std::array{"3.1", "3.3", "3.7", "3.11"} : std::array{"3.2", "3.4", "3.8", "3.12"};
  for (const char* id : ids)
    for (int v : points_.vertices(id)) vertices.push_back(v);
  return vertices;
}

bool FaceModel::supports(int fap) const {
  if (fap < 1 || fap > kNumFaps) return false;
  if (!linear_[static_cast<std::size_t>(fap)].empty()) return true;
  return fap == 3 || fap == 14 || fap == 15 || (fap >= 19 && fap <= 30) || (fap == 47 && !tongueRoll_.empty()) ||
         (fap >= 48 && fap <= 50);
}

double FaceModel::jawAngleFor(double openJaw) const {
  if (openJaw <= 0.0) return 0.0;  // unidirectional: the jaw does not close past rest
  const double target = std::max(0.0, openJaw) * units_.mns;
  const Eigen::Vector3d chin = points_.position(mesh_.positions, "2.1");
  const auto drop = [&](double angle) { return chinFollow_ * (chin.y() - jaw_.rotate(chin, angle).y()); };
  // The drop grows with the angle up to where the chin passes below the hinge; bisect within that.
  double low = 0.0, high = std::numbers::pi / 3;
  if (target >= drop(high)) return high;
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (low + high);
    (drop(middle) < target ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

std::array<double, 2> FaceModel::pupilScale(const FapFrame& faps) const {
  return {std::max(0.1, 1.0 + faps[29] * units_.irisd / pupilRadius_), std::max(0.1, 1.0 + faps[30] * units_.irisd / pupilRadius_)};
}

Eigen::Matrix3Xd FaceModel::deform(const FapFrame& faps) const { return deformSelected(faps, nullptr); }

Eigen::Matrix3Xd FaceModel::deform(const FapFrame& faps, const VertexSelection& selection) const {
  if (selection.columnOf.size() != static_cast<std::size_t>(mesh_.numVertices()) || selection.fields.size() != linear_.size())
    throw Error("FaceModel::deform: the selection was made for another mesh");
  return deformSelected(faps, &selection);
}

VertexSelection FaceModel::select(const std::vector<int>& vertices) const {
  VertexSelection selection;
  selection.vertices = vertices;
  selection.columnOf.assign(static_cast<std::size_t>(mesh_.numVertices()), -1);
  for (std::size_t c = 0; c < vertices.size(); ++c) {
    if (vertices[c] < 0 || vertices[c] >= mesh_.numVertices())
      throw Error("FaceModel::select: vertex " + std::to_string(vertices[c]) + " is not in the mesh");
    int& column = selection.columnOf[static_cast<std::size_t>(vertices[c])];
    if (column < 0) column = static_cast<int>(c);  // a vertex chosen twice is deformed once (the first column)
  }
  selection.fields.resize(linear_.size());
  for (std::size_t fap = 0; fap < linear_.size(); ++fap)
    for (const FieldEntry& entry : linear_[fap])
      if (const int c = selection.columnOf[static_cast<std::size_t>(entry.vertex)]; c >= 0)
        selection.fields[fap].push_back({c, entry.displacement});
  return selection;
}

Eigen::Matrix3Xd FaceModel::deformSelected(const FapFrame& faps, const VertexSelection* selection) const {
  // The column of a mesh vertex in `v` (-1: not deformed here), and the mesh vertex of a column.
  const auto columnOf = [&](int vertex) { return selection ? selection->columnOf[static_cast<std::size_t>(vertex)] : vertex; };
  const auto vertexOf = [&](Eigen::Index column) {
    return selection ? selection->vertices[static_cast<std::size_t>(column)] : static_cast<int>(column);
  };
  Eigen::Matrix3Xd v;
  if (selection) {
    v.resize(3, static_cast<Eigen::Index>(selection->vertices.size()));
    for (Eigen::Index c = 0; c < v.cols(); ++c) v.col(c) = mesh_.positions.col(vertexOf(c));
  } else {
    v = mesh_.positions;
  }
  const Eigen::Matrix3Xd& rest = mesh_.positions;
  for (int fap = 1; fap <= kNumFaps; ++fap) {
    const double value = faps[static_cast<std::size_t>(fap)];
    if (value == 0.0) continue;
    if (selection) {
      for (const VertexSelection::FieldEntry& entry : selection->fields[static_cast<std::size_t>(fap)])
        v.col(entry.column) += value * entry.displacement.cast<double>();
    } else {
      for (const FieldEntry& entry : linear_[static_cast<std::size_t>(fap)])
        v.col(entry.vertex) += value * entry.displacement.cast<double>();
    }
  }

  // Tongue roll (unidirectional: the sides curl up): each side turns about the mid-line's axis, the face's left
  // (+x) counter-clockwise seen from the front, its right clockwise, so both borders rise.
  const double tongueRoll = std::max(0.0, faps[47]) * kAngleUnit;
  if (tongueRoll != 0.0) {
    for (const auto& [vertex, share] : tongueRoll_) {
      const int column = columnOf(vertex);
      if (column < 0) continue;
      const double a = share * tongueRoll, c = std::cos(a), s = std::sin(a);
      const double x = v(0, column), y = v(1, column) - tongueAxisY_;
      v(0, column) = c * x - s * y;
      v(1, column) = tongueAxisY_ + s * x + c * y;
    }
  }

  // Jaw: each vertex turns by its share of the angle and slides by its share of the thrust and shift. The
  // slide is scaled so that the chin point, whose share is chinFollow_, moves by exactly value × FAPU.
  const double angle = jawAngleFor(faps[3]);
  const Eigen::Vector3d slide = (std::max(0.0, faps[14]) * units_.mns * Eigen::Vector3d::UnitZ() +
                                 faps[15] * units_.mw * -Eigen::Vector3d::UnitX()) / chinFollow_;
  if (angle != 0.0 || slide.squaredNorm() > 0.0) {
    for (int vertex : jawVertices_) {
      const int column = columnOf(vertex);
      if (column < 0) continue;
      const double share = jawFollow_[vertex];
      v.col(column) = jaw_.pivot + Eigen::AngleAxisd(share * angle, jaw_.axis) * (v.col(column) - jaw_.pivot) + share * slide;
    }
  }

  // Eyelids and eyeballs.
  for (int e = 0; e < 2; ++e) {
    const Eye& eye = eyes_[static_cast<std::size_t>(e)];
    const bool left = e == 0;
    const double closeUpper = faps[left ? 19 : 20], closeLower = faps[left ? 21 : 22];
    const auto lidAngle = [&](std::string_view point, double drop) {
      // The angle about the eye's x axis that moves the lid's middle vertically by `drop` (down positive).
      const Eigen::Vector3d p = points_.position(rest, point) - eye.centre;
      const double radius = std::hypot(p.y(), p.z());
      const double elevation = std::atan2(p.y(), p.z());
      const double target = std::clamp((p.y() - drop) / radius, -1.0, 1.0);
      return elevation - std::asin(target);  // positive turns the front downwards (about +x)
    };
    if (closeUpper != 0.0) {
      const double turn = lidAngle(left ? "3.1" : "3.2", closeUpper * units_.irisd);
      for (const auto& [vertex, share] : eye.upperLid)
        if (const int c = columnOf(vertex); c >= 0)
          v.col(c) = eye.centre + Eigen::AngleAxisd(share * turn, Eigen::Vector3d::UnitX()) * (v.col(c) - eye.centre);
    }
    if (closeLower != 0.0) {
      const double turn = lidAngle(left ? "3.3" : "3.4", -closeLower * units_.irisd);
      for (const auto& [vertex, share] : eye.lowerLid)
        if (const int c = columnOf(vertex); c >= 0)
          v.col(c) = eye.centre + Eigen::AngleAxisd(share * turn, Eigen::Vector3d::UnitX()) * (v.col(c) - eye.centre);
    }
    const double yaw = faps[left ? 23 : 24] * kAngleUnit, pitch = faps[left ? 25 : 26] * kAngleUnit;
    const double thrust = faps[left ? 27 : 28] * units_.es;
    if (yaw != 0.0 || pitch != 0.0 || thrust != 0.0) {
      const Eigen::Matrix3d turn = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX())).toRotationMatrix();
      for (int vertex : eye.ball)
        if (const int c = columnOf(vertex); c >= 0)
          v.col(c) = eye.centre + turn * (v.col(c) - eye.centre) + thrust * Eigen::Vector3d::UnitZ();
    }
  }

  // Head.
  const double pitch = faps[48] * kAngleUnit, yaw = faps[49] * kAngleUnit, roll = faps[50] * kAngleUnit;
  if (pitch != 0.0 || yaw != 0.0 || roll != 0.0) {
    const Eigen::Matrix3d full = headRotation(pitch, yaw, roll);
    for (Eigen::Index column = 0; column < v.cols(); ++column) {
      const float share = headShare_[static_cast<std::size_t>(vertexOf(column))];
      if (share <= 0.0f) continue;
      const Eigen::Matrix3d turn = share >= 1.0f ? full : headRotation(share * pitch, share * yaw, share * roll);
      v.col(column) = neckPivot_ + turn * (v.col(column) - neckPivot_);
    }
  }
  // A vertex chosen twice was deformed in one column (columnOf holds one); the others take it from there.
  if (selection)
    for (Eigen::Index c = 0; c < v.cols(); ++c)
      if (const int first = columnOf(vertexOf(c)); first != c) v.col(c) = v.col(first);
  return v;
}

}  // namespace th::face
