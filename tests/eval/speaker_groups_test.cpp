// Grouping clips by speaker: people who differ are told apart, the coarse cut holds the fine one, bad cuts are
// refused.
#include "eval/speaker_groups.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "core/error.h"

namespace {

// Clips of `people` made-up people: each has a face, a voice and a look, and each clip of them varies a little.
std::vector<th::eval::ClipIdentity> clipsOf(int people, int clipsEach, unsigned seed, std::vector<int>* person) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  std::vector<th::eval::ClipIdentity> out;
  for (int p = 0; p < people; ++p) {
    th::eval::ClipIdentity base;
    base.face = Eigen::VectorXd::NullaryExpr(82, [&] { return 0.05 * normal(random); });
    base.logPitch = std::log(p % 2 == 0 ? 110.0 : 210.0) + 0.1 * normal(random);
    base.spectrum = Eigen::VectorXd::NullaryExpr(11, [&] { return 3.0 * normal(random); });
    base.colours = Eigen::VectorXd::NullaryExpr(27, [&] { return 128.0 + 40.0 * normal(random); });
    for (int c = 0; c < clipsEach; ++c) {
      th::eval::ClipIdentity clip = base;
      clip.face += Eigen::VectorXd::NullaryExpr(82, [&] { return 0.005 * normal(random); });
      clip.logPitch += 0.02 * normal(random);
      clip.spectrum += Eigen::VectorXd::NullaryExpr(11, [&] { return 0.3 * normal(random); });
      clip.colours += Eigen::VectorXd::NullaryExpr(27, [&] { return 4.0 * normal(random); });
      out.push_back(clip);
      person->push_back(p);
    }
  }
  return out;
}

TEST(SpeakerGroups, ClipsOfOnePersonGoTogetherAndPeopleApart) {
  std::vector<int> person;
  const std::vector<th::eval::ClipIdentity> clips = clipsOf(6, 12, 3, &person);
  const th::eval::SpeakerGroups groups = th::eval::groupSpeakers(clips, {.speakers = 6, .families = 2});
  // One group per person: the same person always shares a group, two people never do.
  std::map<int, int> groupOfPerson;
  std::set<int> groupsSeen;
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const auto [at, inserted] = groupOfPerson.emplace(person[i], groups.speaker[i]);
    EXPECT_EQ(at->second, groups.speaker[i]) << "clip " << i;
    if (inserted) {
      EXPECT_TRUE(groupsSeen.insert(groups.speaker[i]).second) << "two people in one group";
    }
  }
  // Every speaker group lies within one family.
  std::map<int, int> familyOfGroup;
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const auto [at, inserted] = familyOfGroup.emplace(groups.speaker[i], groups.family[i]);
    EXPECT_EQ(at->second, groups.family[i]);
  }
  EXPECT_EQ(std::set<int>(groups.family.begin(), groups.family.end()).size(), 2u);
  // The two families are the low and the high voices.
  for (std::size_t i = 0; i < clips.size(); ++i) {
    EXPECT_EQ(groups.family[i] == groups.family[0], person[i] % 2 == person[0] % 2) << "clip " << i;
  }
}

TEST(SpeakerGroups, AClipWithoutPitchTakesTheMedianAndBadCutsAreRefused) {
  std::vector<int> person;
  std::vector<th::eval::ClipIdentity> clips = clipsOf(3, 5, 4, &person);
  clips[2].logPitch = std::nan("");
  const th::eval::SpeakerGroups groups = th::eval::groupSpeakers(clips, {.speakers = 3, .families = 1});
  EXPECT_EQ(groups.speaker.size(), clips.size());
  EXPECT_EQ(std::set<int>(groups.family.begin(), groups.family.end()).size(), 1u);
  EXPECT_THROW(th::eval::groupSpeakers(clips, {.speakers = 2, .families = 3}), th::Error);
  EXPECT_THROW(th::eval::groupSpeakers(clips, {.speakers = 16, .families = 1}), th::Error);
}

}  // namespace
