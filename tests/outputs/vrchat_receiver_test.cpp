// What VRChat and a face-tracking avatar make of our frames, modelled on what VRChat documents
// (docs.vrchat.com/docs/osc-overview, osc-avatar-parameters: /avatar/parameters/NAME, one int, float or bool a
// message) and on VRCFaceTracking's code (benaclejames/VRCFaceTracking: Unified Expressions' names and ranges,
// MouthClosed clamped to JawOpen, BinaryBaseParameter's bits, the *TrackingActive flags).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "formats/arkit_format.h"
#include "outputs/osc_test_parser.h"
#include "outputs/vrchat_output.h"

namespace th::outputs {
namespace {

// An avatar's parameters as VRChat applies them: floats, and bools of binary parameters decoded as the avatar's
// animator does (each bit worth 2^i / 2^N).
struct Avatar {
  std::map<std::string, float> floats;
  std::map<std::string, bool> bools;
  int received = 0;
  void receive(const std::vector<OscMessage>& messages) {
    std::vector<ParsedMessage> parsed;
    for (const auto& datagram : cutIntoDatagrams(messages, 1400)) {
      const std::vector<char> bytes = serialiseBundle(datagram);
      EXPECT_LE(bytes.size(), 1400U);
      EXPECT_TRUE(UoscParser(bytes).parse(parsed));
    }
    for (const ParsedMessage& m : parsed) {
      ++received;
      EXPECT_EQ(m.path.rfind("/avatar/parameters/", 0), 0U) << m.path;
      ASSERT_EQ(m.arguments.size(), 1U) << "one value a message: " << m.path;
      const std::string name = m.path.substr(std::string("/avatar/parameters/").size());
      if (m.arguments[0].type == 'f')
        floats[name] = m.arguments[0].real;
      else if (m.arguments[0].type == 'T' || m.arguments[0].type == 'F')
        bools[name] = m.arguments[0].flag;
      else
        ADD_FAILURE() << m.path << " has type " << m.arguments[0].type;
    }
  }
  float binary(const std::string& name, int bits) const {
    float value = 0.0f;
    for (int i = 0; i < bits; ++i)
      if (bools.at(name + std::to_string(1 << i))) value += static_cast<float>(1 << i) / static_cast<float>(1 << bits);
    return bools.at(name + "Negative") ? -value : value;
  }
};

AvatarFrame speaking() {
  AvatarFrame frame;
  const auto set = [&](std::string_view name, float value) {
    frame.arkit[static_cast<std::size_t>(formats::arkitIndex(name))] = value;
  };
  set("jawOpen", 0.4f);
  set("mouthClose", 0.7f);  // more than the jaw: VRCFaceTracking keeps it at most JawOpen
  set("mouthPucker", 0.3f);
  set("mouthFrownLeft", 0.5f);
  set("eyeBlinkLeft", 1.0f);
  set("eyeLookInLeft", 0.2f);
  return frame;
}

TEST(VrchatReceiver, AFaceTrackingAvatarGetsItsUnifiedExpressionsInRange) {
  VrchatMessages messages({});
  Avatar avatar;
  avatar.receive(messages.of(speaking(), true));
  EXPECT_TRUE(avatar.bools.at("LipTrackingActive"));
  EXPECT_TRUE(avatar.bools.at("EyeTrackingActive"));
  EXPECT_FLOAT_EQ(avatar.floats.at("FT/v2/JawOpen"), 0.4f);
  EXPECT_FLOAT_EQ(avatar.floats.at("FT/v2/MouthClosed"), 0.4f) << "clamped to JawOpen";
  EXPECT_FLOAT_EQ(avatar.floats.at("FT/v2/LipPucker"), 0.3f);
  EXPECT_FLOAT_EQ(avatar.floats.at("FT/v2/SmileFrownLeft"), -0.5f);
  EXPECT_FLOAT_EQ(avatar.floats.at("FT/v2/EyeLidLeft"), 0.0f) << "shut";
  EXPECT_FLOAT_EQ(avatar.floats.at("FT/v2/EyeLidRight"), 0.75f) << "open";
  EXPECT_FLOAT_EQ(avatar.floats.at("FT/v2/EyeLeftX"), 0.2f) << "the left eye looking in looks to the right";
  for (const auto& [name, value] : avatar.floats) {
    const bool signed_ = name.find("SmileFrown") != std::string::npos || name.find("Eye") != std::string::npos;
    EXPECT_GE(value, signed_ ? -1.0f : 0.0f) << name;
    EXPECT_LE(value, 1.0f) << name;
  }
  // Nothing outside /avatar/parameters, nothing with a FAP's units.
  EXPECT_EQ(avatar.floats.count("FT/v2/fap/3"), 0U);
}

TEST(VrchatReceiver, OnlyChangesAreSentAndEverythingAgainOnRefresh) {
  VrchatMessages messages({});
  Avatar avatar;
  avatar.receive(messages.of(speaking(), true));
  const int first = avatar.received;
  EXPECT_TRUE(messages.of(speaking(), false).empty()) << "the same frame again: nothing changed";
  AvatarFrame moved = speaking();
  moved.arkit[static_cast<std::size_t>(formats::arkitIndex("jawOpen"))] = 0.6f;
  const std::vector<OscMessage> change = messages.of(moved, false);
  ASSERT_EQ(change.size(), 2U);  // the jaw, and the closure clamped to it
  EXPECT_EQ(change[0].path, "/avatar/parameters/FT/v2/JawOpen");
  EXPECT_EQ(change[1].path, "/avatar/parameters/FT/v2/MouthClosed");
  EXPECT_EQ(static_cast<int>(messages.of(moved, true).size()), first) << "a refresh says everything";
}

TEST(VrchatReceiver, BinaryParametersDecodeAsTheAvatarDecodesThem) {
  for (const int bits : {3, 4, 6}) {
    VrchatMessages messages({.prefix = "v2/", .bits = bits});
    Avatar avatar;
    avatar.receive(messages.of(speaking(), true));
    for (const char* name : {"JawOpen", "LipPucker", "SmileFrownLeft", "EyeLidRight"}) {
      const float sent = avatar.floats.at(std::string("v2/") + name);
      EXPECT_NEAR(avatar.binary(std::string("v2/") + name, bits), sent, 1.0f / static_cast<float>(1 << bits))
          << name << " in " << bits << " bits";
    }
    EXPECT_TRUE(avatar.bools.at("v2/SmileFrownLeftNegative"));
    EXPECT_FALSE(avatar.bools.at("v2/JawOpenNegative"));
  }
}

}  // namespace
}  // namespace th::outputs
