// The animated face: every FAP the mesh can show (every low-level one, tongue and ears included) moves its
// feature point by value × FAPU in the standard's direction and leaves the far face alone; the jaw, lids,
// eyeballs, tongue and head turn as they should.
#include "face/face_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "face/fap.h"

namespace {

using th::face::FaceModel;
using th::face::FapFrame;

const FaceModel& face() {
  static const FaceModel model = FaceModel::buildDefault();
  return model;
}

Eigen::Vector3d pointIn(const Eigen::Matrix3Xd& positions, const char* id) {
  return face().points().position(positions, id);
}

double degrees(double d) {
  return d * std::numbers::pi / 180.0 / th::face::kAngleUnit;
}

TEST(FaceModel, AllZeroFapsLeaveTheNeutralFace) {
  const Eigen::Matrix3Xd positions = face().deform(FapFrame{});
  EXPECT_EQ((positions - face().mesh().positions).cwiseAbs().maxCoeff(), 0.0);
}

// Deforming a few vertices (the tracker's 68 landmarks, an eyelid's and the tongue's) moves them exactly as
// deforming the whole mesh does, with every kind of FAP at once.
TEST(FaceModel, ASelectionOfVerticesMovesAsTheWholeMeshDoes) {
  ASSERT_EQ(face().landmarkVertices().size(), 68u);
  std::vector<int> vertices = face().landmarkVertices();
  for (int v : face().eyeLidVertices(0)) vertices.push_back(v);
  for (const char* tip : {"6.1", "6.3"})
    for (int v : face().points().vertices(tip)) vertices.push_back(v);
  const th::face::VertexSelection selection = face().select(vertices);
  FapFrame faps{};
  faps[3] = 300;     // jaw
  faps[5] = -80;     // lower lip
  faps[12] = 60;     // a lip corner
  faps[19] = 400;    // an eyelid
  faps[31] = 50;     // a brow
  faps[43] = 120;    // the tongue
  faps[47] = 20000;  // its roll
  faps[48] = degrees(6.0);
  faps[49] = degrees(-9.0);
  faps[50] = degrees(3.0);
  const Eigen::Matrix3Xd whole = face().deform(faps);
  const Eigen::Matrix3Xd some = face().deform(faps, selection);
  ASSERT_EQ(some.cols(), static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t c = 0; c < vertices.size(); ++c)
    EXPECT_LT((some.col(static_cast<Eigen::Index>(c)) - whole.col(vertices[c])).norm(), 1e-9)
        << "vertex " << vertices[c];
  EXPECT_THROW(face().select({-1}), th::Error);
}

TEST(FaceModel, SupportsTheFapsTheMeshCanShow) {
  // Every low-level FAP: the ICT head has a tongue (43–47) and ears (65–68) too. Only the high-level ones (viseme,
  // expression) are not the face model's.
  for (int fap : {0, 1, 2, 69}) EXPECT_FALSE(face().supports(fap)) << fap;
  for (int fap = 3; fap <= th::face::kNumFaps; ++fap) EXPECT_TRUE(face().supports(fap)) << fap;
}

class LinearFap : public ::testing::TestWithParam<int> {};

TEST_P(LinearFap, MovesItsFeaturePointByValueTimesFapuAndLeavesTheFarFaceAlone) {
  const int number = GetParam();
  const th::face::FapDefinition& fap = th::face::fapDefinition(number);
  const double unit = face().units().of(fap.unit);
  FapFrame faps{};
  faps[static_cast<std::size_t>(number)] = 150.0;
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const Eigen::Matrix3Xd moved = face().deform(faps);
  const Eigen::Vector3d direction(fap.direction[0], fap.direction[1], fap.direction[2]);
  const Eigen::Vector3d shift = pointIn(moved, fap.featurePoint.data()) - pointIn(rest, fap.featurePoint.data());
  EXPECT_NEAR(shift.dot(direction), 150.0 * unit, 0.02 * 150.0 * unit) << fap.name;
  EXPECT_LT((shift - shift.dot(direction) * direction).norm(), 0.02 * 150.0 * unit) << fap.name << ": sideways";
  // Beyond the field's reach (3.5 widened fall-off radii: 4.2 cm for a lip, 11 cm upwards for a brow) nothing
  // moves more than 2 % as far as the feature point.
  const Eigen::Vector3d centre = pointIn(rest, fap.featurePoint.data());
  const double far = face().reach(number);
  ASSERT_GT(far, 0.0);
  ASSERT_LT(far, 0.6 * face().units().mw * 1024 * 4.0);
  double worst = 0.0;
  for (Eigen::Index v = 0; v < rest.cols(); ++v)
    if ((rest.col(v) - centre).norm() > far) worst = std::max(worst, (moved.col(v) - rest.col(v)).norm());
  EXPECT_LT(worst, 0.02 * shift.norm()) << fap.name;
  // Linear: twice the value, twice the motion.
  faps[static_cast<std::size_t>(number)] = 300.0;
  const Eigen::Matrix3Xd twice = face().deform(faps);
  EXPECT_LT(((twice - rest) - 2.0 * (moved - rest)).cwiseAbs().maxCoeff(), 1e-5 * unit * 150);
}

INSTANTIATE_TEST_SUITE_P(Faps, LinearFap,
                         ::testing::Values(4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 16, 17, 18, 31, 32, 33, 34, 35, 36, 37, 38,
                                           39, 40, 41, 42, 43, 44, 45, 46, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61,
                                           62, 63, 64, 65, 66, 67, 68),
                         [](const auto& test) { return std::string(th::face::fapDefinition(test.param).name); });

// The brows' points, inner to outer, left then right; and their raisers, 31–36.
constexpr const char* kBrowPoints[] = {"4.1", "4.3", "4.5", "4.2", "4.4", "4.6"};

FapFrame raisedBrows(double value) {
  FapFrame faps{};
  for (int fap = 31; fap <= 36; ++fap) faps[static_cast<std::size_t>(fap)] = value;
  return faps;
}

TEST(FaceModel, RaisingTheWholeBrowMovesEachBrowPointByTheValue) {
  // Each raiser alone moves its own point by value × ENS (above); raised together, the neighbours' fields must
  // not add to it. Overlapping fields moved the middle points by 1.56 × the value.
  const double raise = 400.0 * face().units().ens;
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const Eigen::Matrix3Xd moved = face().deform(raisedBrows(400.0));
  for (const char* id : kBrowPoints) {
    const Eigen::Vector3d shift = pointIn(moved, id) - pointIn(rest, id);
    EXPECT_NEAR(shift.y(), raise, 0.02 * raise) << id;
    EXPECT_LT(std::hypot(shift.x(), shift.z()), 0.02 * raise) << id << ": sideways";
  }
}

// Outward vertex normals of the skin (face and back of the head), from its triangles.
Eigen::Matrix3Xd skinNormals() {
  return th::face::vertexNormals(face().mesh(), {"M_Face", "M_BackHead"});
}

TEST(FaceModel, ARaisedBrowSlidesTheForeheadOverItsSurfaceInsteadOfBulgingOut) {
  // The upper forehead (from one brow fall-off radius, 0.25 ES, above the highest brow point up; across the
  // brows) under a large raise of the whole brow: how far each moved vertex stands out of the neutral skin's
  // surface, measured along the normal of the nearest neutral skin vertex (the mesh is fine enough, ~3 mm,
  // that this is the distance to the surface within ~0.1 mm).
  const th::face::Mesh& mesh = face().mesh();
  const Eigen::Matrix3Xd& rest = mesh.positions;
  const Eigen::Matrix3Xd normals = skinNormals();
  std::vector<int> skin = mesh.verticesOf("M_Face");
  for (int v : mesh.verticesOf("M_BackHead")) skin.push_back(v);
  double browTop = -std::numeric_limits<double>::infinity(), browSide = 0.0;
  for (const char* id : kBrowPoints)
    browTop = std::max(browTop, pointIn(rest, id).y()), browSide = std::max(browSide, std::abs(pointIn(rest, id).x()));
  std::vector<int> forehead;
  for (int v : mesh.verticesOf("M_Face"))
    if (rest(1, v) > browTop + 0.25 * 1024 * face().units().es && std::abs(rest(0, v)) < browSide &&
        normals(2, v) > 0.0)
      forehead.push_back(v);
  ASSERT_GT(forehead.size(), 100u);
  for (double value : {300.0, 400.0}) {
    const double raise = value * face().units().ens;
    const Eigen::Matrix3Xd moved = face().deform(raisedBrows(value));
    double worst = 0.0;
    for (int v : forehead) {
      const Eigen::Vector3d p = moved.col(v);
      int nearest = skin.front();
      for (int q : skin)
        if ((rest.col(q) - p).squaredNorm() < (rest.col(nearest) - p).squaredNorm()) nearest = q;
      worst = std::max(worst, (p - rest.col(nearest)).dot(normals.col(nearest)));
    }
    // Moved straight up, the forehead (which leans back more the higher it is) stood out by the raise times
    // the normal's upward tilt: 0.54–0.58 of the raise here (1.1 cm at 400), a bulge fading into the fixed
    // lattice top. Sliding by s along a straight tangent still leaves skin that curves with radius R up to
    // s²/2R outside it: with the upper forehead's R ≈ 7 cm (its normal turns ~35° over 4.5 cm) and s up to the
    // raise, 1.9 cm at 400, that is ≈ 0.13 of the raise; allow 0.15.
    RecordProperty("standsOutPerRaiseAt" + std::to_string(static_cast<int>(value)), std::to_string(worst / raise));
    EXPECT_LT(worst, 0.15 * raise) << "brows raised " << value << ": the forehead stands out " << worst;
  }
}

TEST(FaceModel, OpenJawDropsTheChinAndCarriesLowerLipTeethAndTongueTogether) {
  FapFrame faps{};
  faps[3] = 500.0;
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const Eigen::Matrix3Xd moved = face().deform(faps);
  const double drop = pointIn(rest, "2.1").y() - pointIn(moved, "2.1").y();
  EXPECT_NEAR(drop, 500.0 * face().units().mns, 0.02 * 500.0 * face().units().mns);
  // The lower lip comes down almost as far as the chin; the upper lip hardly moves.
  EXPECT_GT(pointIn(rest, "2.3").y() - pointIn(moved, "2.3").y(), 0.7 * drop);
  EXPECT_LT(pointIn(rest, "2.2").y() - pointIn(moved, "2.2").y(), 0.15 * drop);
  // Lower teeth and tongue go with the jaw; the upper teeth and the nose stay.
  const auto meanDrop = [&](const std::vector<int>& vertices, bool lowerHalf) {
    double sum = 0.0;
    int count = 0;
    for (int v : vertices) {
      const double d = rest(1, v) - moved(1, v);
      if ((d > 0.2 * drop) == lowerHalf) sum += d, ++count;
    }
    return count > 0 ? sum / count : 0.0;
  };
  const std::vector<int> teeth = face().mesh().verticesOf("M_Teeth");
  EXPECT_GT(meanDrop(teeth, true), 0.4 * drop);              // the lower teeth went down
  EXPECT_LT(std::abs(meanDrop(teeth, false)), 0.05 * drop);  // the upper teeth did not
  EXPECT_GT(meanDrop(face().mesh().verticesOf("M_GumsTongue"), true), 0.3 * drop);
  EXPECT_LT((pointIn(moved, "9.3") - pointIn(rest, "9.3")).norm(), 0.02 * drop);
}

TEST(FaceModel, ThrustAndShiftMoveTheChinStraight) {
  for (const auto& [fap, axis] : {std::pair{14, 2}, std::pair{15, 0}}) {
    FapFrame faps{};
    faps[static_cast<std::size_t>(fap)] = 100.0;
    const th::face::FapDefinition& definition = th::face::fapDefinition(fap);
    const Eigen::Vector3d shift = pointIn(face().deform(faps), "2.1") - pointIn(face().mesh().positions, "2.1");
    const double expected =
        100.0 * face().units().of(definition.unit) * definition.direction[static_cast<std::size_t>(axis)];
    EXPECT_NEAR(shift[axis], expected, 0.02 * std::abs(expected)) << fap;
  }
}

TEST(FaceModel, EyelidsCloseOverTheEye) {
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const double irisd = face().units().irisd;
  for (const auto& [upperFap, lowerFap, upper, lower] :
       {std::tuple{19, 21, "3.1", "3.3"}, std::tuple{20, 22, "3.2", "3.4"}}) {
    FapFrame faps{};
    faps[static_cast<std::size_t>(upperFap)] = 300.0;
    faps[static_cast<std::size_t>(lowerFap)] = 200.0;
    Eigen::Matrix3Xd moved = face().deform(faps);
    EXPECT_NEAR(pointIn(rest, upper).y() - pointIn(moved, upper).y(), 300.0 * irisd, 0.02 * 300.0 * irisd);
    EXPECT_NEAR(pointIn(moved, lower).y() - pointIn(rest, lower).y(), 200.0 * irisd, 0.02 * 200.0 * irisd);
    // A full blink (1024 = one IRISD, the lids' distance) brings the upper lid's middle onto the lower lid.
    faps = FapFrame{};
    faps[static_cast<std::size_t>(upperFap)] = 1024.0;
    moved = face().deform(faps);
    EXPECT_NEAR(pointIn(moved, upper).y(), pointIn(rest, lower).y(), 0.05 * 1024 * irisd);
    // The lid slides over the eyeball instead of cutting into it: it stays outside the sclera's sphere.
    EXPECT_GT((pointIn(moved, upper) - pointIn(rest, upper)).z(), -0.5 * 1024 * irisd);
  }
}

TEST(FaceModel, EyeballsTurnAboutTheirCentres) {
  FapFrame faps{};
  faps[23] = degrees(15.0);  // left eye, to the face's left
  faps[26] = degrees(10.0);  // right eye, down
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const Eigen::Matrix3Xd moved = face().deform(faps);
  const Eigen::Vector3d left = pointIn(moved, "3.5") - pointIn(rest, "3.5");
  const Eigen::Vector3d right = pointIn(moved, "3.6") - pointIn(rest, "3.6");
  EXPECT_GT(left.x(), 0.0);
  EXPECT_NEAR(left.y(), 0.0, 1e-9);
  EXPECT_LT(right.y(), 0.0);
  EXPECT_NEAR(right.x(), 0.0, 1e-9);
  // The pupil's arc: the apex moves by r·sin(15°) sideways (r = the iris sphere's apex distance from the centre).
  EXPECT_GT(left.norm(), 0.2);
}

TEST(FaceModel, TheHeadTurnsAboutTheNeckAndTheNeckBaseStays) {
  FapFrame faps{};
  faps[49] = degrees(20.0);  // yaw to the face's left
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const Eigen::Matrix3Xd moved = face().deform(faps);
  const Eigen::Vector3d pivot = face().neckPivot();
  const Eigen::Vector3d before = pointIn(rest, "9.3") - pivot, after = pointIn(moved, "9.3") - pivot;
  const double turned = std::atan2(after.x(), after.z()) - std::atan2(before.x(), before.z());
  EXPECT_NEAR(turned * 180 / std::numbers::pi, 20.0, 0.05);
  EXPECT_GT(pointIn(moved, "9.3").x(), pointIn(rest, "9.3").x());  // the nose turns to the face's left
  const double bottom = rest.row(1).minCoeff();
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    if (rest(1, v) < bottom + 1.0) {
      ASSERT_LT((moved.col(v) - rest.col(v)).norm(), 1e-9) << v;
    }
  }
}

