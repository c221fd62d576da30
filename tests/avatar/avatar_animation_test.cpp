// A character's speech as glTF tracks (avatar/avatar_animation.h), on the two test avatars: the tracks aim at the
// file's own nodes, the mouth's weights are the pose's (the jaw's opening on ARKit's jawOpen, the visemes on a
// VRoid character's viseme targets), undriven targets stay at rest, and the bones turn as poseAvatar turns them.
#include "avatar/avatar_animation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "formats/arkit_format.h"
#include "formats/gltf_animation.h"
#include "formats/gltf_test_tracks.h"
#include "glb_edit.h"

namespace {

namespace fs = std::filesystem;
using th::avatar::Avatar;
using th::formats::GltfAnimationTracks;
using Json = nlohmann::json;

constexpr double kRadians = M_PI / 180.0;

using th::test::avatarFile;
using th::test::brunette;
using th::test::vroid;

int nodeNamed(const Avatar& avatar, const std::string& name) {
  for (std::size_t n = 0; n < avatar.nodes.size(); ++n)
    if (avatar.nodes[n].name == name) return static_cast<int>(n);
  return -1;
}

const th::formats::GltfMorphTrack* morphTrackOn(const GltfAnimationTracks& tracks, int node) {
  for (const auto& track : tracks.morphs)
    if (track.node == node) return &track;
  return nullptr;
}

const th::formats::GltfRotationTrack* rotationTrackOn(const GltfAnimationTracks& tracks, int node) {
  for (const auto& track : tracks.rotations)
    if (track.node == node) return &track;
  return nullptr;
}

const th::avatar::MeshInstance& meshOnNode(const Avatar& avatar, int node) {
  for (const auto& mesh : avatar.meshes)
    if (mesh.node == node) return mesh;
  throw std::runtime_error("no mesh on node " + std::to_string(node));
}

// `frames` frames at `fps` in which the jaw (FAP 3) opens and closes twice, shut for the first and last quarter.
th::face::FapTrack jawTrack(int frames, double fps = 30.0) {
  th::face::FapTrack track;
  track.framesPerSecond = fps;
  track.faps = {3};
  track.values = Eigen::MatrixXd::Zero(1, frames);
  for (int t = frames / 4; t < frames - frames / 4; ++t)
    track.values(0, t) = 600.0 * std::abs(std::sin(2.0 * M_PI * (t - frames / 4) / (frames / 2.0)));
  return track;
}

// The head turned `yawDegrees` to the speaker's left throughout.
th::face::FapTrack headTrack(double yawDegrees, int frames = 30) {
  th::face::FapTrack track;
  track.faps = {48, 49, 50};
  track.values = Eigen::MatrixXd::Zero(3, frames);
  track.values.row(1).setConstant(yawDegrees * kRadians * 1e5);  // FAP 49: yaw in 1e-5 rad
  return track;
}

double correlation(Eigen::VectorXd a, Eigen::VectorXd b) {
  a.array() -= a.mean();
  b.array() -= b.mean();
  return a.dot(b) / (a.norm() * b.norm());
}

// The rest rotation of a node in the world (its parents' rest rotations and its own).
Eigen::Quaternionf restGlobal(const Avatar& avatar, int node) {
  Eigen::Quaternionf q = Eigen::Quaternionf::Identity();
  for (int n = node; n >= 0; n = avatar.nodes[static_cast<std::size_t>(n)].parent)
    q = avatar.nodes[static_cast<std::size_t>(n)].rotation * q;
  return q;
}

// The angle between two rotations, radians (q and -q the same).
float angleBetween(const Eigen::Quaternionf& a, const Eigen::Quaternionf& b) {
  return 2.0f * std::acos(std::min(1.0f, std::abs(a.normalized().dot(b.normalized()))));
}

TEST(AvatarAnimation, TracksAimAtTheFilesOwnNodesAndTargetCounts) {
  for (const char* name : {"brunette-t.glb", "vroid.glb"}) {
    const Avatar& avatar = std::string(name) == "vroid.glb" ? vroid() : brunette();
    const th::formats::GltfAvatar file = th::formats::readGltfAvatar(avatarFile(name));
    ASSERT_EQ(avatar.nodes.size(), file.nodes.size()) << name;
    for (std::size_t n = 0; n < avatar.nodes.size(); ++n) ASSERT_EQ(avatar.nodes[n].name, file.nodes[n].name) << name;
    const GltfAnimationTracks tracks = th::avatar::avatarAnimation(jawTrack(30), avatar, th::avatar::rigAvatar(avatar));
    ASSERT_FALSE(tracks.morphs.empty()) << name;
    for (const auto& track : tracks.morphs)
      EXPECT_EQ(track.weights.rows(), file.nodes[static_cast<std::size_t>(track.node)].targetCount) << name;
  }
}

TEST(AvatarAnimation, FramesAreTheSpeechsDurationAtThirtyASecond) {
  const th::avatar::AvatarRig rig = th::avatar::rigAvatar(brunette());
  const GltfAnimationTracks same = th::avatar::avatarAnimation(jawTrack(45), brunette(), rig);
  EXPECT_DOUBLE_EQ(same.framesPerSecond, 30.0);
  EXPECT_EQ(same.name, "speech");
  for (const auto& track : same.morphs) EXPECT_EQ(track.weights.cols(), 45);
  for (const auto& track : same.rotations) EXPECT_EQ(track.rotations.size(), 45u);
  // 2 s at 25 frames a second: 60 frames at 30.
  const GltfAnimationTracks resampled = th::avatar::avatarAnimation(jawTrack(50, 25.0), brunette(), rig);
  for (const auto& track : resampled.morphs) EXPECT_EQ(track.weights.cols(), 60);
  EXPECT_EQ(th::avatar::avatarAnimationFrames(jawTrack(50, 25.0)), 60);
  EXPECT_THROW(th::avatar::avatarAnimation(jawTrack(30), brunette(), rig, {.framesPerSecond = 0.0}), th::Error);
}

TEST(AvatarAnimation, ArkitJawOpenFollowsTheJawAndUndrivenTargetsStayAtRest) {
  const Avatar& avatar = brunette();
  const th::face::FapTrack speech = jawTrack(90);
  const GltfAnimationTracks tracks = th::avatar::avatarAnimation(speech, avatar, th::avatar::rigAvatar(avatar));
  const int headMesh = nodeNamed(avatar, "Wolf3D_Head");
  const th::formats::GltfMorphTrack* face = morphTrackOn(tracks, headMesh);
  ASSERT_NE(face, nullptr);
  const th::avatar::MeshInstance& mesh = meshOnNode(avatar, headMesh);
  const int jaw = mesh.targetIndex("jawOpen");
  const auto jawInput = static_cast<std::size_t>(th::formats::arkitIndex("jawOpen"));
  ASSERT_GE(jaw, 0);
  Eigen::VectorXd weight(90), input(90);
  for (int t = 0; t < 90; ++t) {
    weight[t] = face->weights(jaw, t);
    input[t] = th::avatar::avatarInputAt(speech, t / 30.0).arkit[jawInput];
    EXPECT_NEAR(weight[t], input[t], 1e-6) << t;
  }
  EXPECT_GT(correlation(weight, speech.values.row(0).transpose()), 0.95);
  EXPECT_GT(weight.maxCoeff(), 0.3);
  // Shut for the first and last quarter: jawOpen is 0 there.
  EXPECT_EQ(weight.head(22).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(weight.tail(22).cwiseAbs().maxCoeff(), 0.0);
  // Under ARKit's scheme the Oculus visemes are not driven: their weights stay at rest.
  const int aa = mesh.targetIndex("viseme_aa");
  ASSERT_GE(aa, 0);
  EXPECT_TRUE((face->weights.row(aa).array() == mesh.restWeights[static_cast<std::size_t>(aa)]).all());
  // The teeth's jawOpen moves with the face's; meshes without targets have no track.
  const th::formats::GltfMorphTrack* teeth = morphTrackOn(tracks, nodeNamed(avatar, "Wolf3D_Teeth"));
  ASSERT_NE(teeth, nullptr);
  EXPECT_TRUE(teeth->weights.row(meshOnNode(avatar, nodeNamed(avatar, "Wolf3D_Teeth")).targetIndex("jawOpen"))
                  .isApprox(face->weights.row(jaw)));
  EXPECT_EQ(morphTrackOn(tracks, nodeNamed(avatar, "Wolf3D_Body")), nullptr);
}

TEST(AvatarAnimation, HeadAndNeckTurnAsRestTimesTheTurn) {
  const Avatar& avatar = brunette();
  const GltfAnimationTracks tracks =
      th::avatar::avatarAnimation(headTrack(10.0), avatar, th::avatar::rigAvatar(avatar));
  const int head = avatar.bones[th::avatar::kHead], neck = avatar.bones[th::avatar::kNeck];
  ASSERT_EQ(head, nodeNamed(avatar, "Head"));
  // The head's 60 % and the neck's 40 % of a 10° yaw about the world's up, each in its bone's rest frame:
  // local = rest * G⁻¹ R G, G the bone's rest rotation in the world.
  for (const auto& [node, share] : {std::pair{head, 0.6}, std::pair{neck, 0.4}}) {
    const th::formats::GltfRotationTrack* track = rotationTrackOn(tracks, node);
    ASSERT_NE(track, nullptr) << avatar.nodes[static_cast<std::size_t>(node)].name;
    const Eigen::Quaternionf world(
        Eigen::AngleAxisf(static_cast<float>(share * 10.0 * kRadians), Eigen::Vector3f::UnitY()));
    const Eigen::Quaternionf g = restGlobal(avatar, node);
    const Eigen::Quaternionf expected =
        avatar.nodes[static_cast<std::size_t>(node)].rotation * (g.conjugate() * world * g);
    for (const Eigen::Quaternionf& q : track->rotations) EXPECT_LT(angleBetween(q, expected), 1e-4f);
    // Turned, not at rest.
    EXPECT_NEAR(angleBetween(track->rotations.front(), avatar.nodes[static_cast<std::size_t>(node)].rotation),
                share * 10.0 * kRadians, 1e-4);
  }
  // Brunette's eyes move by eyeLook* targets, so its eye bones have no tracks; head and neck do.
  EXPECT_EQ(tracks.rotations.size(), 2u);
}

TEST(AvatarAnimation, VroidsVisemeTargetsMove) {
  const Avatar& avatar = vroid();
  const th::avatar::AvatarRig rig = th::avatar::rigAvatar(avatar);
  ASSERT_EQ(rig.scheme, th::avatar::MorphScheme::kOculusVisemes);
  // Every mouth class in turn, a fifth of a second each, with the jaw open.
  const int frames = 6 * th::face::kNumMouthClasses;
  th::face::FapTrack speech = jawTrack(frames);
  speech.visemes.posteriors = Eigen::MatrixXd::Zero(th::face::kNumMouthClasses, frames);
  for (int t = 0; t < frames; ++t) {
    speech.visemes.posteriors(t / 6, t) = 1.0;
    speech.visemes.classes.push_back(t / 6);
  }
  const GltfAnimationTracks tracks = th::avatar::avatarAnimation(speech, avatar, rig);
  const int faceNode = nodeNamed(avatar, "Face");
  const th::formats::GltfMorphTrack* face = morphTrackOn(tracks, faceNode);
  ASSERT_NE(face, nullptr);
  const th::avatar::MeshInstance& mesh = meshOnNode(avatar, faceNode);
  const auto meshIndex = static_cast<std::size_t>(&mesh - avatar.meshes.data());
  // Each viseme the rig found (a target that moves nothing is not: VRoid's viseme_sil) carries its weight.
  int moved = 0;
  for (int v = 0; v < th::face::kNumOculusVisemes; ++v) {
    const int target = rig.visemeTargets[meshIndex][static_cast<std::size_t>(v)];
    if (target < 0) continue;
    for (int t = 0; t < frames; ++t)
      ASSERT_NEAR(face->weights(target, t),
                  th::avatar::avatarInputAt(speech, t / 30.0).oculus[static_cast<std::size_t>(v)], 1e-6)
          << th::face::kOculusVisemeNames[static_cast<std::size_t>(v)] << " at frame " << t;
    if (face->weights.row(target).maxCoeff() - face->weights.row(target).minCoeff() > 0.5) ++moved;
  }
  EXPECT_GE(moved, 10);  // of the 15
  // Its jawOpen moves nothing, so it is not driven: at rest.
  const int jaw = mesh.targetIndex("jawOpen");
  ASSERT_GE(jaw, 0);
  EXPECT_TRUE((face->weights.row(jaw).array() == mesh.restWeights[static_cast<std::size_t>(jaw)]).all());
}

// Brunette made a VRM 0.x character whose only mouth is VRM's vowels (its ARKit and viseme names hidden), with eye
// bones and no eyeLook* targets: the vowels' target moves, the meshes no expression binds get no track, the eye
// bones turn with the gaze, and the file written is still a VRM.
TEST(AvatarAnimation, AVrmCharactersVowelsAndEyeBonesAreAnimatedAndItStaysAVrm) {
  const th::TemporaryFolder folder;
  const fs::path vrm = folder.path() / "brunette.vrm";
  int aa = -1;
  th::test::rewriteGlb(avatarFile("brunette-t.glb"), vrm, [&](Json& json) {
    int head = -1;
    for (std::size_t m = 0; m < json["meshes"].size(); ++m)
      if (json["meshes"][m].value("name", "") == "Wolf3D_Head") head = static_cast<int>(m);
    aa = th::test::targetOf(json, head, "viseme_aa");
    th::test::hideArkitAndVisemeNames(json);
    const auto bone = [&](const char* name, const char* node) {
      return Json{{"bone", name}, {"node", th::test::nodeNamed(json, node)}};
    };
    const auto vowel = [&](const char* name, const char* preset, int weight) {
      return Json{{"name", name},
                  {"presetName", preset},
                  {"binds", Json::array({{{"mesh", head}, {"index", aa}, {"weight", weight}}})}};
    };
    json["extensions"]["VRM"] = {
        {"humanoid",
         {{"humanBones", Json::array({bone("head", "Head"), bone("neck", "Neck"), bone("leftEye", "LeftEye"),
                                      bone("rightEye", "RightEye")})}}},
        {"blendShapeMaster",
         {{"blendShapeGroups", Json::array({vowel("A", "a", 100), vowel("I", "i", 50), vowel("U", "u", 50)})}}}};
    json["extensionsUsed"] = Json::array({"VRM"});
  });
  ASSERT_GE(aa, 0);
  const Avatar avatar = th::avatar::loadAvatar(vrm);
  const th::avatar::AvatarRig rig = th::avatar::rigAvatar(avatar);
  ASSERT_EQ(rig.scheme, th::avatar::MorphScheme::kVrmExpressions);
  ASSERT_FALSE(rig.eyesByTargets);

  // The mouth class shown as Oculus's aa for the middle half, silence around it; the eyes 10° to the speaker's
  // left throughout (FAPs 23, 24: the eyeballs' yaw).
  const int frames = 60;
  th::face::FapTrack speech = jawTrack(frames);
  speech.faps = {3, 23, 24};
  speech.values.conservativeResize(3, frames);
  speech.values.bottomRows(2).setConstant(10.0 * kRadians * 1e5);
  int open = -1, closed = -1;
  for (int c = 0; c < th::face::kNumMouthClasses; ++c) {
    if (th::face::oculusVisemeOf(c) == 10 && open < 0) open = c;     // aa
    if (th::face::oculusVisemeOf(c) == 0 && closed < 0) closed = c;  // sil
  }
  ASSERT_GE(open, 0);
  ASSERT_GE(closed, 0);
  speech.visemes.posteriors = Eigen::MatrixXd::Zero(th::face::kNumMouthClasses, frames);
  for (int t = 0; t < frames; ++t) {
    const int c = t >= frames / 4 && t < frames - frames / 4 ? open : closed;
    speech.visemes.posteriors(c, t) = 1.0;
    speech.visemes.classes.push_back(c);
  }
  const GltfAnimationTracks tracks = th::avatar::avatarAnimation(speech, avatar, rig);

  ASSERT_EQ(tracks.morphs.size(), 1u) << "only the mesh the vowels bind";
  const th::formats::GltfMorphTrack& face = tracks.morphs.front();
  EXPECT_EQ(face.node, nodeNamed(avatar, "Wolf3D_Head"));
  EXPECT_EQ(face.weights(aa, 0), 0.0f);
  EXPECT_GT(face.weights(aa, frames / 2), 0.5f);
  ASSERT_EQ(tracks.rotations.size(), 4u);  // neck, head and the two eyes
  for (const char* name : {"LeftEye", "RightEye"}) {
    const int eye = nodeNamed(avatar, name);
    const th::formats::GltfRotationTrack* track = rotationTrackOn(tracks, eye);
    ASSERT_NE(track, nullptr) << name;
    for (const Eigen::Quaternionf& q : track->rotations)
      EXPECT_NEAR(angleBetween(q, avatar.nodes[static_cast<std::size_t>(eye)].rotation), 10.0 * kRadians, 1e-4) << name;
  }

  const fs::path out = folder.path() / "talk.vrm";
  th::avatar::checkAvatarAnimationOutput(vrm, out, false);
  th::formats::writeAvatarAnimation(vrm, tracks, out);
  const Json written = th::formats::test::glbJson(out);
  EXPECT_TRUE(written["extensions"].contains("VRM"));
  ASSERT_EQ(written["animations"].size(), 1u);
  int weights = 0, rotations = 0;
  for (const Json& channel : written["animations"][0]["channels"]) {
    weights += channel["target"]["path"] == "weights";
    rotations += channel["target"]["path"] == "rotation";
  }
  EXPECT_EQ(weights, 1);
  EXPECT_EQ(rotations, 4);
}

TEST(AvatarAnimation, OutputsOtherThanGltfAndVrmFromVrmAreRefusedNamingTheFile) {
  const auto refusal = [](const char* avatar, const char* out, bool animationOnly) {
    try {
      th::avatar::checkAvatarAnimationOutput(avatar, out, animationOnly);
    } catch (const th::Error& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_EQ(refusal("me.glb", "talk.glb", false), "");
  EXPECT_EQ(refusal("me.glb", "talk.GLTF", true), "");
  EXPECT_EQ(refusal("me.vrm", "talk.vrm", false), "");
  EXPECT_NE(refusal("me.glb", "talk.csv", false).find("talk.csv"), std::string::npos);
  EXPECT_NE(refusal("me.glb", "talk.vrm", false).find("talk.vrm"), std::string::npos);
  EXPECT_NE(refusal("me.vrm", "talk.vrm", true).find("talk.vrm"), std::string::npos);
}

}  // namespace
