// The user's characters as the avatar stage reads and poses them: the two test avatars (a Ready Player Me and a
// VRoid character, the second meshopt-compressed with WebP textures), VRM files made from one of them (VRM is
// glTF with an extension), and bad files.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "formats/arkit_format.h"
#include "glb_edit.h"

namespace {

namespace fs = std::filesystem;
using th::avatar::Avatar;
using th::avatar::AvatarInput;
using th::avatar::AvatarPose;
using th::avatar::DeformedMesh;
using Json = nlohmann::json;
using th::test::hideArkitAndVisemeNames;
using th::test::nodeNamed;
using th::test::rewriteGlb;
using th::test::targetOf;

using th::test::avatarFile;
using th::test::brunette;
using th::test::vroid;

int meshNamed(const Avatar& avatar, const std::string& name) {
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m)
    if (avatar.meshes[m].name == name) return static_cast<int>(m);
  return -1;
}

std::vector<DeformedMesh> deformed(const Avatar& avatar, const AvatarInput& input) {
  const th::avatar::AvatarRig rig = th::avatar::rigAvatar(avatar);
  AvatarPose pose;
  th::avatar::poseAvatar(avatar, rig, input, pose);
  std::vector<DeformedMesh> meshes;
  th::avatar::deformAvatar(avatar, pose, meshes);
  return meshes;
}

float& arkit(AvatarInput& input, const char* name) {
  return input.arkit[static_cast<std::size_t>(th::formats::arkitIndex(name))];
}

// The largest distance any vertex of a mesh moved between two poses.
float largestMove(const std::vector<DeformedMesh>& a, const std::vector<DeformedMesh>& b, int mesh) {
  float largest = 0.0f;
  const auto m = static_cast<std::size_t>(mesh);
  for (std::size_t p = 0; p < a[m].positions.size(); ++p)
    largest = std::max(largest, (a[m].positions[p] - b[m].positions[p]).colwise().norm().maxCoeff());
  return largest;
}

Eigen::Vector3f centroid(const std::vector<DeformedMesh>& meshes, int mesh) {
  const DeformedMesh& d = meshes[static_cast<std::size_t>(mesh)];
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  Eigen::Index count = 0;
  for (const auto& positions : d.positions) {
    sum += positions.rowwise().sum();
    count += positions.cols();
  }
  return sum / static_cast<float>(count);
}

TEST(Avatar, ReadyPlayerMeCharacterHasItsMeshesBonesTexturesAndArkitShapes) {
  const Avatar& avatar = brunette();
  EXPECT_EQ(avatar.meshes.size(), 10u);
  EXPECT_EQ(avatar.format, th::avatar::AvatarFormat::kGltf);
  for (const int bone : avatar.bones) ASSERT_GE(bone, 0);
  EXPECT_EQ(avatar.nodes[static_cast<std::size_t>(avatar.bones[th::avatar::kHead])].name, "Head");
  EXPECT_EQ(avatar.nodes[static_cast<std::size_t>(avatar.bones[th::avatar::kNeck])].name, "Neck");
  // The eye bones, not the eye meshes of the same names.
  EXPECT_EQ(avatar.nodes[static_cast<std::size_t>(avatar.bones[th::avatar::kLeftEye])].name, "LeftEye");
  const int head = meshNamed(avatar, "Wolf3D_Head");
  ASSERT_GE(head, 0);
  EXPECT_EQ(avatar.meshes[static_cast<std::size_t>(head)].targetNames.size(), 67u);
  EXPECT_GE(avatar.meshes[static_cast<std::size_t>(head)].targetIndex("jawOpen"), 0);
  ASSERT_FALSE(avatar.textures.empty());
  EXPECT_GT(avatar.textures.front().width, 0);
  EXPECT_EQ(avatar.textures.front().rgba.size(),
            static_cast<std::size_t>(avatar.textures.front().width * avatar.textures.front().height * 4));
  EXPECT_EQ(th::avatar::rigAvatar(avatar).scheme, th::avatar::MorphScheme::kArkit);
}

