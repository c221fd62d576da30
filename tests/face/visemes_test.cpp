// The viseme sets and the phone map.
#include "face/visemes.h"

#include <gtest/gtest.h>

#include <set>

namespace {

using namespace th::face;

TEST(Visemes, PhonesMapWithStressAndCaseIgnored) {
  EXPECT_EQ(mouthClassOfPhone("AH0"), kAh);
  EXPECT_EQ(mouthClassOfPhone("ah1"), kAh);
  EXPECT_EQ(mouthClassOfPhone("IY2"), kIh);
  EXPECT_EQ(mouthClassOfPhone("B"), kPp);
  EXPECT_EQ(mouthClassOfPhone("SIL"), kSilence);
  EXPECT_EQ(mouthClassOfPhone(""), kSilence);
  EXPECT_EQ(mouthClassOfPhone("hello"), -1);
  EXPECT_EQ(mouthClassOfPhone("Q"), -1);
}

TEST(Visemes, EveryArpabetPhoneHasAClass) {
  for (const char* phone : {"AA", "AE", "AH", "AO", "AW", "AY", "B",  "CH", "D", "DH", "EH", "ER", "EY",
                            "F",  "G",  "HH", "IH", "IY", "JH", "K",  "L",  "M", "N",  "NG", "OW", "OY",
                            "P",  "R",  "S",  "SH", "T",  "TH", "UH", "UW", "V", "W",  "Y",  "Z",  "ZH"})
    EXPECT_GE(mouthClassOfPhone(phone), 1) << phone;
}

TEST(Visemes, EachSetIsAFunctionOfTheClassesAndCoversItself) {
  std::set<int> oculus;
  std::set<char> rhubarb;
  for (int c = 0; c < kNumMouthClasses; ++c) {
    oculus.insert(oculusVisemeOf(c));
    rhubarb.insert(rhubarbShapeOf(c));
  }
  EXPECT_EQ(oculus.size(), static_cast<std::size_t>(kNumOculusVisemes));
  EXPECT_EQ(rhubarb.size(), kRhubarbShapes.size());
  EXPECT_EQ(kOculusVisemeNames[static_cast<std::size_t>(oculusVisemeOf(kL))], "nn");
  EXPECT_EQ(kOculusVisemeNames[static_cast<std::size_t>(oculusVisemeOf(kAh))], "aa");
  EXPECT_EQ(rhubarbShapeOf(kPp), 'A');
  EXPECT_EQ(rhubarbShapeOf(kFf), 'G');
  EXPECT_EQ(rhubarbShapeOf(kL), 'H');
  EXPECT_EQ(rhubarbShapeOf(kSilence), 'X');
  EXPECT_EQ(rhubarbShapeOf(kAa), 'D');
  EXPECT_EQ(rhubarbShapeOf(kOu), 'F');
}

TEST(Visemes, WeightsFollowTheProbabilities) {
  Eigen::VectorXd p = Eigen::VectorXd::Zero(kNumMouthClasses);
  p[kAa] = 0.5;
  p[kAh] = 0.25;
  p[kL] = 0.25;
  const Eigen::VectorXd oculus = oculusWeights(p);
  EXPECT_NEAR(oculus.sum(), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(oculus[10], 0.75);  // aa
  EXPECT_DOUBLE_EQ(oculus[8], 0.25);   // nn
  const Eigen::VectorXd vrm = vrmWeights(p);
  EXPECT_GT(vrm[0], 0.7);         // A
  EXPECT_DOUBLE_EQ(vrm[2], 0.0);  // U
  Eigen::VectorXd silence = Eigen::VectorXd::Zero(kNumMouthClasses);
  silence[kSilence] = 1.0;
  EXPECT_EQ(vrmWeights(silence).sum(), 0.0);
}

TEST(Visemes, RunsOfEqualValues) {
  const std::vector<th::face::Run> runs = runsOf({3, 3, 1, 1, 1, 3});
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].length, 2);
  EXPECT_EQ(runs[1].first, 2);
  EXPECT_EQ(runs[1].length, 3);
  EXPECT_EQ(runs[2].value, 3);
  EXPECT_TRUE(runsOf({}).empty());
}

}  // namespace
