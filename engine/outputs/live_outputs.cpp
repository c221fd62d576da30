#include <charconv>
#include <cstdio>

#include "core/error.h"
#include "outputs/live_output.h"

namespace th::outputs {

std::string describe(const OutputStatus& status, double seconds) {
  char text[256];
  std::snprintf(text, sizeof text, "%s %s: %llu frames sent, %.1f a second, %llu dropped; %s", status.name.c_str(),
                status.target.c_str(), static_cast<unsigned long long>(status.framesSent),
                seconds > 0.0 ? static_cast<double>(status.framesSent) / seconds : 0.0,
                static_cast<unsigned long long>(status.framesDropped), status.state.c_str());
  return text;
}

int defaultPortOf(std::string_view defaultAddress) {
  const std::size_t colon = defaultAddress.rfind(':');
  int port = 0;
  const std::string_view digits = defaultAddress.substr(colon + 1);
  if (colon == std::string_view::npos ||
      std::from_chars(digits.data(), digits.data() + digits.size(), port).ec != std::errc{})
    throw Error("an output's default address has no port: " + std::string(defaultAddress));
  return port;
}

}  // namespace th::outputs