TEST(Avatar, VroidCharacterIsDecodedFromMeshoptAndWebp) {
  const Avatar& avatar = vroid();
  EXPECT_EQ(avatar.meshes.size(), 3u);
  const int face = meshNamed(avatar, "Face (merged)(Clone)");
  ASSERT_GE(face, 0);
  EXPECT_EQ(avatar.meshes[static_cast<std::size_t>(face)].targetNames.size(), 124u);
  // Quantised positions come out in metres: a character about 1.5 m tall.
  Eigen::Vector3f low = Eigen::Vector3f::Constant(1e9f), high = -low;
  for (const DeformedMesh& mesh : deformed(avatar, {}))
    for (const auto& positions : mesh.positions) {
      low = low.cwiseMin(positions.rowwise().minCoeff());
      high = high.cwiseMax(positions.rowwise().maxCoeff());
    }
  EXPECT_GT(high.y() - low.y(), 1.2f);
  EXPECT_LT(high.y() - low.y(), 2.0f);
  std::size_t decoded = 0;
  for (const auto& texture : avatar.textures) decoded += texture.width > 0 && !texture.rgba.empty();
  EXPECT_GE(decoded, 10u) << "the WebP textures";
  for (const int bone : avatar.bones) EXPECT_GE(bone, 0);
  // Its ARKit names include a jawOpen that moves nothing: the mouth is driven by its Oculus visemes, the eyes,
  // brows and blinks by its ARKit shapes.
  const th::avatar::AvatarRig rig = th::avatar::rigAvatar(avatar);
  EXPECT_EQ(rig.scheme, th::avatar::MorphScheme::kOculusVisemes);
  EXPECT_TRUE(rig.eyesByTargets);
}

TEST(AvatarPose, AtRestTheSkinnedMeshesStayWhereTheFileHasThem) {
  const Avatar& avatar = brunette();
  const std::vector<DeformedMesh> rest = deformed(avatar, {});
  const int head = meshNamed(avatar, "Wolf3D_Head");
  // Ready Player Me binds near the scene's pose: skinning at rest keeps the head within a centimetre of its bind
  // positions (a wrong joint order or matrix layout would throw it metres away).
  const auto& primitive = avatar.meshes[static_cast<std::size_t>(head)].primitives.front();
  EXPECT_LT((rest[static_cast<std::size_t>(head)].positions.front() - primitive.positions).cwiseAbs().maxCoeff(),
            0.01f);
}

TEST(AvatarPose, TheMouthOpensItBlinksAndTheHeadTurnsToItsLeft) {
  for (const Avatar* avatar : {&brunette(), &vroid()}) {
    SCOPED_TRACE(avatar->name);
    const int face =
        avatar == &brunette() ? meshNamed(*avatar, "Wolf3D_Head") : meshNamed(*avatar, "Face (merged)(Clone)");
    const std::vector<DeformedMesh> rest = deformed(*avatar, {});
    // The mouth opens: by ARKit's jawOpen on the first, by the viseme aa on the second (its jawOpen is empty).
    AvatarInput open;
    arkit(open, "jawOpen") = 1.0f;
    open.hasVisemes = true;
    open.oculus[10] = 1.0f;  // aa
    EXPECT_GT(largestMove(rest, deformed(*avatar, open), face), 0.01f) << "the mouth opens by a centimetre or more";
    AvatarInput blink;
    arkit(blink, "eyeBlinkLeft") = arkit(blink, "eyeBlinkRight") = 1.0f;
    EXPECT_GT(largestMove(rest, deformed(*avatar, blink), face), 0.003f);
    // Yaw 20° to the character's left (+x for a character facing +z): the face's centroid moves to +x; the feet
    // do not move.
    AvatarInput turned;
    turned.headDegrees = {0.0, 20.0, 0.0};
    const std::vector<DeformedMesh> yawed = deformed(*avatar, turned);
    EXPECT_GT(centroid(yawed, face).x() - centroid(rest, face).x(), 0.01f);
    // Pitch down: the face goes down.
    AvatarInput nod;
    nod.headDegrees = {20.0, 0.0, 0.0};
    EXPECT_LT(centroid(deformed(*avatar, nod), face).y() - centroid(rest, face).y(), -0.003f);
  }
}

