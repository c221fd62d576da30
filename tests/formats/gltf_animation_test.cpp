// glTF animation: written into the real avatars (Ready Player Me's brunette-t.glb, VRoid's vroid.glb) and as the
// animation alone, as .glb and .gltf; tinygltf reads back the animation exactly as written (times, weights in
// frame-major order, rotations on one hemisphere) and the avatar's meshes, materials, skins and textures unchanged
// in number; bad avatars, bad tracks and unwritable outputs are refused with one line naming the file, leaving no
// file behind.
#include "formats/gltf_animation.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "formats/gltf_test_tracks.h"
#include "support/files.h"

namespace th::formats {
namespace {

namespace fs = std::filesystem;
using test::countOf;
using test::glbJson;
using test::loadGltf;
using test::speechTracks;
using th::test::expectFileError;
using th::test::listFolder;

std::string errorOf(const std::function<void()>& run) {
  try {
    run();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// The floats of an accessor (tightly packed or strided).
std::vector<float> floatsOf(const tinygltf::Model& model, int index) {
  const auto& accessor = model.accessors.at(index);
  EXPECT_EQ(accessor.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const auto& view = model.bufferViews.at(accessor.bufferView);
  const auto& buffer = model.buffers.at(view.buffer);
  const int components = tinygltf::GetNumComponentsInType(accessor.type);
  const std::size_t stride = view.byteStride ? view.byteStride : components * sizeof(float);
  std::vector<float> values;
  for (std::size_t i = 0; i < accessor.count; ++i)
    for (int c = 0; c < components; ++c) {
      float value;
      std::memcpy(&value, buffer.data.data() + view.byteOffset + accessor.byteOffset + i * stride + c * sizeof(float),
                  sizeof(float));
      values.push_back(value);
    }
  return values;
}

std::size_t animationChannels(const GltfAnimationTracks& tracks) {
  return tracks.morphs.size() + tracks.rotations.size();
}

struct Case {
  const char* avatar;
  const char* extension;
};

class GltfAnimationWrite : public ::testing::TestWithParam<Case> {};

TEST_P(GltfAnimationWrite, AvatarReadsBackWithTheAnimationAndEverythingElse) {
  const fs::path avatar = sharedDataPath(std::string("face/avatars/") + GetParam().avatar);
  const nlohmann::json original = glbJson(avatar);
  const GltfAvatar avatarNodes = readGltfAvatar(avatar);
  const GltfAnimationTracks tracks = speechTracks(avatarNodes);
  ASSERT_FALSE(tracks.morphs.empty()) << "no meshes with morph targets in " << avatar;
  ASSERT_EQ(tracks.rotations.size(), 1u) << "no Head node in " << avatar;
  ASSERT_GE(avatarNodes.findNode("Neck"), 0);

  TemporaryFolder folder;
  const fs::path out = folder.path() / (std::string("talk") + GetParam().extension);
  writeAvatarAnimation(avatar, tracks, out);
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{out.filename().string()});
  const tinygltf::Model written = loadGltf(out);

  EXPECT_EQ(written.meshes.size(), countOf(original, "meshes"));
  EXPECT_EQ(written.materials.size(), countOf(original, "materials"));
  EXPECT_EQ(written.skins.size(), countOf(original, "skins"));
  EXPECT_EQ(written.textures.size(), countOf(original, "textures"));
  EXPECT_EQ(written.images.size(), countOf(original, "images"));
  EXPECT_EQ(written.nodes.size(), countOf(original, "nodes"));
  EXPECT_EQ(written.accessors.size(), countOf(original, "accessors") + 1 + animationChannels(tracks));
  EXPECT_EQ(written.buffers.size(), 1u);
  for (std::size_t i = 0; i < written.images.size(); ++i) {
    EXPECT_GE(written.images[i].bufferView, 0) << "image " << i;
    EXPECT_EQ(written.images[i].mimeType, original["images"][i]["mimeType"]) << "image " << i;
  }
  for (std::size_t m = 0; m < written.meshes.size(); ++m) {
    const auto& primitives = original["meshes"][m]["primitives"];
    ASSERT_EQ(written.meshes[m].primitives.size(), primitives.size());
    for (std::size_t p = 0; p < primitives.size(); ++p)
      EXPECT_EQ(written.meshes[m].primitives[p].targets.size(), countOf(primitives[p], "targets"));
  }
  // Extensions the written file still needs (meshopt's is decoded away).
  for (const auto& name : original.value("extensionsUsed", nlohmann::json::array())) {
    if (name == "EXT_meshopt_compression") continue;
    EXPECT_NE(std::find(written.extensionsUsed.begin(), written.extensionsUsed.end(), name),
              written.extensionsUsed.end())
        << name;
  }
  ASSERT_EQ(written.animations.size(), countOf(original, "animations") + 1);
  const auto& animation = written.animations.back();
  EXPECT_EQ(animation.name, "speech");
  ASSERT_EQ(animation.channels.size(), tracks.morphs.size() + tracks.rotations.size());
  ASSERT_EQ(animation.samplers.size(), animation.channels.size());

  const int frames = 60;
  for (std::size_t c = 0; c < animation.channels.size(); ++c) {
    const auto& channel = animation.channels[c];
    const auto& sampler = animation.samplers.at(channel.sampler);
    EXPECT_EQ(sampler.interpolation, "LINEAR");
    const auto& input = written.accessors.at(sampler.input);
    ASSERT_EQ(input.minValues.size(), 1u);
    ASSERT_EQ(input.maxValues.size(), 1u);
    EXPECT_EQ(input.minValues[0], 0.0);
    EXPECT_FLOAT_EQ(static_cast<float>(input.maxValues[0]), (frames - 1) / 30.0f);
    const auto times = floatsOf(written, sampler.input);
    ASSERT_EQ(times.size(), static_cast<std::size_t>(frames));
    for (int i = 0; i < frames; ++i) EXPECT_FLOAT_EQ(times[i], static_cast<float>(i / 30.0));
    const auto output = floatsOf(written, sampler.output);

    if (c < tracks.morphs.size()) {
      const auto& track = tracks.morphs[c];
      EXPECT_EQ(channel.target_path, "weights");
      EXPECT_EQ(channel.target_node, track.node);
      const auto rows = track.weights.rows();
      ASSERT_EQ(output.size(), static_cast<std::size_t>(rows * frames));
      for (int t = 0; t < frames; ++t)
        for (Eigen::Index k = 0; k < rows; ++k) ASSERT_EQ(output[t * rows + k], track.weights(k, t)) << t << " " << k;
    } else {
      const auto& track = tracks.rotations[c - tracks.morphs.size()];
      EXPECT_EQ(channel.target_path, "rotation");
      EXPECT_EQ(channel.target_node, track.node);
      ASSERT_EQ(written.accessors.at(sampler.output).type, TINYGLTF_TYPE_VEC4);
      ASSERT_EQ(output.size(), 4u * frames);
      for (int t = 0; t < frames; ++t) {
        const Eigen::Vector4f read(output[4 * t], output[4 * t + 1], output[4 * t + 2], output[4 * t + 3]);
        const Eigen::Vector4f given = track.rotations[t].coeffs().normalized();
        EXPECT_NEAR(read.norm(), 1.0f, 1e-6f);
        // The same rotation (q or -q), on the same side as the frame before.
        EXPECT_NEAR(std::abs(read.dot(given)), 1.0f, 1e-6f) << "frame " << t;
        if (t > 0) {
          const Eigen::Vector4f before(output[4 * t - 4], output[4 * t - 3], output[4 * t - 2], output[4 * t - 1]);
          EXPECT_GT(read.dot(before), 0.0f) << "frame " << t;
        }
      }
    }
  }
}

TEST_P(GltfAnimationWrite, AnimationOnlyHasTheHierarchyTargetNamesAndTheAnimation) {
  const fs::path avatar = sharedDataPath(std::string("face/avatars/") + GetParam().avatar);
  const nlohmann::json original = glbJson(avatar);
  const GltfAnimationTracks tracks = speechTracks(readGltfAvatar(avatar));

  TemporaryFolder folder;
  const fs::path out = folder.path() / (std::string("talk-animation") + GetParam().extension);
  writeAnimationOnly(avatar, tracks, out);
  const tinygltf::Model written = loadGltf(out);

  ASSERT_EQ(written.nodes.size(), countOf(original, "nodes"));
  for (std::size_t i = 0; i < written.nodes.size(); ++i) {
    const auto& node = original["nodes"][i];
    EXPECT_EQ(written.nodes[i].name, node.value("name", std::string()));
    EXPECT_EQ(written.nodes[i].children, node.value("children", std::vector<int>{}));
    EXPECT_EQ(written.nodes[i].translation, node.value("translation", std::vector<double>{}));
    EXPECT_EQ(written.nodes[i].rotation, node.value("rotation", std::vector<double>{}));
    EXPECT_EQ(written.nodes[i].scale, node.value("scale", std::vector<double>{}));
  }
  EXPECT_TRUE(written.skins.empty());
  EXPECT_TRUE(written.materials.empty());
  EXPECT_TRUE(written.images.empty());
  EXPECT_EQ(written.meshes.size(), tracks.morphs.size());
  for (const auto& track : tracks.morphs) {
    const int mesh = written.nodes[track.node].mesh;
    ASSERT_GE(mesh, 0);
    const auto& from = original["meshes"][original["nodes"][track.node]["mesh"].get<int>()];
    EXPECT_EQ(written.meshes[mesh].name, from.value("name", std::string()));
    ASSERT_EQ(written.meshes[mesh].primitives.size(), 1u);
    EXPECT_EQ(static_cast<Eigen::Index>(written.meshes[mesh].primitives[0].targets.size()), track.weights.rows());
    const auto& fromNames = from.at("extras").at("targetNames");
    const auto& names = written.meshes[mesh].extras.Get("targetNames");
    ASSERT_EQ(names.ArrayLen(), fromNames.size());
    for (int k = 0; k < static_cast<int>(names.ArrayLen()); ++k)
      EXPECT_EQ(names.Get(k).Get<std::string>(), fromNames[k].get<std::string>());
  }
  ASSERT_EQ(written.animations.size(), 1u);
  const auto& animation = written.animations[0];
  ASSERT_EQ(animation.channels.size(), tracks.morphs.size() + tracks.rotations.size());
  for (std::size_t c = 0; c < tracks.morphs.size(); ++c) {
    const auto output = floatsOf(written, animation.samplers.at(animation.channels[c].sampler).output);
    const auto& weights = tracks.morphs[c].weights;
    ASSERT_EQ(output.size(), static_cast<std::size_t>(weights.size()));
    for (int t = 0; t < weights.cols(); ++t)
      for (int k = 0; k < weights.rows(); ++k) ASSERT_EQ(output[t * weights.rows() + k], weights(k, t));
  }
}

INSTANTIATE_TEST_SUITE_P(Avatars, GltfAnimationWrite,
                         ::testing::Values(Case{"brunette-t.glb", ".glb"}, Case{"brunette-t.glb", ".gltf"},
                                           Case{"vroid.glb", ".glb"}, Case{"vroid.glb", ".gltf"}),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           std::string name = std::string(param.param.avatar) + param.param.extension;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// A .gltf avatar with its buffer and a texture as files beside it, and a binary one named .vrm: the written file
// holds everything itself, the texture's bytes unchanged.
TEST(GltfAvatarForms, GltfWithFilesBesideItAndVrm) {
  TemporaryFolder folder;
  const fs::path brunette = sharedDataPath("face/avatars/brunette-t.glb");
  const GltfAnimationTracks tracks = speechTracks(readGltfAvatar(brunette), 5);
  // brunette-t.glb through our writer (tinygltf reads that), then split into files by tinygltf.
  const fs::path whole = folder.path() / "whole.glb";
  writeAvatarAnimation(brunette, tracks, whole);
  tinygltf::Model model = loadGltf(whole);
  auto& image = model.images.at(0);
  const auto& view = model.bufferViews.at(image.bufferView);
  const std::string texture(
      model.buffers[0].data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset),
      model.buffers[0].data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset + view.byteLength));
  std::ofstream(folder.path() / "skin.jpg", std::ios::binary) << texture;
  image.uri = "skin.jpg";
  image.bufferView = -1;
  tinygltf::TinyGLTF writer;
  writer.SetImageWriter(
      [](const std::string*, const std::string*, const tinygltf::Image*, bool, std::string*, void*) { return false; },
      nullptr);
  const fs::path split = folder.path() / "split.gltf";
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, split.string(), false, false, true, false));
  ASSERT_TRUE(fs::exists(folder.path() / "split.bin"));

