// What real VMC receivers make of our frames, modelled on their receive code, not on our sender:
// - uOSC (hecomi/uOSC 2.2, the OSC library of EVMC4U and VMagicMirror; Runtime/Core/Parser.cs): bundles and
//   nested bundles, every message with a type tag string, only i, f, s (and b T F) arguments;
// - EVMC4U (gpsnmeajp/EasyVirtualMotionCaptureForUnity, ExternalReceiver.cs): Bone/Pos and Root/Pos read eight
//   arguments (a shorter message throws, and any exception shuts the receiver down for good); with
//   BonePositionSynchronize (on by default) a bone's localPosition is set to the position received; blendshape
//   names are matched lower-cased;
// - VMagicMirror (malaybaku/VMagicMirror, VMCP/VMCPBlendShape.cs): names matched exactly against the avatar's
//   clip names and VRM 0.x's presets; perfect-sync avatars name their clips as ARKit's in PascalCase.
// The VMC specification (sh-akira/VirtualMotionCaptureProtocol): bundles within 1500 bytes; an Assistant sends
// blendshapes, not bones.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "formats/arkit_format.h"
#include "outputs/osc_test_parser.h"
#include "outputs/vmc_output.h"

namespace th::outputs {
namespace {

std::vector<ParsedMessage> received(const std::vector<std::vector<char>>& packets) {
  std::vector<ParsedMessage> messages;
  for (const std::vector<char>& packet : packets) {
    EXPECT_LE(packet.size(), 1400U) << "a datagram over the usual MTU is fragmented";
    EXPECT_TRUE(UoscParser(packet).parse(messages)) << "uOSC could not read a datagram";
  }
  return messages;
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// EVMC4U with its defaults, on a humanoid whose Neck and Head stand at their rest offsets.
struct Evmc4u {
  bool shutdown = false;
  std::map<std::string, Eigen::Vector3f> localPosition{{"Neck", {0.0f, 0.12f, 0.0f}}, {"Head", {0.0f, 0.09f, 0.0f}}};
  std::map<std::string, Eigen::Quaternionf> localRotation;
  std::set<std::string> clips;  // lower-cased, as its table holds them
  std::set<std::string> applied;

  void receive(const std::vector<ParsedMessage>& messages) {
    for (const ParsedMessage& m : messages) {
      if (shutdown) return;
      const auto f = [&](std::size_t k) {
        if (k >= m.arguments.size() || m.arguments[k].type != 'f') shutdown = true;  // its exception, for good
        return k < m.arguments.size() ? m.arguments[k].real : 0.0f;
      };
      if (m.path == "/VMC/Ext/Bone/Pos" || m.path == "/VMC/Ext/Root/Pos") {
        if (m.arguments.empty() || m.arguments[0].type != 's') continue;
        const Eigen::Vector3f position(f(1), f(2), f(3));
        const Eigen::Quaternionf rotation(f(7), f(4), f(5), f(6));
        if (shutdown) return;
        localPosition[m.arguments[0].text] = position;  // BonePositionSynchronize: on by default
        localRotation[m.arguments[0].text] = rotation;
      }
      if (m.path == "/VMC/Ext/Blend/Val" && m.arguments.size() == 2 && clips.count(lower(m.arguments[0].text)))
        applied.insert(m.arguments[0].text);
    }
  }
};

// VMagicMirror's VMC input: exact names; positions only for the hips.
struct VMagicMirror {
  explicit VMagicMirror(std::set<std::string> avatarClips) : clips(std::move(avatarClips)) {}
  std::set<std::string> clips;  // the avatar's clip names and VRM 0.x's presets
  std::set<std::string> applied, ignored;
  void receive(const std::vector<ParsedMessage>& messages) {
    for (const ParsedMessage& m : messages)
      if (m.path == "/VMC/Ext/Blend/Val" && m.arguments.size() == 2 && m.arguments[1].type == 'f')
        (clips.count(m.arguments[0].text) ? applied : ignored).insert(m.arguments[0].text);
  }
};

const std::set<std::string> kVrm0Presets{"A",   "I",     "U",      "E",   "O",      "Blink",    "Blink_L", "Blink_R",
                                         "Joy", "Angry", "Sorrow", "Fun", "LookUp", "LookDown", "Neutral"};

std::set<std::string> perfectSyncAvatar() {  // a perfect-sync VRM: ARKit's 52 as clips named in PascalCase
  std::set<std::string> clips = kVrm0Presets;
  for (std::string_view name : formats::kArkitNames) {
    std::string pascal(name);
    pascal[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(pascal[0])));
    clips.insert(pascal);
  }
  return clips;
}

AvatarFrame speakingFrame(double yawDegrees = 0.0) {
  AvatarFrame frame;
  frame.timeSeconds = 1.5;
  for (std::size_t k = 0; k < frame.arkit.size(); ++k) frame.arkit[k] = 0.01f * static_cast<float>(k % 50);
  frame.vrm = {0.6f, 0.1f, 0.0f, 0.2f, 0.1f};
  frame.headDegrees = Eigen::Vector3d(0.0, yawDegrees, 0.0);
  return frame;
}

TEST(VmcReceivers, EveryDatagramFitsTheMtuAndUoscReadsEveryMessage) {
  for (const VmcNames names : {VmcNames::kVrm0, VmcNames::kVrm1, VmcNames::kPerfectSync, VmcNames::kPerfectSyncApple}) {
    const VmcOptions options{.names = names};
    const std::vector<std::vector<char>> packets = vmcPackets(speakingFrame(), options);
    const std::vector<ParsedMessage> messages = received(packets);
    ASSERT_FALSE(messages.empty());
    EXPECT_EQ(messages.back().path, "/VMC/Ext/Blend/Apply") << "applied after every value";
    EXPECT_EQ(
        std::count_if(messages.begin(), messages.end(), [](const ParsedMessage& m) { return m.path == "/VMC/Ext/T"; }),
        1)
        << "one time a frame (EVMC4U drops a Unity frame's packets after 30)";
    // The arithmetic that cuts the frame agrees with the bytes liblo writes.
    const std::vector<std::vector<OscMessage>> datagrams = vmcDatagrams(speakingFrame(), options);
    ASSERT_EQ(datagrams.size(), packets.size());
    for (std::size_t d = 0; d < packets.size(); ++d) {
      std::size_t bytes = 16;
      for (const OscMessage& m : datagrams[d]) bytes += m.bytes();
      EXPECT_EQ(bytes, packets[d].size());
    }
  }
  // The 52 perfect-sync values and the bones do not fit one datagram: a frame is cut, not fragmented.
  EXPECT_GT(vmcPackets(speakingFrame(), {.names = VmcNames::kPerfectSync}).size(), 1U);
}

TEST(VmcReceivers, Evmc4uKeepsTheHeadOnTheNeckAndNeverShutsDown) {
  Evmc4u evmc4u;
  for (int frame = 0; frame < 100; ++frame)
    evmc4u.receive(received(vmcPackets(speakingFrame(10.0 * std::sin(frame * 0.1)), {})));
  EXPECT_FALSE(evmc4u.shutdown);
  // It applies the positions received: the head stays a head's length above the neck, the neck a neck's above the
  // chest (at 0 the head would sink onto the neck's joint).
  EXPECT_NEAR(evmc4u.localPosition.at("Head").y(), 0.085f, 1e-6f);
  EXPECT_NEAR(evmc4u.localPosition.at("Neck").y(), 0.13f, 1e-6f);
  EXPECT_EQ(evmc4u.localPosition.at("root"), Eigen::Vector3f::Zero());
  // Lengths of the user's own avatar, if given.
  Evmc4u custom;
  custom.receive(received(vmcPackets(speakingFrame(), {.neckLength = 0.11f, .headLength = 0.07f})));
  EXPECT_NEAR(custom.localPosition.at("Head").y(), 0.07f, 1e-6f);
  EXPECT_NEAR(custom.localPosition.at("Neck").y(), 0.11f, 1e-6f);
}

TEST(VmcReceivers, AYawToTheSpeakersLeftTurnsTheAvatarToItsLeftInUnity) {
  // Unity: left-handed, y up, the avatar facing +z; a positive turn about y turns it to its right. Our yaw is
  // positive to the speaker's left, so +20° is -20° about Unity's y: (0, -sin 10°, 0, cos 10°), shared between
  // the neck and the head.
  Evmc4u evmc4u;
  evmc4u.receive(received(vmcPackets(speakingFrame(20.0), {})));
  const Eigen::Quaternionf whole = evmc4u.localRotation.at("Neck") * evmc4u.localRotation.at("Head");
  const float s = std::sin(10.0f * 3.14159265f / 180.0f), c = std::cos(10.0f * 3.14159265f / 180.0f);
  EXPECT_NEAR(whole.x(), 0.0f, 1e-6f);
  EXPECT_NEAR(whole.y(), -s, 1e-6f);
  EXPECT_NEAR(whole.z(), 0.0f, 1e-6f);
  EXPECT_NEAR(whole.w(), c, 1e-6f);
  const Eigen::AngleAxisf neck(evmc4u.localRotation.at("Neck"));
  EXPECT_NEAR(neck.angle() * 180.0f / 3.14159265f, 0.4f * 20.0f, 1e-3f) << "the neck's share";
}

TEST(VmcReceivers, VMagicMirrorAppliesEveryNameOfTheSetChosenAndNothingIsDrivenTwice) {
  // The default: VRM 0.x's names, which every VRM avatar has; the mouth by the vowels alone.
  VMagicMirror vrm(kVrm0Presets);
  vrm.receive(received(vmcPackets(speakingFrame(), {})));
  EXPECT_EQ(vrm.applied, (std::set<std::string>{"A", "I", "U", "E", "O", "Blink_L", "Blink_R"}));
  EXPECT_TRUE(vrm.ignored.empty());

  // A perfect-sync avatar: the 52 by their clips' names, and no vowels beside them (JawOpen and A would add).
  VMagicMirror perfect(perfectSyncAvatar());
  perfect.receive(received(vmcPackets(speakingFrame(), {.names = VmcNames::kPerfectSync})));
  EXPECT_EQ(perfect.applied.size(), 52U);
  EXPECT_TRUE(perfect.ignored.empty());
  EXPECT_FALSE(perfect.applied.count("A"));
  // Apple's spelling, as sent before: VMagicMirror matches names exactly, and applies none of them.
  VMagicMirror apple(perfectSyncAvatar());
  apple.receive(received(vmcPackets(speakingFrame(), {.names = VmcNames::kPerfectSyncApple})));
  EXPECT_EQ(apple.applied.size(), 0U);
  EXPECT_EQ(apple.ignored.size(), 52U);

  // VRM 1.0's expression names, for avatars that have only those.
  VMagicMirror vrm1({"aa", "ih", "ou", "ee", "oh", "blink", "blinkLeft", "blinkRight"});
  vrm1.receive(received(vmcPackets(speakingFrame(), {.names = VmcNames::kVrm1})));
  EXPECT_EQ(vrm1.applied.size(), 7U);
  EXPECT_TRUE(vrm1.ignored.empty());
  // EVMC4U matches lower-cased: the default names reach it too.
  Evmc4u evmc4u;
  evmc4u.clips = {"a", "i", "u", "e", "o", "blink_l", "blink_r"};
  evmc4u.receive(received(vmcPackets(speakingFrame(), {})));
  EXPECT_EQ(evmc4u.applied.size(), 7U);
}

TEST(VmcReceivers, AnAssistantSendsTheBlendshapesAloneToAPerformer) {
  const std::vector<ParsedMessage> messages =
      received(vmcPackets(speakingFrame(15.0), {.role = VmcRole::kAssistant, .names = VmcNames::kPerfectSync}));
  for (const ParsedMessage& m : messages)
    EXPECT_TRUE(m.path == "/VMC/Ext/Blend/Val" || m.path == "/VMC/Ext/Blend/Apply") << m.path;
  EXPECT_EQ(messages.size(), 53U);
  EXPECT_EQ(messages.back().path, "/VMC/Ext/Blend/Apply");
}

TEST(VmcReceivers, UnknownNameSetsAreRefusedInOneLine) {
  EXPECT_EQ(parseVmcNames("perfect-sync", "--vmc-names"), VmcNames::kPerfectSync);
  try {
    parseVmcNames("arkit", "--vmc-names");
    FAIL() << "accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("--vmc-names: 'arkit'"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace th::outputs
