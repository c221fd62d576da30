// th_animation_write_avatar through libtalkinghead (the shared library, as a C program calls it): a recording
// animated, written onto both test characters in both forms, and read back with tinygltf; bad arguments fail
// with a status and a message naming the file, leaving no file.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>

#include "core/data_path.h"
#include "core/temporary_file.h"
#include "talkinghead/talkinghead.h"

namespace {

namespace fs = std::filesystem;

tinygltf::Model loadGltf(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                           void*) { return true; },
                        nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const bool ok = path.extension() == ".gltf" ? loader.LoadASCIIFromFile(&model, &error, &warning, path.string())
                                              : loader.LoadBinaryFromFile(&model, &error, &warning, path.string());
  if (!ok) throw std::runtime_error(path.string() + ": tinygltf: " + error);
  return model;
}

class LibraryAvatarAnimation : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    th_models* models = nullptr;
    ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
    th_animation* made = nullptr;
    const th_status animated =
        th_animate(models, th::sharedDataPath("speech/arctic/arctic_a0001.wav").c_str(), nullptr, &made);
    th_models_free(models);
    ASSERT_EQ(animated, TH_OK) << th_last_error();
    animation_ = made;
  }
  static void TearDownTestSuite() {
    th_animation_free(animation_);
    animation_ = nullptr;
  }
  static std::string avatar(const char* name) { return th::sharedDataPath("face/avatars").string() + "/" + name; }

  static th_animation* animation_;
  th::TemporaryFolder folder;
};

th_animation* LibraryAvatarAnimation::animation_ = nullptr;

TEST_F(LibraryAvatarAnimation, BothFormsOnBothCharactersReadBack) {
  const int frames = th_animation_frames(animation_);
  ASSERT_GT(frames, 30);
  for (const char* name : {"brunette-t.glb", "vroid.glb"}) {
    for (const auto& [file, only] : {std::pair{"talk.glb", 0}, std::pair{"animation.gltf", 1}}) {
      const fs::path out = folder.path() / file;
      ASSERT_EQ(th_animation_write_avatar(animation_, avatar(name).c_str(), out.c_str(), only), TH_OK)
          << th_last_error();
      const tinygltf::Model model = loadGltf(out);
      ASSERT_EQ(model.animations.size(), 1u) << name << " " << file;
      const tinygltf::Animation& speech = model.animations.front();
      EXPECT_EQ(speech.name, "speech");
      int weights = 0, rotations = 0;
      for (const tinygltf::AnimationChannel& channel : speech.channels) {
        weights += channel.target_path == "weights";
        rotations += channel.target_path == "rotation";
        const tinygltf::Accessor& input =
            model.accessors[static_cast<std::size_t>(speech.samplers[static_cast<std::size_t>(channel.sampler)].input)];
        EXPECT_EQ(input.count, static_cast<std::size_t>(frames));
        ASSERT_EQ(input.maxValues.size(), 1u);
        EXPECT_NEAR(input.maxValues[0], (frames - 1) / 30.0, 1e-5);
      }
      EXPECT_GE(weights, 1) << name;
      EXPECT_GE(rotations, 2) << name;  // neck and head
      EXPECT_EQ(model.skins.empty(), only != 0) << name << " " << file;
    }
  }
}

TEST_F(LibraryAvatarAnimation, FailuresNameTheFileAndLeaveNoFile) {
  const fs::path out = folder.path() / "never.glb";
  EXPECT_EQ(th_animation_write_avatar(animation_, (folder.path() / "missing.glb").c_str(), out.c_str(), 0),
            TH_ERROR_FILE);
  EXPECT_NE(std::string(th_last_error()).find("missing.glb"), std::string::npos) << th_last_error();
  EXPECT_EQ(
      th_animation_write_avatar(animation_, avatar("brunette-t.glb").c_str(), (folder.path() / "never.csv").c_str(), 0),
      TH_ERROR_FILE);
  EXPECT_NE(std::string(th_last_error()).find("never.csv"), std::string::npos) << th_last_error();
  EXPECT_EQ(th_animation_write_avatar(nullptr, avatar("brunette-t.glb").c_str(), out.c_str(), 0), TH_ERROR_ARGUMENT);
  EXPECT_EQ(th_animation_write_avatar(animation_, nullptr, out.c_str(), 0), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(fs::is_empty(folder.path()));
}

}  // namespace