  const fs::path out = folder.path() / "out" / "talk.glb";
  fs::create_directory(out.parent_path());
  writeAvatarAnimation(split, tracks, out);
  const tinygltf::Model written = loadGltf(out);
  EXPECT_EQ(written.animations.size(), 2u);  // the one split.gltf had, and the new one
  EXPECT_EQ(written.buffers.size(), 1u);
  EXPECT_TRUE(written.buffers[0].uri.empty());
  const auto& moved = written.images.at(0);
  ASSERT_GE(moved.bufferView, 0);
  EXPECT_EQ(moved.mimeType, "image/jpeg");
  const auto& movedView = written.bufferViews.at(moved.bufferView);
  EXPECT_EQ(std::string(written.buffers[0].data.begin() + static_cast<std::ptrdiff_t>(movedView.byteOffset),
                        written.buffers[0].data.begin() +
                            static_cast<std::ptrdiff_t>(movedView.byteOffset + movedView.byteLength)),
            texture);

  // A VRM is a GLB by another name: read by its bytes, written as .vrm (binary).
  const fs::path vrm = folder.path() / "avatar.vrm";
  fs::copy_file(brunette, vrm);
  writeAvatarAnimation(vrm, tracks, folder.path() / "out" / "talk.vrm");
  EXPECT_EQ(loadGltf(folder.path() / "out" / "talk.vrm").animations.size(), 1u);
}

TEST(GltfAvatar, ReadsNodesParentsAndTargetNames) {
  const GltfAvatar avatar = readGltfAvatar(sharedDataPath("face/avatars/brunette-t.glb"));
  const int head = avatar.findNode("Head");
  const int neck = avatar.findNode("Neck");
  ASSERT_GE(head, 0);
  ASSERT_GE(neck, 0);
  EXPECT_EQ(avatar.nodes[head].parent, neck);
  const int face = avatar.findNode("Wolf3D_Head");
  ASSERT_GE(face, 0);
  EXPECT_EQ(avatar.nodes[face].targetCount, 67);
  EXPECT_GE(avatar.targetIndex(face, "jawOpen"), 0);
  EXPECT_EQ(avatar.targetIndex(face, "noSuchShape"), -1);
  EXPECT_EQ(avatar.morphNodes().size(), 4u);
  EXPECT_EQ(avatar.findNode("noSuchNode"), -1);
}

class GltfAnimationErrors : public ::testing::Test {
 protected:
  fs::path avatar = sharedDataPath("face/avatars/brunette-t.glb");
  GltfAvatar model = readGltfAvatar(avatar);
  GltfAnimationTracks tracks = speechTracks(model, 10);
  TemporaryFolder folder;
  fs::path out = folder.path() / "talk.glb";

