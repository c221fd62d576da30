// The VMC protocol (https://protocol.vmc.info, github sh-akira/VirtualMotionCaptureProtocol), in either of the
// two roles a face-only source can play:
//
// - Performer, to a Marionette (EVMC4U, VMagicMirror's VMC input, Warudo, VMC4B; port 39539), each frame
//     /VMC/Ext/OK 1                                 the avatar is loaded
//     /VMC/Ext/T TIME                               the frame's time, seconds (once a frame: EVMC4U drops a
//                                                   Unity frame's packets after 30 of them)
//     /VMC/Ext/Root/Pos root 0 0 0 0 0 0 1          the avatar where it stands
//     /VMC/Ext/Bone/Pos Neck px py pz qx qy qz qw   local poses, in Unity's frame (left-handed, y up, the avatar
//     /VMC/Ext/Bone/Pos Head px py pz qx qy qz qw   facing +z, x to its right; metres): the head's rotation
//                                                   shared between the two, each at a standard humanoid's offset
//                                                   from its parent (receivers such as EVMC4U apply positions:
//                                                   at 0 the head would sink onto the neck's joint)
//     /VMC/Ext/Blend/Val NAME VALUE ...             one name set (below), so nothing is driven twice
//     /VMC/Ext/Blend/Apply
// - Assistant, to a Performer's assistant input (VSeeFace, Virtual Motion Capture; port 39540): the blendshapes
//   alone (Blend/Val, Apply), as the Performer specification takes them.
//
// Names are case-sensitive (VMagicMirror matches them exactly): VRM 0.x's A I U E O Blink_L Blink_R (every VRM
// avatar has them; the specification asks senders for these), VRM 1.0's aa ih ou ee oh blinkLeft blinkRight,
// or ARKit's 52 for "perfect sync" avatars, as their clips are named (JawOpen, EyeBlinkLeft) or as Apple spells
// them (jawOpen). A frame is cut into bundles of at most 1,400 bytes (one datagram each, unfragmented on an
// ordinary network), Apply in the last, after every value.
// Thread contract: as LiveOutput; vmcMessages is a pure function.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "outputs/live_output.h"
#include "outputs/osc_sender.h"

namespace th::outputs {

enum class VmcRole { kPerformer, kAssistant };
enum class VmcNames { kVrm0, kVrm1, kPerfectSync, kPerfectSyncApple };

// "vrm0", "vrm1", "perfect-sync", "perfect-sync-apple"; throws th::Error naming `option` for other text.
VmcNames parseVmcNames(std::string_view text, std::string_view option);

// `live --vmc [HOST:]PORT` (to a Marionette), `--vmc-assistant` (to a Performer's assistant input) and the
// options both share (live_output.h: an output's settings).
struct VmcSettings {
  static constexpr std::string_view kPrefix = "vmc";
  static constexpr std::string_view kDefaultAddress = "127.0.0.1:39539";
  static constexpr std::string_view kDefaultAssistantAddress = "127.0.0.1:39540";
  std::string address;         // the VMC protocol as a Performer, to a Marionette: [HOST:]PORT (empty: off)
  std::string assistant;       // as an Assistant, to a Performer (VSeeFace, Virtual Motion Capture) (empty: off)
  std::string names = "vrm0";  // the blendshapes' names: parseVmcNames
  // The neck's joint above its parent's (the upper chest) and the head's above the neck's, metres: a standard
  // humanoid's (the two avatars of the test data: 0.124 / 0.143 and 0.091 / 0.082).
  double neckLength = 0.13;
  double headLength = 0.085;
  double neckShare = 0.4;  // of the head's rotation turned at the neck, the rest at the head

  void visitOptions(OptionVisitor& v);
  void addRows(std::vector<OutputRow>& rows);
  void open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const;
};

struct VmcOptions {
  VmcRole role = VmcRole::kPerformer;
  VmcNames names = VmcNames::kVrm0;
  float neckLength = static_cast<float>(VmcSettings{}.neckLength);  // VmcSettings says what each is
  float headLength = static_cast<float>(VmcSettings{}.headLength);
  float neckShare = static_cast<float>(VmcSettings{}.neckShare);
  // false: the avatar turns as the speaker does (to its own left when they turn to theirs); true: as their
  // mirror image (the yaw and the roll the other way).
  bool mirrorHead = false;
  int maxDatagramBytes = 1400;
};

// A frame's messages, cut into datagrams (each one bundle of at most options.maxDatagramBytes bytes).
std::vector<std::vector<OscMessage>> vmcDatagrams(const AvatarFrame& frame, const VmcOptions& options);
// The same as the bytes sent: one serialised OSC bundle a datagram.
std::vector<std::vector<char>> vmcPackets(const AvatarFrame& frame, const VmcOptions& options);
// The names sent, in order, and their values for a frame.
std::vector<std::pair<std::string, float>> vmcBlendshapes(const AvatarFrame& frame, VmcNames names);

class VmcOutput final : public LiveOutput {
 public:
  VmcOutput(UdpEndpoint endpoint, const VmcOptions& options) : sender_(std::move(endpoint)), options_(options) {}
  void send(const AvatarFrame& frame) override;
  OutputStatus status() const override;

 private:
  OscSender sender_;
  VmcOptions options_;
  std::uint64_t framesSent_ = 0;     // every datagram of the frame went out
  std::uint64_t framesDropped_ = 0;  // one or more did not
};

}  // namespace th::outputs