TEST(AvatarPose, VrmOneExpressionsDriveTheVowelsAndBlinks) {
  const th::TemporaryFolder folder;
  const fs::path vrm = folder.path() / "vroid.vrm";
  int faceMesh = -1, vowelA = -1, blinkTarget = -1;
  rewriteGlb(avatarFile("vroid.glb"), vrm, [&](Json& json) {
    for (std::size_t m = 0; m < json["meshes"].size(); ++m)
      if (json["meshes"][m].value("name", "") == "Face (merged)(Clone)") faceMesh = static_cast<int>(m);
    int faceNode = -1;
    for (std::size_t n = 0; n < json["nodes"].size(); ++n)
      if (json["nodes"][n].value("mesh", -1) == faceMesh) faceNode = static_cast<int>(n);
    vowelA = targetOf(json, faceMesh, "Fcl_MTH_A");
    blinkTarget = targetOf(json, faceMesh, "Fcl_EYE_Close");
    hideArkitAndVisemeNames(json);
    const auto bind = [&](int target) {
      return Json{{"morphTargetBinds", Json::array({{{"node", faceNode}, {"index", target}, {"weight", 1.0}}})}};
    };
    json["extensions"]["VRMC_vrm"] = {
        {"specVersion", "1.0"},
        {"meta", {{"name", "test"}, {"licenseUrl", "https://vrm.dev/licenses/1.0/"}}},
        {"humanoid",
         {{"humanBones",
           {{"head", {{"node", nodeNamed(json, "Head")}}}, {"neck", {{"node", nodeNamed(json, "Neck")}}}}}}},
        {"expressions",
         {{"preset",
           {{"aa", bind(vowelA)},
            {"ih", bind(targetOf(json, faceMesh, "Fcl_MTH_I"))},
            {"ou", bind(targetOf(json, faceMesh, "Fcl_MTH_U"))},
            {"ee", bind(targetOf(json, faceMesh, "Fcl_MTH_E"))},
            {"oh", bind(targetOf(json, faceMesh, "Fcl_MTH_O"))},
            {"blink", bind(blinkTarget)}}}}}};
    json["extensionsUsed"].push_back("VRMC_vrm");
  });
  ASSERT_GE(vowelA, 0);
  const Avatar avatar = th::avatar::loadAvatar(vrm);
  EXPECT_EQ(avatar.format, th::avatar::AvatarFormat::kVrm1);
  EXPECT_FALSE(avatar.facesMinusZ());
  const th::avatar::AvatarRig rig = th::avatar::rigAvatar(avatar);
  ASSERT_EQ(rig.scheme, th::avatar::MorphScheme::kVrmExpressions);
  AvatarInput input;
  input.hasVisemes = true;
  input.vrm = {0.8f, 0.0f, 0.0f, 0.0f, 0.0f};
  arkit(input, "eyeBlinkLeft") = arkit(input, "eyeBlinkRight") = 1.0f;
  arkit(input, "jawOpen") = 1.0f;  // not a VRM expression: ignored
  AvatarPose pose;
  th::avatar::poseAvatar(avatar, rig, input, pose);
  const int face = meshNamed(avatar, "Face (merged)(Clone)");
  const auto& weights = pose.weights[static_cast<std::size_t>(face)];
  EXPECT_FLOAT_EQ(weights[static_cast<std::size_t>(vowelA)], 0.8f);
  EXPECT_FLOAT_EQ(weights[static_cast<std::size_t>(blinkTarget)], 1.0f);
  float others = 0.0f;
  for (std::size_t t = 0; t < weights.size(); ++t)
    if (static_cast<int>(t) != vowelA && static_cast<int>(t) != blinkTarget) others += std::abs(weights[t]);
  EXPECT_EQ(others, 0.0f) << "only the expressions' targets move";
}

