#include "outputs/vrchat_output.h"

#include <algorithm>
#include <cmath>

#include "formats/arkit_format.h"

namespace th::outputs {
namespace {

float arkit(const AvatarFrame& frame, std::string_view name) {
  return frame.arkit[static_cast<std::size_t>(formats::arkitIndex(name))];
}

float clampSigned(float value) {
  return std::clamp(value, -1.0f, 1.0f);
}

}  // namespace

std::vector<std::pair<std::string, float>> vrchatParameters(const AvatarFrame& frame) {
  const float jaw = arkit(frame, "jawOpen");
  const auto lid = [&](std::string_view side) {
    const std::string s(side);
    return std::clamp(0.75f * (1.0f - arkit(frame, "eyeBlink" + s)) + 0.25f * arkit(frame, "eyeWide" + s), 0.0f, 1.0f);
  };
  return {
      {"JawOpen", jaw},
      {"MouthClosed", std::min(arkit(frame, "mouthClose"), jaw)},
      {"LipFunnel", arkit(frame, "mouthFunnel")},
      {"LipPucker", arkit(frame, "mouthPucker")},
      {"MouthUpperUp", 0.5f * (arkit(frame, "mouthUpperUpLeft") + arkit(frame, "mouthUpperUpRight"))},
      {"MouthLowerDown", 0.5f * (arkit(frame, "mouthLowerDownLeft") + arkit(frame, "mouthLowerDownRight"))},
      {"MouthSmileLeft", arkit(frame, "mouthSmileLeft")},
      {"MouthSmileRight", arkit(frame, "mouthSmileRight")},
      {"SmileFrownLeft", clampSigned(arkit(frame, "mouthSmileLeft") - arkit(frame, "mouthFrownLeft"))},
      {"SmileFrownRight", clampSigned(arkit(frame, "mouthSmileRight") - arkit(frame, "mouthFrownRight"))},
      {"EyeLidLeft", lid("Left")},
      {"EyeLidRight", lid("Right")},
      // + to the right (the avatar's, as a person's gaze): the left eye looks right when it looks in.
      {"EyeLeftX", clampSigned(arkit(frame, "eyeLookInLeft") - arkit(frame, "eyeLookOutLeft"))},
      {"EyeRightX", clampSigned(arkit(frame, "eyeLookOutRight") - arkit(frame, "eyeLookInRight"))},
      {"EyeY", clampSigned(0.5f * (arkit(frame, "eyeLookUpLeft") + arkit(frame, "eyeLookUpRight") -
                                   arkit(frame, "eyeLookDownLeft") - arkit(frame, "eyeLookDownRight")))},
  };
}

std::vector<OscMessage> VrchatMessages::of(const AvatarFrame& frame, bool refresh) {
  const std::string base = "/avatar/parameters/";
  std::vector<OscMessage> messages;
  if (refresh) {
    messages.push_back({base + "LipTrackingActive", {true}});
    messages.push_back({base + "EyeTrackingActive", {true}});
  }
  for (const auto& [name, value] : vrchatParameters(frame)) {
    const auto last = sent_.find(name);
    if (!refresh && last != sent_.end() && std::abs(last->second - value) < options_.changeThreshold) continue;
    sent_[name] = value;
    const std::string address = base + options_.prefix + name;
    messages.push_back({address, {value}});
    if (options_.bits <= 0) continue;
    // VRCFaceTracking's BinaryBaseParameter: the magnitude in N bits, all on at full scale; the sign apart.
    const float magnitude = std::abs(value);
    const long steps = 1L << options_.bits;
    const long k = magnitude > 0.99999f ? steps - 1 : static_cast<long>(magnitude * static_cast<float>(steps));
    for (int bit = 0; bit < options_.bits; ++bit)
      messages.push_back({address + std::to_string(1L << bit), {((k >> bit) & 1L) != 0}});
    messages.push_back({address + "Negative", {value < 0.0f}});
  }
  return messages;
}

void VrchatOutput::send(const AvatarFrame& frame) {
  const bool refresh = frame.timeSeconds - lastRefresh_ >= options_.refreshSeconds || frame.timeSeconds < lastRefresh_;
  if (refresh) lastRefresh_ = frame.timeSeconds;
  std::vector<OscMessage> messages = messages_.of(frame, refresh);
  if (messages.empty()) return;  // nothing changed
  bool whole = true;
  for (const std::vector<OscMessage>& datagram : cutIntoDatagrams(std::move(messages), options_.maxDatagramBytes))
    whole = sender_.send(serialiseBundle(datagram)) && whole;
  ++(whole ? framesSent_ : framesDropped_);
}

OutputStatus VrchatOutput::status() const {
  OutputStatus status = sender_.statusAs("VRChat");
  status.framesSent = framesSent_;
  status.framesDropped = framesDropped_;
  return status;
}

}  // namespace th::outputs

namespace th::outputs {

void VrchatSettings::visitOptions(OptionVisitor& v) {
  v.option(address, {.name = "",
                     .help = "Drive a VRChat avatar's face-tracking parameters (VRCFaceTracking's Unified "
                             "Expressions: JawOpen, MouthClosed, LipFunnel, EyeLid...) over OSC: [HOST:]PORT",
                     .panel = false,
                     .implicitValue = kDefaultAddress});
  v.option(prefix, {.name = "prefix",
                    .help = "VRChat: the prefix of the avatar's face-tracking parameters (\"v2/\" for "
                            "avatars without VRCFaceTracking templates' \"FT/\")",
                    .panel = false});
  v.option(bits, {.name = "bits",
                  .help = "VRChat: binary parameters per value as the avatar syncs them (NAME1, NAME2, NAME4, "
                          "... and NAMENegative; 0: floats only)",
                  .min = 0,
                  .max = 8,
                  .panel = false});
}

void VrchatSettings::addRows(std::vector<OutputRow>& rows) {
  rows.push_back({"VRChat (face-tracking avatars)", "VRChat", &address, kDefaultAddress});
}

void VrchatSettings::open(const OutputContext& /*context*/, std::vector<std::unique_ptr<LiveOutput>>& outputs) const {
  if (address.empty()) return;
  outputs.push_back(
      std::make_unique<VrchatOutput>(parseUdpEndpoint(address, defaultPortOf(kDefaultAddress), "--vrchat"),
                                     VrchatOptions{.prefix = prefix, .bits = bits}));
}

}  // namespace th::outputs