// The ears (65–68) move the auricle as a whole: both of an ear's points move by value × ENS whichever of its
// FAPs is given (the per-FAP test above checks the FAP's own point, direction and sideways motion), and nothing
// of the face or the other side of the head moves.
TEST(FaceModel, EarFapsMoveTheWholeAuricleAndNothingOfTheFaceOrTheOtherEar) {
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const double ens = face().units().ens;
  for (const auto& [fap, top, back, axis] : {std::tuple{65, "10.1", "10.3", 1}, std::tuple{66, "10.2", "10.4", 1},
                                             std::tuple{67, "10.1", "10.3", 0}, std::tuple{68, "10.2", "10.4", 0}}) {
    const th::face::FapDefinition& definition = th::face::fapDefinition(fap);
    FapFrame faps{};
    faps[static_cast<std::size_t>(fap)] = 200.0;
    const Eigen::Matrix3Xd moved = face().deform(faps);
    const double expected = 200.0 * ens * definition.direction[static_cast<std::size_t>(axis)];
    for (const char* id : {top, back}) {
      const Eigen::Vector3d shift = pointIn(moved, id) - pointIn(rest, id);
      EXPECT_NEAR(shift[axis], expected, 0.02 * std::abs(expected)) << definition.name << " at " << id;
    }
    // The face: nose, mouth, chin, eyes and brows stay exactly.
    for (const char* id :
         {"9.3", "9.15", "8.3", "8.4", "2.1", "2.2", "3.5", "3.6", "3.7", "3.8", "4.5", "4.6", "5.3", "5.4"})
      EXPECT_EQ((pointIn(moved, id) - pointIn(rest, id)).norm(), 0.0) << definition.name << " moved " << id;
    // The other side of the head, its ear included, does not move at all; on this side only the ear moves
    // (nothing farther from the moved ear's top than the auricle's size, 0.6 ES past its centre).
    const double side = definition.direction[0] != 0.0 ? definition.direction[0] : (fap == 65 ? 1.0 : -1.0);
    const Eigen::Vector3d earTop = pointIn(rest, top);
    double otherSide = 0.0, farAway = 0.0;
    for (Eigen::Index v = 0; v < rest.cols(); ++v) {
      const double motion = (moved.col(v) - rest.col(v)).norm();
      if (side * rest(0, v) <= 0.0) otherSide = std::max(otherSide, motion);
      if ((rest.col(v) - earTop).norm() > 1.5 * face().units().es * 1024) farAway = std::max(farAway, motion);
    }
    EXPECT_EQ(otherSide, 0.0) << definition.name;
    EXPECT_EQ(farAway, 0.0) << definition.name;
  }
}