  // Refused by both forms with `problem` on the line naming `at`, and nothing written.
  void expectRefused(const fs::path& at, const std::string& problem) {
    expectFileError(errorOf([&] { writeAvatarAnimation(avatar, tracks, out); }), at, problem);
    expectFileError(errorOf([&] { writeAnimationOnly(avatar, tracks, out); }), at, problem);
    EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{});
  }
};

TEST_F(GltfAnimationErrors, ATextFileIsNotAnAvatar) {
  avatar = folder.path() / "notes.glb";
  std::ofstream(avatar) << "hello, not a model\n";
  expectFileError(errorOf([&] { readGltfAvatar(avatar); }), avatar, "not a glTF file");
  expectFileError(errorOf([&] { writeAvatarAnimation(avatar, tracks, out); }), avatar, "not a glTF file");
  expectFileError(errorOf([&] { writeAnimationOnly(avatar, tracks, out); }), avatar, "not a glTF file");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"notes.glb"});
}

TEST_F(GltfAnimationErrors, BrokenJsonAndBinaryAreRefusedNamingTheFile) {
  avatar = folder.path() / "broken.gltf";
  std::ofstream(avatar) << "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [";
  expectFileError(errorOf([&] { readGltfAvatar(avatar); }), avatar, "not a readable glTF file");
  avatar = folder.path() / "cut.glb";
  std::ofstream(avatar, std::ios::binary) << "glTF\x02";
  expectFileError(errorOf([&] { readGltfAvatar(avatar); }), avatar, "glTF");
}

