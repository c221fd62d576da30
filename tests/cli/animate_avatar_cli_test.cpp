// `talkinghead animate IN -o OUT.glb --avatar FILE` as a user meets it: the character with the speech as its
// glTF animation, or (--animation-only) the animation alone, read back with tinygltf; and the ways it is asked
// wrongly, each refused in one line naming the file, with no file left.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "cli_runner.h"
#include "core/data_path.h"
#include "support/files.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::runCli;

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

class AnimateAvatarCli : public th::test::CliTest {
 protected:
  static fs::path speech() { return th::sharedDataPath("speech/arctic/arctic_a0001.wav"); }  // 3.355 s
  static fs::path character(const char* name) { return th::sharedDataPath("face/avatars") / name; }
};

TEST_F(AnimateAvatarCli, TheCharacterAndTheAnimationAloneCarryTheSpeech) {
  const th::audio::AudioClip clip = th::audio::readAudioFile(speech());
  const double seconds = static_cast<double>(clip.samples.size()) / clip.sampleRateHz;
  for (const char* name : {"brunette-t.glb", "vroid.glb"}) {
    for (const auto& [file, only] : {std::pair{"talk.glb", false}, std::pair{"animation.gltf", true}}) {
      const fs::path out = this->out() / (fs::path(name).stem().string() + "-" + file);
      std::vector<std::string> arguments{"animate",    speech().string(), "-o",
                                         out.string(), "--avatar",        character(name).string()};
      if (only) arguments.emplace_back("--animation-only");
      const CliResult result = runCli(arguments, logs());
      ASSERT_EQ(result.exitCode, 0) << result.err;
      // The character's scheme on stderr, as export --avatar says it.
      EXPECT_NE(result.err.find(fs::path(name).stem().string() +
                                (std::string(name) == "vroid.glb" ? ": Oculus visemes" : ": ARKit blendshapes")),
                std::string::npos)
          << result.err;
      EXPECT_NE(result.out.find("wrote " + out.string()), std::string::npos) << result.out;

      const tinygltf::Model model = loadGltf(out);
      ASSERT_EQ(model.animations.size(), 1u) << out;
      const tinygltf::Animation& animation = model.animations.front();
      int weights = 0, rotations = 0;
      for (const tinygltf::AnimationChannel& channel : animation.channels) {
        weights += channel.target_path == "weights";
        rotations += channel.target_path == "rotation";
        const tinygltf::Accessor& input = model.accessors[static_cast<std::size_t>(
            animation.samplers[static_cast<std::size_t>(channel.sampler)].input)];
        // Frames i/30 s over the recording: the last one within a frame of its end.
        ASSERT_EQ(input.maxValues.size(), 1u);
        EXPECT_NEAR(input.maxValues[0], (static_cast<double>(input.count) - 1.0) / 30.0, 1e-5);
        EXPECT_NEAR(input.maxValues[0], seconds, 2.0 / 30.0) << out;
      }
      EXPECT_GE(weights, 1) << out;
      EXPECT_GE(rotations, 2) << out;  // neck and head
      EXPECT_EQ(model.skins.empty(), only) << out;
      EXPECT_EQ(model.materials.empty(), only) << out;
    }
  }
}

TEST_F(AnimateAvatarCli, WrongRequestsFailInOneLineAndLeaveNoFile) {
  const std::string wav = speech().string(), brunette = character("brunette-t.glb").string();
  const std::string glb = (out() / "x.glb").string(), csv = (out() / "x.csv").string();
  expectOneLineFailure(runCli({"animate", wav, "-o", glb}, logs()), glb,
                       "a glTF animation moves a character: give --avatar FILE");
  expectOneLineFailure(runCli({"animate", wav, "-o", csv, "--avatar", brunette}, logs()), csv,
                       "a character's animation is glTF");
  expectOneLineFailure(runCli({"animate", wav, "-o", csv, "--animation-only"}, logs()), csv, "--avatar FILE");
  const std::string vrm = (out() / "x.vrm").string();
  expectOneLineFailure(runCli({"animate", wav, "-o", vrm, "--avatar", brunette, "--animation-only"}, logs()), vrm,
                       ".glb or .gltf");
  expectOneLineFailure(runCli({"animate", wav, "-o", vrm, "--avatar", brunette}, logs()), vrm, "from a VRM character");
  expectOneLineFailure(runCli({"animate", wav, "-o", glb, "--avatar", brunette, "--format", "csv"}, logs()), glb,
                       "--format is for the other formats");
  // A file that is not a character.
  const fs::path text = folder_.path() / "notes.glb";
  std::ofstream(text) << "not a character\n";
  expectOneLineFailure(runCli({"animate", wav, "-o", glb, "--avatar", text.string()}, logs()), text.string(),
                       "not a glTF file");
  EXPECT_TRUE(outFolderIsEmpty());
}

}  // namespace