TEST(FaceModel, EarFeaturePointsSitOnTheAuricle) {
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  for (const auto& [top, back, side] : {std::tuple{"10.1", "10.3", 1.0}, std::tuple{"10.2", "10.4", -1.0}}) {
    const Eigen::Vector3d t = pointIn(rest, top), b = pointIn(rest, back);
    // Beside the head, level with the eyes (the ear's top) and behind the eyes' outer corners.
    EXPECT_GT(side * b.x(), side * pointIn(rest, side > 0 ? "3.7" : "3.8").x() + 3.0) << back;
    EXPECT_GE(side * b.x(), side * t.x()) << "the outermost point is the ear's outermost";
    EXPECT_GT(t.y(), pointIn(rest, "9.15").y()) << top;
    EXPECT_LT(t.z(), pointIn(rest, "3.7").z() - 5.0) << top;
  }
  // The mesh is mirrored, so are the points.
  EXPECT_NEAR(pointIn(rest, "10.1").x(), -pointIn(rest, "10.2").x(), 1e-6);
  EXPECT_NEAR(pointIn(rest, "10.3").y(), pointIn(rest, "10.4").y(), 1e-6);
}

// The tongue (43–46 linear, 47 roll): it moves inside the mouth and leaves the teeth, gums and lips alone.
TEST(FaceModel, TongueFapsMoveTheTongueAndNotTheTeethGumsOrLips) {
  const th::face::Mesh& mesh = face().mesh();
  const Eigen::Matrix3Xd& rest = mesh.positions;
  const std::vector<int> teeth = mesh.verticesOf("M_Teeth");
  const std::vector<int> mouth = mesh.verticesOf("M_GumsTongue");
  const Eigen::Vector3d tip = pointIn(rest, "6.1");
  const double halfWidth = 0.5 * (pointIn(rest, "6.3").x() - pointIn(rest, "6.4").x());
  for (int fap : {43, 44, 45, 46, 47}) {
    FapFrame faps{};
    faps[static_cast<std::size_t>(fap)] = fap == 47 ? degrees(20.0) : 150.0;
    const Eigen::Matrix3Xd moved = face().deform(faps);
    const std::string name(th::face::fapDefinition(fap).name);
    double teethMotion = 0.0, gumMotion = 0.0, skinMotion = 0.0;
    for (int v : teeth) teethMotion = std::max(teethMotion, (moved.col(v) - rest.col(v)).norm());
    // The gums: everything in front of the tongue's tip (the lower gums behind the incisors) and outside its
    // borders (the gums along the molars).
    for (int v : mouth)
      if (rest(2, v) > tip.z() + 0.05 || std::abs(rest(0, v)) > halfWidth + 0.1)
        gumMotion = std::max(gumMotion, (moved.col(v) - rest.col(v)).norm());
    for (int v : mesh.verticesOf("M_Face")) skinMotion = std::max(skinMotion, (moved.col(v) - rest.col(v)).norm());
    EXPECT_EQ(teethMotion, 0.0) << name;
    EXPECT_EQ(gumMotion, 0.0) << name;
    EXPECT_EQ(skinMotion, 0.0) << name << ": lips and face";
    // The tongue does move: the tip for 43–46 (by value × FAPU, checked above), the borders for the roll.
    const char* moving = fap == 47 ? "6.3" : "6.1";
    EXPECT_GT((pointIn(moved, moving) - pointIn(rest, moving)).norm(), 0.1) << name;
  }
}