TEST_F(GltfAnimationErrors, AMissingAvatarIsNamed) {
  avatar = folder.path() / "nowhere.vrm";
  expectRefused(avatar, "does not exist");
}

TEST_F(GltfAnimationErrors, WrongTargetCount) {
  tracks.morphs[0].weights.conservativeResize(tracks.morphs[0].weights.rows() - 1, Eigen::NoChange);
  expectRefused(avatar, "has 67 morph targets, the track 66 rows");
}

TEST_F(GltfAnimationErrors, NodesOutOfRangeOrWithoutTargets) {
  tracks.rotations[0].node = static_cast<int>(model.nodes.size());
  expectRefused(avatar, "but the avatar has 78 nodes");
  tracks = speechTracks(model, 10);
  tracks.morphs[0].node = model.findNode("Head");
  expectRefused(avatar, "(Head) has no morph targets");
  tracks = speechTracks(model, 10);
  tracks.morphs[1].node = tracks.morphs[0].node;
  expectRefused(out, "already has a morph track");
}

TEST_F(GltfAnimationErrors, FrameCountsMustAgree) {
  tracks.rotations[0].rotations.pop_back();
  expectRefused(out, "rotation track 0 has 9 frames, the first track 10");
  tracks = speechTracks(model, 10);
  tracks.morphs[2].weights.conservativeResize(Eigen::NoChange, 11);
  expectRefused(out, "morph track 2 has 11 frames");
}

