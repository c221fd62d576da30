// ARKit blendshape weights from FAPs.
#include "formats/arkit_format.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <string>

#include "core/error.h"
#include "core/temporary_file.h"
#include "face/face_model.h"

namespace {

using Animation = th::face::FapTrack;

double weight(const Eigen::MatrixXd& weights, int frame, std::string_view name) {
  for (std::size_t i = 0; i < th::formats::kArkitNames.size(); ++i)
    if (th::formats::kArkitNames[i] == name) return weights(static_cast<Eigen::Index>(i), frame);
  ADD_FAILURE() << name;
  return -1;
}

Animation oneFrame(std::vector<int> faps, std::vector<double> values) {
  Animation anim;
  anim.faps = std::move(faps);
  anim.values = Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));  // one frame
  return anim;
}

TEST(Arkit, FiftyTwoDistinctNames) {
  const std::set<std::string_view> names(th::formats::kArkitNames.begin(), th::formats::kArkitNames.end());
  EXPECT_EQ(names.size(), 52u);
}

TEST(Arkit, EachSideAndDirectionFeedsItsOwnShape) {
  // Left lid half closed, left eye to the face's left, right eye to the face's left too, jaw to the right.
  const Animation anim = oneFrame({15, 19, 23, 24}, {100, 512, 17453, 17453});
  const Eigen::MatrixXd w = th::formats::arkitWeights(anim);
  EXPECT_DOUBLE_EQ(weight(w, 0, "eyeBlinkLeft"), 0.5);
  EXPECT_DOUBLE_EQ(weight(w, 0, "eyeBlinkRight"), 0.0);
  EXPECT_NEAR(weight(w, 0, "eyeLookOutLeft"), 1.0 / 3.0, 1e-3);  // 10° of 30°
  EXPECT_DOUBLE_EQ(weight(w, 0, "eyeLookInLeft"), 0.0);
  EXPECT_NEAR(weight(w, 0, "eyeLookInRight"), 1.0 / 3.0, 1e-3);
  EXPECT_DOUBLE_EQ(weight(w, 0, "eyeLookOutRight"), 0.0);
  EXPECT_DOUBLE_EQ(weight(w, 0, "jawRight"), 0.5);
  EXPECT_DOUBLE_EQ(weight(w, 0, "jawLeft"), 0.0);
  EXPECT_DOUBLE_EQ(weight(w, 0, "tongueOut"), 0.0);
}

TEST(Arkit, SymmetricLipsNeitherShiftTheMouthNorTellLeftFromRight) {
  const Animation anim = oneFrame({6, 7, 12, 13, 53, 54, 59, 60}, {150, 150, 300, 300, 150, 150, 300, 300});
  const Eigen::MatrixXd w = th::formats::arkitWeights(anim);
  EXPECT_DOUBLE_EQ(weight(w, 0, "mouthLeft"), 0.0);
  EXPECT_DOUBLE_EQ(weight(w, 0, "mouthRight"), 0.0);
  EXPECT_DOUBLE_EQ(weight(w, 0, "mouthSmileLeft"), 1.0);
  EXPECT_DOUBLE_EQ(weight(w, 0, "mouthSmileRight"), 1.0);
  EXPECT_DOUBLE_EQ(weight(w, 0, "mouthStretchLeft"), 0.5);
  EXPECT_DOUBLE_EQ(weight(w, 0, "mouthFrownLeft"), 0.0);
  EXPECT_DOUBLE_EQ(weight(w, 0, "mouthPucker"), 0.0);
}

TEST(Arkit, TheLipsRollAndFunnelAsTheirFapsShapeThem) {
  const th::formats::ArkitScale scale;
  // At rest: none of them.
  const Eigen::MatrixXd rest = th::formats::arkitWeights(oneFrame({3, 4, 5, 51, 52}, {0, 0, 0, 0, 0}), scale);
  for (const char* name : {"mouthRollLower", "mouthRollUpper", "mouthFunnel"})
    EXPECT_EQ(weight(rest, 0, name), 0.0) << name;
  // /p b m/: both lips close, neither rolled, no funnel.
  const Eigen::MatrixXd closed =
      th::formats::arkitWeights(oneFrame({3, 4, 5, 51, 52}, {300, 120, 120, 120, 120}), scale);
  EXPECT_GT(weight(closed, 0, "mouthClose"), 0.3);
  EXPECT_EQ(weight(closed, 0, "mouthRollLower"), 0.0);
  EXPECT_EQ(weight(closed, 0, "mouthRollUpper"), 0.0);
  EXPECT_EQ(weight(closed, 0, "mouthFunnel"), 0.0);
  // /f v/: the lower lip raised to the upper teeth rolls in.
  const Eigen::MatrixXd lower = th::formats::arkitWeights(oneFrame({3, 5, 52}, {200, 150, 150}), scale);
  EXPECT_GT(weight(lower, 0, "mouthRollLower"), 0.4);
  EXPECT_EQ(weight(lower, 0, "mouthRollUpper"), 0.0);
  // /u o/: the corners drawn in with the lips apart make a funnel; drawn in and shut, a pucker alone.
  const Eigen::MatrixXd round =
      th::formats::arkitWeights(oneFrame({3, 6, 7, 53, 54}, {500, -90, -90, -90, -90}), scale);
  EXPECT_GT(weight(round, 0, "mouthFunnel"), 0.2);
  EXPECT_GT(weight(round, 0, "mouthPucker"), 0.2);
  const Eigen::MatrixXd kiss = th::formats::arkitWeights(oneFrame({6, 7, 53, 54}, {-90, -90, -90, -90}), scale);
  EXPECT_EQ(weight(kiss, 0, "mouthFunnel"), 0.0);
  EXPECT_GT(weight(kiss, 0, "mouthPucker"), 0.2);
}

TEST(Arkit, JawOpenIsFullAtTheReferenceFacesJawOpenShape) {
  const th::face::FaceModel face = th::face::FaceModel::buildDefault();
  const th::formats::ArkitScale scale = th::formats::arkitScaleFor(face);
  EXPECT_NEAR(face.jawAngleFor(scale.jawOpen), face.jaw().shapeAngle, 1e-6);
  const Animation anim = oneFrame({3}, {0.5 * scale.jawOpen});
  EXPECT_NEAR(weight(th::formats::arkitWeights(anim, scale), 0, "jawOpen"), 0.5, 1e-9);
}

TEST(Arkit, CsvHasTimeAndTheFiftyTwoNames) {
  const th::TemporaryFolder folder;
  Animation anim = oneFrame({19}, {1024});
  anim.values.conservativeResize(1, 2);
  anim.values(0, 1) = 0.0;
  th::formats::writeAnimation(folder.path() / "a.csv", anim, th::formats::arkitFormat());
  std::ifstream in(folder.path() / "a.csv");
  std::string header, first, second;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  EXPECT_EQ(header.rfind("time_s,eyeBlinkLeft,eyeLookDownLeft,", 0), 0u) << header;
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), 52);
  EXPECT_EQ(first.rfind("0.000000,1.0000,", 0), 0u) << first;
  EXPECT_EQ(second.rfind("0.033333,0.0000,", 0), 0u) << second;
  EXPECT_THROW(th::formats::writeAnimation(folder.path() / "missing" / "a.csv", anim, th::formats::arkitFormat()),
               th::Error);
}

}  // namespace
