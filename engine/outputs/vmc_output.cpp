#include "outputs/vmc_output.h"

#include <array>
#include <cctype>

#include "core/error.h"
#include "formats/arkit_format.h"

namespace th::outputs {
namespace {

constexpr std::array<std::string_view, 5> kVrm1Vowels{"aa", "ih", "ou", "ee", "oh"};

std::string pascalCase(std::string_view apple) {
  std::string name(apple);
  name[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
  return name;
}

OscMessage boneMessage(std::string name, const Eigen::Vector3f& position, const Eigen::Quaternionf& rotation) {
  return {"/VMC/Ext/Bone/Pos",
          {std::move(name), position.x(), position.y(), position.z(), rotation.x(), rotation.y(), rotation.z(),
           rotation.w()}};
}

}  // namespace

VmcNames parseVmcNames(std::string_view text, std::string_view option) {
  if (text == "vrm0") return VmcNames::kVrm0;
  if (text == "vrm1") return VmcNames::kVrm1;
  if (text == "perfect-sync") return VmcNames::kPerfectSync;
  if (text == "perfect-sync-apple") return VmcNames::kPerfectSyncApple;
  throw Error(std::string(option) + ": '" + std::string(text) +
              "' is not one of vrm0, vrm1, perfect-sync, perfect-sync-apple");
}

std::vector<std::pair<std::string, float>> vmcBlendshapes(const AvatarFrame& frame, VmcNames names) {
  std::vector<std::pair<std::string, float>> values;
  switch (names) {
    case VmcNames::kVrm0:
      for (std::size_t k = 0; k < face::kVrmVowelNames.size(); ++k)
        values.emplace_back(face::kVrmVowelNames[k], frame.vrm[k]);
      values.emplace_back("Blink_L", frame.blinkLeft());
      values.emplace_back("Blink_R", frame.blinkRight());
      break;
    case VmcNames::kVrm1:
      for (std::size_t k = 0; k < kVrm1Vowels.size(); ++k) values.emplace_back(kVrm1Vowels[k], frame.vrm[k]);
      values.emplace_back("blinkLeft", frame.blinkLeft());
      values.emplace_back("blinkRight", frame.blinkRight());
      break;
    case VmcNames::kPerfectSync:
    case VmcNames::kPerfectSyncApple:
      for (std::size_t k = 0; k < formats::kArkitNames.size(); ++k)
        values.emplace_back(names == VmcNames::kPerfectSync ? pascalCase(formats::kArkitNames[k])
                                                            : std::string(formats::kArkitNames[k]),
                            frame.arkit[k]);
      break;
  }
  return values;
}

std::vector<std::vector<OscMessage>> vmcDatagrams(const AvatarFrame& frame, const VmcOptions& options) {
  std::vector<OscMessage> messages;
  if (options.role == VmcRole::kPerformer) {
    messages.push_back({"/VMC/Ext/OK", {std::int32_t{1}}});
    messages.push_back({"/VMC/Ext/T", {static_cast<float>(frame.timeSeconds)}});
    messages.push_back({"/VMC/Ext/Root/Pos", {std::string("root"), 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f}});
    // The head's rotation as two turns about the same axis, the neck's share first: together exactly the head's.
    Eigen::Quaternionf head = frame.unityHeadRotation();
    if (options.mirrorHead) head = Eigen::Quaternionf(head.w(), head.x(), -head.y(), -head.z());
    const Eigen::Quaternionf neck = Eigen::Quaternionf::Identity().slerp(options.neckShare, head);
    const Eigen::Quaternionf rest = (neck.conjugate() * head).normalized();
    messages.push_back(boneMessage("Neck", {0.0f, options.neckLength, 0.0f}, neck));
    messages.push_back(boneMessage("Head", {0.0f, options.headLength, 0.0f}, rest));
  }
  for (auto& [name, value] : vmcBlendshapes(frame, options.names))
    messages.push_back({"/VMC/Ext/Blend/Val", {std::move(name), value}});
  messages.push_back({"/VMC/Ext/Blend/Apply", {}});

  return cutIntoDatagrams(std::move(messages), options.maxDatagramBytes);
}

std::vector<std::vector<char>> vmcPackets(const AvatarFrame& frame, const VmcOptions& options) {
  std::vector<std::vector<char>> packets;
  for (const std::vector<OscMessage>& datagram : vmcDatagrams(frame, options))
    packets.push_back(serialiseBundle(datagram));
  return packets;
}

void VmcOutput::send(const AvatarFrame& frame) {
  bool whole = true;
  for (const std::vector<char>& packet : vmcPackets(frame, options_)) whole = sender_.send(packet) && whole;
  ++(whole ? framesSent_ : framesDropped_);
}

OutputStatus VmcOutput::status() const {
  OutputStatus status = sender_.statusAs(options_.role == VmcRole::kAssistant ? "VMC assistant" : "VMC");
  status.framesSent = framesSent_;
  status.framesDropped = framesDropped_;
  return status;
}

}  // namespace th::outputs

namespace th::outputs {

void VmcSettings::visitOptions(OptionVisitor& v) {
  v.option(address,
           {.name = "",
            .help = "Send the face and head to a VMC Marionette (VMagicMirror, EVMC4U, Warudo, VMC4B): [HOST:]PORT",
            .panel = false,
            .implicitValue = kDefaultAddress});
  v.option(assistant,
           {.name = "assistant",
            .help = "Send the face's blendshapes to a VMC Performer's assistant input (VSeeFace, Virtual Motion "
                    "Capture): [HOST:]PORT",
            .panel = false,
            .implicitValue = kDefaultAssistantAddress});
  static constexpr std::array<std::string_view, 4> kNames{"vrm0", "vrm1", "perfect-sync", "perfect-sync-apple"};
  v.option(names, {.name = "names",
                   .help = "VMC blendshape names: VRM 0.x (A I U E O Blink_L Blink_R), VRM 1.0 (aa ih ou ee oh "
                           "blinkLeft blinkRight), ARKit's 52 as perfect-sync avatars name them (JawOpen) or "
                           "as Apple spells them (jawOpen)",
                   .choices = kNames,
                   .panel = false});
  v.option(neckLength, {.name = "neck-length-m",
                        .help = "VMC: the neck's joint above the upper chest's (the Neck bone's local position)",
                        .unit = "m",
                        .min = 0.0,
                        .max = 1.0,
                        .panel = false,
                        .formerName = "neck-length"});
  v.option(headLength, {.name = "head-length-m",
                        .help = "VMC: the head's joint above the neck's (the Head bone's local position)",
                        .unit = "m",
                        .min = 0.0,
                        .max = 1.0,
                        .panel = false,
                        .formerName = "head-length"});
  v.option(neckShare, {.name = "neck-share",
                       .help = "VMC: the share of the head's rotation turned at the neck (the rest at the head)",
                       .min = 0.0,
                       .max = 1.0,
                       .panel = false});
}

void VmcSettings::addRows(std::vector<OutputRow>& rows) {
  rows.push_back({"VMC (VMagicMirror, EVMC4U, Warudo, VMC4B)", "VMC", &address, kDefaultAddress});
  rows.push_back(
      {"VMC assistant (VSeeFace, Virtual Motion Capture)", "VMC assistant", &assistant, kDefaultAssistantAddress});
}

void VmcSettings::open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const {
  VmcOptions options{.names = parseVmcNames(names, "--vmc-names"),
                     .neckLength = static_cast<float>(neckLength),
                     .headLength = static_cast<float>(headLength),
                     .neckShare = static_cast<float>(neckShare),
                     .mirrorHead = context.mirrorHead};
  if (!address.empty())
    outputs.push_back(
        std::make_unique<VmcOutput>(parseUdpEndpoint(address, defaultPortOf(kDefaultAddress), "--vmc"), options));
  if (!assistant.empty()) {
    options.role = VmcRole::kAssistant;
    outputs.push_back(std::make_unique<VmcOutput>(
        parseUdpEndpoint(assistant, defaultPortOf(kDefaultAssistantAddress), "--vmc-assistant"), options));
  }
}

}  // namespace th::outputs
