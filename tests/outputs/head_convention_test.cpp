// One convention for the head in every output: the avatar turns as the speaker does (to its own left when the
// speaker turns to theirs), or, with --mirror-head, as their mirror image; VTube Studio's mouth form at rest.
// Unity (VMC): left-handed, y up, the avatar facing +z, x to its right, so a turn to the avatar's left is
// negative about y. Live2D (VTube Studio): angle X is positive toward the screen's right, the character's own
// left (the VTube Studio API's README, "InjectParameterDataRequest"; Live2D's standard parameters).
#include <gtest/gtest.h>

#include <cmath>

#include "formats/arkit_format.h"
#include "outputs/vmc_output.h"
#include "outputs/vts_output.h"

namespace th::outputs {
namespace {

double parameter(const std::vector<std::pair<std::string, double>>& parameters, const std::string& name) {
  for (const auto& [id, value] : parameters)
    if (id == name) return value;
  ADD_FAILURE() << name << " not sent";
  return 0.0;
}

AvatarFrame turned(double yawDegrees, double rollDegrees = 0.0) {
  AvatarFrame frame;
  frame.headDegrees = Eigen::Vector3d(0.0, yawDegrees, rollDegrees);
  return frame;
}

Eigen::Quaternionf vmcHead(const AvatarFrame& frame, const VmcOptions& options) {
  Eigen::Quaternionf neck = Eigen::Quaternionf::Identity(), head = Eigen::Quaternionf::Identity();
  for (const std::vector<OscMessage>& datagram : vmcDatagrams(frame, options))
    for (const OscMessage& m : datagram) {
      if (m.path != "/VMC/Ext/Bone/Pos") continue;
      const auto f = [&](std::size_t k) { return std::get<float>(m.arguments[k]); };
      const Eigen::Quaternionf q(f(7), f(4), f(5), f(6));
      (std::get<std::string>(m.arguments[0]) == "Neck" ? neck : head) = q;
    }
  return neck * head;
}

TEST(HeadConvention, AYawToTheSpeakersLeftTurnsEveryAvatarToItsOwnLeft) {
  const float s = std::sin(10.0f * 3.14159265f / 180.0f), c = std::cos(10.0f * 3.14159265f / 180.0f);
  const Eigen::Quaternionf vmc = vmcHead(turned(20.0), {});
  EXPECT_NEAR(vmc.y(), -s, 1e-6f);
  EXPECT_NEAR(vmc.w(), c, 1e-6f);
  EXPECT_NEAR(parameter(vtsParameters(turned(20.0)), "FaceAngleX"), 20.0, 1e-9);
  // Mirrored, both the other way.
  const Eigen::Quaternionf mirrored = vmcHead(turned(20.0), {.mirrorHead = true});
  EXPECT_NEAR(mirrored.y(), s, 1e-6f);
  EXPECT_NEAR(parameter(vtsParameters(turned(20.0), true), "FaceAngleX"), -20.0, 1e-9);
  // The roll too; the pitch is the same either way.
  EXPECT_NEAR(parameter(vtsParameters(turned(0.0, 10.0)), "FaceAngleZ"), 10.0, 1e-9);
  EXPECT_NEAR(parameter(vtsParameters(turned(0.0, 10.0), true), "FaceAngleZ"), -10.0, 1e-9);
  EXPECT_NEAR(vmcHead(turned(0.0, 10.0), {}).z(), -vmcHead(turned(0.0, 10.0), {.mirrorHead = true}).z(), 1e-6f);
  // Within VTube Studio's documented ranges.
  EXPECT_NEAR(parameter(vtsParameters(turned(70.0)), "FaceAngleX"), 30.0, 1e-9);
}

TEST(HeadConvention, VtubeStudiosMouthFormIsNeutralAtRest) {
  AvatarFrame rest;
  EXPECT_NEAR(parameter(vtsParameters(rest), "MouthSmile"), 0.5, 1e-9) << "its default mapping's 0 is 0.5";
  AvatarFrame smiling;
  smiling.arkit[static_cast<std::size_t>(formats::arkitIndex("mouthSmileLeft"))] = 0.8f;
  smiling.arkit[static_cast<std::size_t>(formats::arkitIndex("mouthSmileRight"))] = 0.8f;
  EXPECT_NEAR(parameter(vtsParameters(smiling), "MouthSmile"), 0.9, 1e-6);
  AvatarFrame frowning;
  frowning.arkit[static_cast<std::size_t>(formats::arkitIndex("mouthFrownLeft"))] = 0.6f;
  frowning.arkit[static_cast<std::size_t>(formats::arkitIndex("mouthFrownRight"))] = 0.6f;
  EXPECT_NEAR(parameter(vtsParameters(frowning), "MouthSmile"), 0.2, 1e-6);
}

}  // namespace
}  // namespace th::outputs