TEST(FaceModel, TongueFeaturePointsSitOnTheTongue) {
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  const Eigen::Vector3d tip = pointIn(rest, "6.1"), top = pointIn(rest, "6.2");
  // The tip on the mid-line, behind the lower incisors and below the upper lip's inner edge; the body's top
  // behind it and higher; the borders either side, behind the tip.
  EXPECT_NEAR(tip.x(), 0.0, 1e-6);
  EXPECT_NEAR(top.x(), 0.0, 1e-6);
  EXPECT_LT(tip.z(), pointIn(rest, "2.3").z() - 1.0);
  EXPECT_LT(tip.y(), pointIn(rest, "2.2").y());
  EXPECT_GT(top.y(), tip.y());
  EXPECT_LT(top.z(), tip.z());
  EXPECT_GT(pointIn(rest, "6.3").x(), 1.0);
  EXPECT_LT(pointIn(rest, "6.4").x(), -1.0);
  EXPECT_LT(pointIn(rest, "6.3").z(), tip.z());
}

TEST(FaceModel, TongueRollCurlsBothSidesUpByTheAngle) {
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  FapFrame faps{};
  faps[47] = degrees(20.0);
  const Eigen::Matrix3Xd moved = face().deform(faps);
  // The sides turn about the mid-line (along z, at the tongue's top): each border's elevation about it grows by
  // the angle; the mid-line (tip, top) stays.
  const double axisY = pointIn(rest, "6.2").y();
  for (const char* id : {"6.3", "6.4"}) {
    const Eigen::Vector3d before = pointIn(rest, id), after = pointIn(moved, id);
    const double turned =
        std::atan2(after.y() - axisY, std::abs(after.x())) - std::atan2(before.y() - axisY, std::abs(before.x()));
    EXPECT_NEAR(turned * 180 / std::numbers::pi, 20.0, 0.02 * 20.0) << id;
    EXPECT_GT(after.y(), before.y()) << id;
    EXPECT_NEAR(after.z(), before.z(), 1e-9) << id;
  }
  for (const char* id : {"6.1", "6.2"}) EXPECT_LT((pointIn(moved, id) - pointIn(rest, id)).norm(), 1e-9) << id;
  // Unidirectional: a negative roll does nothing.
  faps[47] = -degrees(20.0);
  EXPECT_EQ((face().deform(faps) - rest).cwiseAbs().maxCoeff(), 0.0);
}

