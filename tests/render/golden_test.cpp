// Golden images: the face in its key poses, rendered off-screen, against reference PNGs in tests/render/golden;
// and the two test characters (../shared/data/face/avatars) in the same poses, as `--avatar` draws them.
//
// Tolerance: llvmpipe renders the same scene the same way on the same Mesa, but another CPU (vector width) or
// Mesa version may round differently at edges. A pose passes when the mean absolute difference over all pixels
// and channels is at most 1.5 (of 255) and at most 0.5 % of pixels differ by more than 40 in any channel. Each
// pose is checked to fail that tolerance against the neutral face, so a face that stopped moving fails.
// To remake the references after an intended change: TALKINGHEAD_UPDATE_GOLDEN=1 build/tests/render/golden_test
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "avatar/avatar_model.h"
#include "core/data_path.h"
#include "face/face_model.h"
#include "face/poses.h"
#include "render/animated_avatar.h"
#include "render/animated_face.h"
#include "render/gl_context.h"
#include "render/image.h"

namespace {

constexpr int kSize = 256;
constexpr double kMeanTolerance = 1.5;
constexpr double kOutlierShare = 0.005;
constexpr int kOutlierLevel = 40;

struct Difference {
  double mean = 0.0;
  double outliers = 0.0;  // share of pixels beyond kOutlierLevel
};

Difference compare(const th::render::Image& a, const th::render::Image& b) {
  Difference d;
  if (a.width != b.width || a.height != b.height) return {255.0, 1.0};
  std::size_t outliers = 0;
  double sum = 0.0;
  for (std::size_t p = 0; p < a.pixels.size(); p += 3) {
    int largest = 0;
    for (std::size_t c = 0; c < 3; ++c) {
      const int diff = std::abs(int{a.pixels[p + c]} - int{b.pixels[p + c]});
      sum += diff;
      largest = std::max(largest, diff);
    }
    outliers += largest > kOutlierLevel ? 1 : 0;
  }
  d.mean = sum / static_cast<double>(a.pixels.size());
  d.outliers = static_cast<double>(outliers) / static_cast<double>(a.pixels.size() / 3);
  return d;
}

class Golden : public ::testing::TestWithParam<th::face::Pose> {
 protected:
  struct Scene {
    th::face::FaceModel face = th::face::FaceModel::buildDefault();
    th::render::OffscreenContext context;
    th::render::AnimatedFace animated{face, context, {.width = kSize, .height = kSize}};
    th::render::Image draw(const th::face::FapFrame& faps) { return animated.draw(faps); }
  };
  static Scene& scene() {
    static Scene built;
    return built;
  }
  static std::filesystem::path reference(const std::string& name) {
    return std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "tests" / "render" / "golden" / (name + ".png");
  }
};

TEST_P(Golden, MatchesItsReferenceImage) {
  const th::face::Pose& pose = GetParam();
  const th::render::Image image = scene().draw(pose.faps);
  const char* update = std::getenv("TALKINGHEAD_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    th::render::writePng(reference(pose.name), image);
    GTEST_SKIP() << "rewrote " << reference(pose.name);
  }
  const th::render::Image expected = th::render::readPng(reference(pose.name));
  const Difference d = compare(image, expected);
  EXPECT_LE(d.mean, kMeanTolerance) << pose.name;
  EXPECT_LE(d.outliers, kOutlierShare) << pose.name;
  if (pose.name != "neutral") {
    // The pose must fail the tolerance against the neutral face: the test can tell a face that stopped moving.
    const Difference fromNeutral = compare(image, th::render::readPng(reference("neutral")));
    EXPECT_GT(fromNeutral.outliers, kOutlierShare) << pose.name << " looks like the neutral face";
  }
}

INSTANTIATE_TEST_SUITE_P(Poses, Golden, ::testing::ValuesIn(th::face::goldenPoses()),
                         [](const auto& test) { return test.param.name; });

// A character in a key pose: the references are named CHARACTER_POSE.png.
struct CharacterPose {
  std::string character;  // the file's stem in face/avatars
  th::face::Pose pose;
};

std::vector<CharacterPose> characterPoses() {
  std::vector<CharacterPose> poses;
  for (const std::string character : {"brunette-t", "vroid"})
    for (const th::face::Pose& pose : th::face::goldenPoses()) {
      // The VRoid character's mouth runs on its visemes, which have no smile.
      if (character == "vroid" && pose.name == "smile") continue;
      poses.push_back({character, pose});
    }
  return poses;
}

class GoldenCharacter : public ::testing::TestWithParam<CharacterPose> {
 protected:
  struct Scene {
    th::avatar::Avatar avatar;
    th::render::OffscreenContext context;
    th::render::AnimatedAvatar animated{avatar, context, {.width = kSize, .height = kSize}};
    explicit Scene(const std::string& name)
        : avatar(th::avatar::loadAvatar(th::sharedDataPath("face/avatars/" + name + ".glb"))) {}
  };
  static Scene& scene(const std::string& name) {
    // Never destroyed: a map made before the first scene would be destroyed at exit after Mesa has torn itself
    // down (exit handlers run in reverse), and a renderer's destructor then crashes in OSMesaMakeCurrent.
    static auto& built = *new std::map<std::string, std::unique_ptr<Scene>>;
    std::unique_ptr<Scene>& scene = built[name];
    if (!scene) scene = std::make_unique<Scene>(name);
    return *scene;
  }
  static std::filesystem::path reference(const std::string& name) {
    return std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "tests" / "render" / "golden" / (name + ".png");
  }
};

TEST_P(GoldenCharacter, MatchesItsReferenceImage) {
  const CharacterPose& shown = GetParam();
  const std::string name = shown.character + "_" + shown.pose.name;
  const th::render::Image image = scene(shown.character).animated.draw(shown.pose.faps, nullptr);
  const char* update = std::getenv("TALKINGHEAD_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    th::render::writePng(reference(name), image);
    GTEST_SKIP() << "rewrote " << reference(name);
  }
  const Difference d = compare(image, th::render::readPng(reference(name)));
  EXPECT_LE(d.mean, kMeanTolerance) << name;
  EXPECT_LE(d.outliers, kOutlierShare) << name;
  if (shown.pose.name != "neutral") {
    const Difference fromNeutral = compare(image, th::render::readPng(reference(shown.character + "_neutral")));
    // A character's face is a smaller part of the frame than ours (the VRoid character's mouth opens over about
    // 150 pixels): it must differ from the rest pose over a fifth of the tolerance's share.
    EXPECT_GT(fromNeutral.outliers, kOutlierShare / 5) << name << " looks like the character at rest";
  }
}

INSTANTIATE_TEST_SUITE_P(Characters, GoldenCharacter, ::testing::ValuesIn(characterPoses()), [](const auto& test) {
  std::string name = test.param.character + "_" + test.param.pose.name;
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
});

}  // namespace
