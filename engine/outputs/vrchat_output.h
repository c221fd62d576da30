// VRChat's OSC input (docs.vrchat.com/docs/osc-overview: it listens on 9000): avatar parameters, one value a
// message, at /avatar/parameters/NAME. The face drives the parameters that face-tracking avatars already carry,
// VRCFaceTracking's Unified Expressions (github benaclejames/VRCFaceTracking, docs.vrcft.io), under the prefix
// the avatar's parameters have (VRCFaceTracking's templates: "FT/v2/"):
//   JawOpen, MouthClosed (never above JawOpen, as VRCFaceTracking clamps it), LipFunnel, LipPucker,
//   MouthUpperUp, MouthLowerDown, MouthSmileLeft/Right 0..1, SmileFrownLeft/Right -1..1,
//   EyeLidLeft/Right 0..1 (0.75 open, 0 shut, 1 wide), EyeLeftX, EyeRightX, EyeY -1..1 (+ right, up),
// and, at the start and every refreshSeconds, the bools LipTrackingActive and EyeTrackingActive (no prefix)
// that such avatars switch their tracking on with. Many avatars sync parameters as bits: with bits N > 0, each
// value goes also as bools NAME1, NAME2, NAME4 ... (N of them) and NAMENegative, quantised as VRCFaceTracking's
// BinaryBaseParameter does (k = floor(|v| 2^N), bit i of k; all on above 0.99999). Only values that changed
// are sent (everything again every refreshSeconds, for an avatar loaded since), in bundles of at most 1,400
// bytes.
// Thread contract: as LiveOutput.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "outputs/live_output.h"
#include "outputs/osc_sender.h"

namespace th::outputs {

struct VrchatOptions {
  std::string prefix = "FT/v2/";  // before each face parameter's name
  int bits = 0;                   // binary parameters per value (0: floats only)
  double refreshSeconds = 2.0;    // everything sent again
  double changeThreshold = 1.0 / 256.0;
  int maxDatagramBytes = 1400;
};

// `live --vrchat [HOST:]PORT` and its options (live_output.h: an output's settings).
struct VrchatSettings {
  static constexpr std::string_view kPrefix = "vrchat";
  static constexpr std::string_view kDefaultAddress = "127.0.0.1:9000";  // VRChat's own input port
  std::string address;                                                   // empty: off
  std::string prefix = VrchatOptions{}.prefix;  // before each face parameter's name, as the avatar has them
  int bits = VrchatOptions{}.bits;              // binary parameters per value (0: floats only)

  void visitOptions(OptionVisitor& v);
  void addRows(std::vector<OutputRow>& rows);
  void open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const;
};

// The face's Unified Expressions values for a frame (names without the prefix), in a fixed order.
std::vector<std::pair<std::string, float>> vrchatParameters(const AvatarFrame& frame);

// The messages that say a frame, given what was sent before (updated); `refresh`: all of them.
class VrchatMessages {
 public:
  explicit VrchatMessages(const VrchatOptions& options) : options_(options) {}
  std::vector<OscMessage> of(const AvatarFrame& frame, bool refresh);

 private:
  VrchatOptions options_;
  std::map<std::string, float> sent_;
};

class VrchatOutput final : public LiveOutput {
 public:
  VrchatOutput(UdpEndpoint endpoint, const VrchatOptions& options)
      : sender_(std::move(endpoint)), options_(options), messages_(options) {}
  void send(const AvatarFrame& frame) override;
  OutputStatus status() const override;

 private:
  OscSender sender_;
  VrchatOptions options_;
  VrchatMessages messages_;
  double lastRefresh_ = -1e9;
  std::uint64_t framesSent_ = 0, framesDropped_ = 0;
};

}  // namespace th::outputs
