// Plain OSC for anything else that listens (TouchDesigner, Max, Pure Data; VRChat has its own, vrchat_output.h):
// each frame one bundle
//   /talkinghead/time SECONDS
//   /talkinghead/fap/N VALUE              each FAP the decoder sets (its value in FAP units, face/fap.h)
//   /talkinghead/viseme/NAME WEIGHT       Oculus's 15 visemes (sil PP FF ... ou), when there is a viseme model
//   /talkinghead/vrm/NAME WEIGHT          VRM's A I U E O, likewise
//   /talkinghead/head PITCH YAW ROLL      degrees (avatar_frame.h's convention)
//   /talkinghead/jaw OPEN                 ARKit's jawOpen, 0..1
// Thread contract: as LiveOutput.
#pragma once

#include <vector>

#include "outputs/live_output.h"
#include "outputs/osc_sender.h"

namespace th::outputs {

// `live --osc [HOST:]PORT` (live_output.h: an output's settings).
struct OscSettings {
  static constexpr std::string_view kPrefix = "osc";
  static constexpr std::string_view kDefaultAddress = "127.0.0.1:9100";  // beside VRChat's 9000 and 9001
  std::string address;                                                   // empty: off

  void visitOptions(OptionVisitor& v);
  void addRows(std::vector<OutputRow>& rows);
  void open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const;
};

class OscOutput final : public LiveOutput {
 public:
  // faps: the FAP numbers to send (the decoder's).
  OscOutput(UdpEndpoint endpoint, std::vector<int> faps) : sender_(std::move(endpoint)), faps_(std::move(faps)) {}
  void send(const AvatarFrame& frame) override;
  OutputStatus status() const override;
  void fill(OscBundle& bundle, const AvatarFrame& frame) const;

 private:
  OscSender sender_;
  std::vector<int> faps_;
};

}  // namespace th::outputs
