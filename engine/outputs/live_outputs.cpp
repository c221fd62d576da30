#include <cstdio>

#include "outputs/live_output.h"
#include "outputs/osc_output.h"
#include "outputs/vmc_output.h"
#include "outputs/vrchat_output.h"
#include "outputs/vts_output.h"

namespace th::outputs {

std::string describe(const OutputStatus& status, double seconds) {
  char text[256];
  std::snprintf(text, sizeof text, "%s %s: %llu frames sent, %.1f a second, %llu dropped; %s", status.name.c_str(),
                status.target.c_str(), static_cast<unsigned long long>(status.framesSent),
                seconds > 0.0 ? static_cast<double>(status.framesSent) / seconds : 0.0,
                static_cast<unsigned long long>(status.framesDropped), status.state.c_str());
  return text;
}

std::vector<std::unique_ptr<LiveOutput>> openOutputs(const pipeline::OutputSettings& options,
                                                     const std::vector<int>& faps,
                                                     std::function<void(const std::string&)> tokenIssued) {
  std::vector<std::unique_ptr<LiveOutput>> outputs;
  VmcOptions vmc{.names = parseVmcNames(options.vmcNames, "--vmc-names"),
                 .neckLength = static_cast<float>(options.vmcNeckLength),
                 .headLength = static_cast<float>(options.vmcHeadLength),
                 .neckShare = static_cast<float>(options.vmcNeckShare),
                 .mirrorHead = options.mirrorHead};
  if (!options.vmc.empty())
    outputs.push_back(std::make_unique<VmcOutput>(parseUdpEndpoint(options.vmc, 39539, "--vmc"), vmc));
  if (!options.vmcAssistant.empty()) {
    vmc.role = VmcRole::kAssistant;
    outputs.push_back(
        std::make_unique<VmcOutput>(parseUdpEndpoint(options.vmcAssistant, 39540, "--vmc-assistant"), vmc));
  }
  if (!options.vrchat.empty())
    outputs.push_back(
        std::make_unique<VrchatOutput>(parseUdpEndpoint(options.vrchat, 9000, "--vrchat"),
                                       VrchatOptions{.prefix = options.vrchatPrefix, .bits = options.vrchatBits}));
  if (!options.osc.empty())
    outputs.push_back(std::make_unique<OscOutput>(parseUdpEndpoint(options.osc, 9100, "--osc"), faps));
  if (!options.vts.empty())
    outputs.push_back(std::make_unique<VtsOutput>(parseVtsUrl(options.vts), options.vtsToken, std::move(tokenIssued),
                                                  VtsOptions{.mirrorHead = options.mirrorHead}));
  return outputs;
}

}  // namespace th::outputs