TEST(AvatarPose, VrmZeroCharacterFacesMinusZAndTurnsTheOtherWay) {
  const th::TemporaryFolder folder;
  const fs::path vrm = folder.path() / "brunette.vrm";
  rewriteGlb(avatarFile("brunette-t.glb"), vrm, [&](Json& json) {
    int head = -1;
    for (std::size_t m = 0; m < json["meshes"].size(); ++m)
      if (json["meshes"][m].value("name", "") == "Wolf3D_Head") head = static_cast<int>(m);
    const int a = targetOf(json, head, "viseme_aa");
    hideArkitAndVisemeNames(json);
    json["extensions"]["VRM"] = {
        {"humanoid",
         {{"humanBones", Json::array({{{"bone", "head"}, {"node", nodeNamed(json, "Head")}},
                                      {{"bone", "neck"}, {"node", nodeNamed(json, "Neck")}}})}}},
        {"blendShapeMaster",
         {{"blendShapeGroups",
           Json::array({{{"name", "A"},
                         {"presetName", "a"},
                         {"binds", Json::array({{{"mesh", head}, {"index", a}, {"weight", 100}}})}},
                        {{"name", "I"},
                         {"presetName", "i"},
                         {"binds", Json::array({{{"mesh", head}, {"index", a}, {"weight", 50}}})}},
                        {{"name", "U"},
                         {"presetName", "u"},
                         {"binds", Json::array({{{"mesh", head}, {"index", a}, {"weight", 50}}})}}})}}}};
    json["extensionsUsed"] = Json::array({"VRM"});
  });
  const Avatar avatar = th::avatar::loadAvatar(vrm);
  EXPECT_EQ(avatar.format, th::avatar::AvatarFormat::kVrm0);
  EXPECT_EQ(th::avatar::rigAvatar(avatar).scheme, th::avatar::MorphScheme::kVrmExpressions);
  ASSERT_EQ(avatar.expressions.count("aa"), 1u);
  EXPECT_FLOAT_EQ(avatar.expressions.at("ih").front().weight, 0.5f);
  // This character really faces +z: read as VRM 0.x (facing −z), a nod forward tips its real face up, and a
  // turn to its left (about the vertical, which faces do not change) still moves its face to +x.
  const int face = meshNamed(avatar, "Wolf3D_Head");
  AvatarInput nod, turned;
  nod.headDegrees = {20.0, 0.0, 0.0};
  turned.headDegrees = {0.0, 20.0, 0.0};
  const Eigen::Vector3f rest = centroid(deformed(avatar, {}), face);
  EXPECT_GT(centroid(deformed(avatar, nod), face).y() - rest.y(), 0.003f);
  EXPECT_GT(centroid(deformed(avatar, turned), face).x() - rest.x(), 0.01f);
}

