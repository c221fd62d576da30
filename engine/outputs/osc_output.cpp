#include "outputs/osc_output.h"

#include <string>

namespace th::outputs {

void OscOutput::fill(OscBundle& bundle, const AvatarFrame& frame) const {
  bundle.add("/talkinghead/time").real(static_cast<float>(frame.timeSeconds));
  for (int fap : faps_)
    bundle.add("/talkinghead/fap/" + std::to_string(fap))
        .real(static_cast<float>(frame.faps[static_cast<std::size_t>(fap)]));
  if (frame.hasVisemes) {
    for (std::size_t k = 0; k < face::kOculusVisemeNames.size(); ++k)
      bundle.add("/talkinghead/viseme/" + std::string(face::kOculusVisemeNames[k])).real(frame.oculus[k]);
    for (std::size_t k = 0; k < face::kVrmVowelNames.size(); ++k)
      bundle.add("/talkinghead/vrm/" + std::string(face::kVrmVowelNames[k])).real(frame.vrm[k]);
  }
  bundle.add("/talkinghead/head")
      .real(static_cast<float>(frame.headDegrees[0]))
      .real(static_cast<float>(frame.headDegrees[1]))
      .real(static_cast<float>(frame.headDegrees[2]));
  bundle.add("/talkinghead/jaw").real(frame.jawOpen());
}

void OscOutput::send(const AvatarFrame& frame) {
  OscBundle bundle;
  fill(bundle, frame);
  sender_.send(bundle);
}

OutputStatus OscOutput::status() const {
  return sender_.statusAs("OSC");
}

}  // namespace th::outputs

namespace th::outputs {

void OscSettings::visitOptions(OptionVisitor& v) {
  v.option(address,
           {.name = "",
            .help = "Send FAPs, visemes and the head as plain OSC (TouchDesigner, Max, Pure Data): [HOST:]PORT",
            .panel = false,
            .implicitValue = kDefaultAddress});
}

void OscSettings::addRows(std::vector<OutputRow>& rows) {
  rows.push_back({"OSC (TouchDesigner, Max, Pure Data)", "OSC", &address, kDefaultAddress});
}

void OscSettings::open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const {
  if (address.empty()) return;
  outputs.push_back(
      std::make_unique<OscOutput>(parseUdpEndpoint(address, defaultPortOf(kDefaultAddress), "--osc"), context.faps));
}

}  // namespace th::outputs
