// The reference face's geometry: feature points, FAP units and the jaw hinge measured on ICT FaceKit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "core/error.h"
#include "core/temporary_file.h"
#include "face/fap.h"
#include "face/feature_points.h"
#include "face/jaw.h"

namespace {

using th::face::FaceAssets;

const FaceAssets& ict() {
  static const FaceAssets face = th::face::loadIctFace(th::face::ictFaceDirectory());
  return face;
}

TEST(FapTable, NamesUnitsAndDirectionsFollowTheStandard) {
  EXPECT_EQ(th::face::fapDefinition(3).name, "open_jaw");
  EXPECT_EQ(th::face::fapDefinition(3).unit, th::face::Fapu::kMns);
  EXPECT_FALSE(th::face::fapDefinition(3).bidirectional);
  EXPECT_EQ(th::face::fapDefinition(3).direction[1], -1.0);
  EXPECT_EQ(th::face::fapDefinition(6).direction[0], 1.0);  // stretch_l_cornerlip: to the face's left
  EXPECT_EQ(th::face::fapDefinition(7).direction[0], -1.0);
  EXPECT_EQ(th::face::fapDefinition(37).direction[0], -1.0);  // squeeze_l_eyebrow: towards the middle
  EXPECT_EQ(th::face::fapDefinition(48).unit, th::face::Fapu::kAngle);
  EXPECT_EQ(th::face::fapNumber("head_yaw"), 49);
  EXPECT_EQ(th::face::fapNumber("raise_r_cornerlip_o"), 60);
  EXPECT_EQ(th::face::fapNumber("no_such_fap"), 0);
  EXPECT_THROW(th::face::fapDefinition(0), th::Error);
  EXPECT_THROW(th::face::fapDefinition(69), th::Error);
  for (int n = 3; n <= th::face::kNumFaps; ++n) {
    const auto& fap = th::face::fapDefinition(n);
    const double length = std::hypot(fap.direction[0], fap.direction[1], fap.direction[2]);
    if (n == 29 || n == 30 || n == 47)
      EXPECT_EQ(length, 0.0) << n;  // pupil size, tongue roll: no direction
    else
      EXPECT_DOUBLE_EQ(length, 1.0) << n;
  }
}

TEST(IctFace, FeaturePointsSitWhereTheirNamesSay) {
  const Eigen::Matrix3Xd& p = ict().neutral.positions;
  const auto at = [&](const char* id) { return ict().points.position(p, id); };
  EXPECT_GT(at("3.5").x(), 0.0);  // left pupil on the face's left (+x)
  EXPECT_LT(at("3.6").x(), 0.0);
  EXPECT_GT(at("8.3").x(), at("8.4").x());
  EXPECT_GT(at("2.2").y(), at("2.3").y() - 0.2);  // the mouth is closed: inner lips (nearly) touch
  EXPECT_LT(at("2.1").y(), at("8.2").y());        // chin below the lower lip
  EXPECT_GT(at("9.15").y(), at("2.2").y());       // nose above the mouth
  EXPECT_GT(at("3.1").y(), at("3.3").y());        // upper lid above lower lid
}

TEST(IctFace, FapUnitsAreTheNeutralFacesDistancesOver1024) {
  const th::face::FapUnits units = th::face::measureFapUnits(ict().points, ict().neutral.positions);
  // The ICT head is in centimetres: eyes about 6.3 cm apart, mouth about 5 cm wide (a human face).
  EXPECT_NEAR(units.es * 1024, 6.3, 0.5);
  EXPECT_NEAR(units.mw * 1024, 5.06, 0.1);
  EXPECT_GT(units.mns * 1024, 1.0);
  EXPECT_LT(units.mns * 1024, 3.0);
  EXPECT_GT(units.ens * 1024, units.mns * 1024);
  EXPECT_GT(units.irisd * 1024, 0.5);
  EXPECT_LT(units.irisd * 1024, 1.6);
}

TEST(JawHinge, TheLowerTeethOfTheJawOpenShapeTurnRigidlyAboutAHingeInFrontOfTheEar) {
  const Eigen::Matrix3Xd& neutral = ict().neutral.positions;
  const std::vector<int> teeth = ict().neutral.verticesOf("M_Teeth");
  const std::vector<int> lower = th::face::movedVertices(neutral, ict().jawOpen, teeth);
  ASSERT_GT(lower.size(), 100u);
  EXPECT_LT(lower.size(), teeth.size());  // the upper teeth stay
  const th::face::JawHinge hinge = th::face::fitJawHinge(neutral, ict().jawOpen, lower);
  EXPECT_LT(hinge.rmsResidual, 0.05);         // rigid to half a millimetre
  EXPECT_GT(std::abs(hinge.axis.x()), 0.95);  // a left-right axis
  const Eigen::Vector3d chin = ict().points.position(neutral, "2.1");
  EXPECT_GT(hinge.pivot.y(), chin.y() + 4.0);  // above and behind the chin, towards the ear
  EXPECT_LT(hinge.pivot.z(), chin.z() - 4.0);
  // The chin is skin over the bone: in the shape it goes the bone's way, a little less far (it stretches).
  const Eigen::Vector3d skin = ict().points.position(ict().jawOpen, "2.1") - chin;
  const Eigen::Vector3d bone = hinge.rotate(chin, hinge.shapeAngle) - chin;
  EXPECT_GT(skin.normalized().dot(bone.normalized()), 0.98);
  EXPECT_GT(skin.norm(), 0.7 * bone.norm());
  EXPECT_LT(skin.norm(), bone.norm());
  // A positive angle opens: the chin goes down.
  EXPECT_LT(hinge.rotate(chin, 0.1).y(), chin.y());
}

TEST(JawHinge, ATranslationAloneIsNotAHinge) {
  Eigen::Matrix3Xd from(3, 4);
  from << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3Xd to = from.colwise() + Eigen::Vector3d(0, -1, 0);
  EXPECT_THROW(th::face::fitJawHinge(from, to, {0, 1, 2, 3}), th::Error);
}

TEST(IctFace, MissingOrBrokenAssetsAreOneLineErrorsNamingTheFile) {
  const th::TemporaryFolder folder;  // unique: two test runs at once do not share it
  const std::filesystem::path& dir = folder.path();
  try {
    th::face::loadIctFace(dir);
    FAIL();
  } catch (const th::Error& e) {
    EXPECT_NE(std::string(e.what()).find("generic_neutral_mesh.obj"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "generic_neutral_mesh.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir / "jawOpen.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 2\n";
  try {
    th::face::loadIctFace(dir);
    FAIL();
  } catch (const th::Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("jawOpen.obj"), std::string::npos) << message;
    EXPECT_NE(message.find("2 vertices"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

}  // namespace