TEST(FaceModel, TheTongueStillRidesOnTheJawWhenItMoves) {
  // The tongue's fields act before the jaw turns, like the lips': with the jaw open, thrusting the tip moves it
  // by value × MW along the jaw's turned forward direction, and the tip goes down with the jaw.
  const Eigen::Matrix3Xd& rest = face().mesh().positions;
  FapFrame open{};
  open[3] = 400.0;
  const Eigen::Matrix3Xd opened = face().deform(open);
  FapFrame thrust = open;
  thrust[45] = 150.0;
  const Eigen::Matrix3Xd both = face().deform(thrust);
  const double chinDrop = pointIn(rest, "2.1").y() - pointIn(opened, "2.1").y();
  EXPECT_GT(pointIn(rest, "6.1").y() - pointIn(opened, "6.1").y(), 0.3 * chinDrop) << "the tip goes down with the jaw";
  const Eigen::Vector3d shift = pointIn(both, "6.1") - pointIn(opened, "6.1");
  const double expected = 150.0 * face().units().mw;
  EXPECT_NEAR(shift.norm(), expected, 0.02 * expected);
  const double angle = face().jawAngleFor(400.0);
  const Eigen::Vector3d turnedForward = Eigen::AngleAxisd(angle, face().jaw().axis) * Eigen::Vector3d::UnitZ();
  EXPECT_LT(std::acos(std::clamp(shift.normalized().dot(turnedForward), -1.0, 1.0)), 0.15 * angle)
      << "the thrust turns with the jaw (jaw angle " << angle << " rad)";
  // The rest of the mouth goes on riding on the jaw as before: whatever the thrust's field does not hold is
  // where the open jaw alone puts it.
  std::vector<char> inField(static_cast<std::size_t>(rest.cols()), 0);
  for (const FaceModel::FieldEntry& entry : face().linearField(45)) inField[static_cast<std::size_t>(entry.vertex)] = 1;
  double same = 0.0;
  for (int v : face().mesh().verticesOf("M_GumsTongue"))
    if (!inField[static_cast<std::size_t>(v)]) same = std::max(same, (both.col(v) - opened.col(v)).norm());
  EXPECT_EQ(same, 0.0);
}

}  // namespace
