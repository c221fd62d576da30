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