TEST(Avatar, BadFilesFailInOneLineNamingThem) {
  const th::TemporaryFolder folder;
  const fs::path text = folder.path() / "notes.glb";
  std::ofstream(text) << "hello\n";
  const auto message = [](const fs::path& path) {
    try {
      th::avatar::loadAvatar(path);
    } catch (const th::Error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  for (const fs::path& path : {text, folder.path() / "missing.glb"}) {
    const std::string what = message(path);
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // A triangle with neither morph targets nor bones: read, but nothing to drive.
  const fs::path plain = folder.path() / "triangle.gltf";
  std::ofstream(plain)
      << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"name":"tri"}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
  const Avatar triangle = th::avatar::loadAvatar(plain);
  EXPECT_EQ(triangle.meshes.size(), 1u);
  try {
    th::avatar::rigAvatar(triangle);
    ADD_FAILURE() << "a character with nothing to drive is refused";
  } catch (const th::Error& error) {
    EXPECT_NE(std::string(error.what()).find("nothing to drive"), std::string::npos) << error.what();
  }
}

// What a character lacks is said, and it is still driven by what it has: morph targets we do not know leave
// the head turning; no head bone leaves the mouth speaking.
TEST(AvatarRig, ACharacterWithoutKnownTargetsOrWithoutAHeadBoneFallsBackToWhatItHas) {
  Avatar renamed = brunette();
  for (th::avatar::MeshInstance& mesh : renamed.meshes)
    for (std::string& name : mesh.targetNames) name = "custom_" + name;
  const th::avatar::AvatarRig headOnly = th::avatar::rigAvatar(renamed);
  EXPECT_EQ(headOnly.scheme, th::avatar::MorphScheme::kNone);
  EXPECT_NE(
      std::find(headOnly.missing.begin(), headOnly.missing.end(), "no morph targets we know (the mouth stays still)"),
      headOnly.missing.end());
  AvatarInput turned;
  turned.headDegrees = {0.0, 20.0, 0.0};
  th::avatar::AvatarPose pose;
  th::avatar::poseAvatar(renamed, headOnly, turned, pose);
  const int head = renamed.bones[th::avatar::kHead];
  const Eigen::Matrix3f rest = renamed.nodes[static_cast<std::size_t>(head)].local().rotation();
  EXPECT_FALSE(pose.locals[static_cast<std::size_t>(head)].rotation().isApprox(rest, 1e-4f)) << "the head turns";

  Avatar headless = brunette();
  headless.bones[th::avatar::kHead] = -1;
  headless.bones[th::avatar::kNeck] = -1;
  const th::avatar::AvatarRig mouthOnly = th::avatar::rigAvatar(headless);
  EXPECT_EQ(mouthOnly.scheme, th::avatar::MorphScheme::kArkit);
  EXPECT_NE(std::find(mouthOnly.missing.begin(), mouthOnly.missing.end(), "no head bone (the head stays still)"),
            mouthOnly.missing.end());
  AvatarInput open;
  open.arkit[static_cast<std::size_t>(th::formats::arkitIndex("jawOpen"))] = 1.0f;
  th::avatar::poseAvatar(headless, mouthOnly, open, pose);
  const int face = meshNamed(headless, "Wolf3D_Head");
  ASSERT_GE(face, 0);
  const int jaw = headless.meshes[static_cast<std::size_t>(face)].targetIndex("jawOpen");
  EXPECT_FLOAT_EQ(pose.weights[static_cast<std::size_t>(face)][static_cast<std::size_t>(jaw)], 1.0f);
}

// Both test characters were made in a T-pose: shown, their upper arms hang 70° below the horizontal, each on
// its own side; with armsDownDegrees 0, as the file has them.
TEST(AvatarPose, ATPosedCharactersArmsAreLowered) {
  for (const Avatar* character : {&brunette(), &vroid()}) {
    for (std::size_t side = 0; side < 2; ++side) ASSERT_GE(character->upperArms[side], 0) << character->name;
    const auto elbowAngle = [&](const th::avatar::RigOptions& options, std::size_t side) {
      const th::avatar::AvatarRig rig = th::avatar::rigAvatar(*character, options);
      th::avatar::AvatarPose pose;
      th::avatar::poseAvatar(*character, rig, AvatarInput{}, pose);
      const std::vector<Eigen::Affine3f> globals = th::avatar::globalTransforms(*character, pose.locals);
      const int arm = character->upperArms[side];
      int elbow = -1;
      float farthest = 0.0f;
      for (std::size_t n = 0; n < character->nodes.size(); ++n)
        if (character->nodes[n].parent == arm) {
          const float d = (globals[n].translation() - globals[static_cast<std::size_t>(arm)].translation()).norm();
          if (d > farthest) farthest = d, elbow = static_cast<int>(n);
        }
      const Eigen::Vector3f along = (globals[static_cast<std::size_t>(elbow)].translation() -
                                     globals[static_cast<std::size_t>(arm)].translation())
                                        .normalized();
      return std::pair{std::asin(-along.y()) * 180.0f / 3.14159265f, along.x()};
    };
    const auto [leftDown, leftX] = elbowAngle({}, 0);
    const auto [rightDown, rightX] = elbowAngle({}, 1);
    EXPECT_NEAR(leftDown, 70.0f, 0.5f) << character->name;
    EXPECT_NEAR(rightDown, 70.0f, 0.5f) << character->name;
    EXPECT_LT(leftX * rightX, 0.0f) << character->name << ": the arms hang on either side";
    EXPECT_NEAR(elbowAngle({.armsDownDegrees = 0.0}, 0).first, 0.0f, 10.0f) << character->name << " at rest";
  }
}

}  // namespace
