// From model outputs to MPEG-4 FAPs: head angles to FAPs 48–50, the jaw opening to FAP 3 and the lip FAPs.
#include "animation/fap_mapping.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/error.h"
#include "face/fap.h"
#include "face/jaw.h"

namespace {

using th::animation::MouthFapMap;

const th::face::FaceAssets& ict() {
  static const th::face::FaceAssets face = th::face::loadIctFace(th::face::ictFaceDirectory());
  return face;
}

const MouthFapMap& icMap() {
  static const MouthFapMap map = th::animation::defineMouthFapMap(ict());
  return map;
}

double valueOf(const MouthFapMap& map, const Eigen::MatrixXd& faps, int fap, int frame) {
  const std::vector<int> numbers = th::animation::mouthFapNumbers(map);
  for (std::size_t i = 0; i < numbers.size(); ++i)
    if (numbers[i] == fap) return faps(static_cast<Eigen::Index>(i), frame);
  ADD_FAILURE() << "FAP " << fap << " is not in the map";
  return 0.0;
}

TEST(HeadFaps, DegreesBecomeAngleUnits) {
  Eigen::MatrixXd degrees(3, 2);
  degrees << 1, -2, 0, 10, -0.5, 0;
  const Eigen::MatrixXd au = th::animation::headFaps(degrees);
  EXPECT_NEAR(au(0, 0), std::numbers::pi / 180 * 1e5, 1e-9);  // 1° = 1745.33 AU
  EXPECT_NEAR(au(1, 1), 10 * std::numbers::pi / 180 * 1e5, 1e-9);
  EXPECT_NEAR(au(2, 0), -0.5 * std::numbers::pi / 180 * 1e5, 1e-9);
}

TEST(MouthFaps, AClosedJawIsTheNeutralFaceAndOpeningIsMonotonic) {
  Eigen::RowVectorXd jaw(6);
  jaw << -1.0, 0.0, 0.5, 1.0, 2.0, 4.0;
  const Eigen::MatrixXd faps = th::animation::mouthFaps(icMap(), jaw);
  ASSERT_EQ(faps.rows(), 21);
  EXPECT_EQ(faps.col(0).norm(), 0.0);  // FLAME's jaw below 0 is still a closed mouth
  EXPECT_EQ(faps.col(1).norm(), 0.0);
  for (int t = 2; t < 6; ++t) EXPECT_GT(faps(0, t), faps(0, t - 1));
  // Small angles: the chin's drop is nearly linear in the angle (r·θ, bent a little by the chin sitting in
  // front of the pivot, so its path turns backwards as it goes down).
  EXPECT_NEAR(faps(0, 5) / faps(0, 3), 4.0, 0.15);
}

TEST(MouthFaps, AtTheShapesOpeningTheFapsRebuildTheShapesChinAndLips) {
  const Eigen::Matrix3Xd& neutral = ict().neutral.positions;
  const th::face::FapUnits units = th::face::measureFapUnits(ict().points, neutral);
  const std::vector<int> lowerTeeth =
      th::face::movedVertices(neutral, ict().jawOpen, ict().neutral.verticesOf("M_Teeth"));
  const th::face::JawHinge hinge = th::face::fitJawHinge(neutral, ict().jawOpen, lowerTeeth);
  const Eigen::VectorXd follow = th::face::jawFollowWeights(neutral, ict().jawOpen, hinge);
  Eigen::RowVectorXd jaw(1);
  jaw << icMap().shapeAngleDegrees;
  const Eigen::MatrixXd faps = th::animation::mouthFaps(icMap(), jaw);
  const auto moved = [&](const char* id) {
    return (ict().points.position(ict().jawOpen, id) - ict().points.position(neutral, id)).eval();
  };
  // FAP 3: the chin's share of the hinge's motion approximates the artist's chin (which drops a little further
  // and goes back a little less).
  EXPECT_NEAR(valueOf(icMap(), faps, 3, 0) * units.mns, -moved("2.1").y(), 0.15 * -moved("2.1").y());
  // Each lip point's height in the shape = its share of the jaw's motion + its own FAP (signed by the FAP's
  // direction): so jaw and lip FAPs together rebuild the shape's mouth opening exactly.
  const auto heightFromFaps = [&](const char* id, int fap) {
    const int vertex = ict().points.vertices(id).front();
    const Eigen::Vector3d rest = neutral.col(vertex);
    const double carried = follow[vertex] * (hinge.rotate(rest, hinge.shapeAngle) - rest).y();
    return carried + th::face::fapDefinition(fap).direction[1] * valueOf(icMap(), faps, fap, 0) * units.mns;
  };
  const double opening = heightFromFaps("2.2", 4) - heightFromFaps("2.3", 5);
  const double shapeOpening = moved("2.2").y() - moved("2.3").y();
  EXPECT_GT(shapeOpening, 3.0);  // the shape opens the lips by about 3 cm
  EXPECT_NEAR(opening, shapeOpening, 1e-3 * shapeOpening);
  EXPECT_NEAR(heightFromFaps("2.4", 12), moved("2.4").y(), 1e-3);  // a corner, FAP 12
  // Symmetric face, symmetric FAPs.
  EXPECT_NEAR(valueOf(icMap(), faps, 6, 0), valueOf(icMap(), faps, 7, 0), 1.0);
  EXPECT_NEAR(valueOf(icMap(), faps, 10, 0), valueOf(icMap(), faps, 11, 0), 1.0);
}

TEST(JawFollow, TheLowerTeethFollowFullyTheForeheadNotAtAllTheLipsInBetween) {
  const Eigen::Matrix3Xd& neutral = ict().neutral.positions;
  const std::vector<int> lowerTeeth =
      th::face::movedVertices(neutral, ict().jawOpen, ict().neutral.verticesOf("M_Teeth"));
  const th::face::JawHinge hinge = th::face::fitJawHinge(neutral, ict().jawOpen, lowerTeeth);
  const Eigen::VectorXd follow = th::face::jawFollowWeights(neutral, ict().jawOpen, hinge);
  for (int v : lowerTeeth) ASSERT_GT(follow[v], 0.98);
  const auto at = [&](const char* id) { return follow[ict().points.vertices(id).front()]; };
  EXPECT_GT(at("2.3"), 0.8);          // lower lip
  EXPECT_GT(at("2.1"), 0.75);         // chin
  EXPECT_NEAR(at("2.4"), 0.5, 0.15);  // corner
  EXPECT_LT(at("2.2"), 0.15);         // upper lip
  EXPECT_LT(at("4.1"), 0.02);         // eyebrow
  EXPECT_LT(at("9.3"), 0.02);         // nose tip
}

TEST(MouthFapMap, RoundTripsThroughJsonAndRejectsBrokenFields) {
  const nlohmann::json json = th::animation::mouthFapMapJson(icMap());
  const MouthFapMap back = th::animation::mouthFapMapFromJson(json, "m.json");
  EXPECT_TRUE(back.hingeAxis.isApprox(icMap().hingeAxis));
  EXPECT_TRUE(back.chinFromPivot.isApprox(icMap().chinFromPivot));
  EXPECT_EQ(back.lipFaps, icMap().lipFaps);
  EXPECT_TRUE(back.lipPerRadian.isApprox(icMap().lipPerRadian));
  EXPECT_DOUBLE_EQ(back.chinFollow, icMap().chinFollow);

  const auto expectError = [](nlohmann::json broken, const char* text) {
    try {
      th::animation::mouthFapMapFromJson(broken, "m.json");
      ADD_FAILURE() << "accepted " << broken.dump();
    } catch (const th::Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("m.json: ", 0), 0u) << message;
      EXPECT_NE(message.find(text), std::string::npos) << message;
    }
  };
  nlohmann::json broken = json;
  broken["hinge_axis"] = {1, 1, 0};
  expectError(broken, "unit vector");
  broken = json;
  broken["lip_faps_per_radian"]["48"] = 1.0;
  expectError(broken, "not a lip FAP");
  broken = json;
  broken["lip_faps_per_radian"]["x5"] = 1.0;
  expectError(broken, "not a lip FAP");
  broken = json;
  broken.erase("chin_follow");
  expectError(broken, "chin_follow");
  broken = json;
  broken["chin_from_pivot_mns"] = {1, "a", 2};
  expectError(broken, "chin_from_pivot_mns");
}

}  // namespace