TEST_F(GltfAnimationErrors, ValuesMustBeFinite) {
  tracks.morphs[1].weights(3, 4) = std::numeric_limits<float>::quiet_NaN();
  expectRefused(out, "not finite");
  tracks = speechTracks(model, 10);
  tracks.rotations[0].rotations[5].coeffs().setZero();
  expectRefused(out, "zero length");
  tracks = speechTracks(model, 10);
  tracks.framesPerSecond = 0;
  expectRefused(out, "frame rate");
  tracks = GltfAnimationTracks{};
  expectRefused(out, "no tracks");
}

TEST_F(GltfAnimationErrors, UnknownExtension) {
  out = folder.path() / "talk.fbx";
  expectRefused(out, ".glb");
  // A .vrm is an avatar: the animation alone is not one.
  out = folder.path() / "talk.vrm";
  expectFileError(errorOf([&] { writeAnimationOnly(avatar, tracks, out); }), out, ".glb or .gltf");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{});
}

TEST_F(GltfAnimationErrors, UnwritableOutputLeavesNothing) {
  out = folder.path() / "no_such_folder" / "talk.glb";
  expectRefused(out, "");
  const fs::path unwritable = "/proc/talkinghead-test.glb";
  expectFileError(errorOf([&] { writeAvatarAnimation(avatar, tracks, unwritable); }), unwritable, "");
  EXPECT_FALSE(fs::exists(unwritable));
  // A file that is there already stays as it was when the new one cannot be made.
  out = folder.path() / "talk.glb";
  std::ofstream(out) << "old";
  tracks.morphs[0].weights(0, 0) = std::numeric_limits<float>::infinity();
  EXPECT_NE(errorOf([&] { writeAvatarAnimation(avatar, tracks, out); }), "(no error)");
  EXPECT_EQ(th::test::readText(out), "old");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"talk.glb"});
}

}  // namespace
}  // namespace th::formats
