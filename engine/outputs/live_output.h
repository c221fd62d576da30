// A live output: where the face's frames go besides the window, to another program. Each output takes the frame
// the face shows and sends it without blocking the caller (a lost receiver never stalls the face); what it could
// not send is counted.
//
//   auto outputs = th::outputs::openOutputs(settings.outputs, decoderFaps, tokenSaver);
//   for (auto& output : outputs) output->send(avatar);          // each frame the face shows
//   output->status();                                           // for the panel and the run's summary
//
// The outputs: VMC (vmc_output.h), plain OSC (osc_output.h), VTube Studio (vts_output.h).
// Thread contract: send() and status() from one thread (the display's); an output may run a thread of its own.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "outputs/avatar_frame.h"
#include "pipeline/options.h"

namespace th::outputs {

struct OutputStatus {
  std::string name;        // "VMC", "OSC", "VTube Studio"
  std::string target;      // "127.0.0.1:39539", "ws://localhost:8001"
  bool connected = false;  // UDP: the last send went out; VTube Studio: authenticated
  std::string state;       // a few words for the panel: "sending", "waiting for VTube Studio to allow the plugin"
  std::uint64_t framesSent = 0;
  std::uint64_t framesDropped = 0;
  bool refused = false;  // the receiver's user refused us: not asked again until the output is opened again
};

class LiveOutput {
 public:
  virtual ~LiveOutput() = default;
  virtual void send(const AvatarFrame& frame) = 0;
  virtual OutputStatus status() const = 0;
};

// A token VTube Studio issued, handed from the output's thread to whoever keeps the settings.
class IssuedToken {
 public:
  void set(const std::string& token) {
    const std::lock_guard lock(mutex_);
    token_ = token;
  }
  std::string get() const {
    const std::lock_guard lock(mutex_);
    return token_;
  }

 private:
  mutable std::mutex mutex_;
  std::string token_;
};

// "VMC 127.0.0.1:39539: 900 frames sent, 30.0 a second, 0 dropped; sending" for the run's summary.
std::string describe(const OutputStatus& status, double seconds);

// The outputs the options name, opened (throws th::Error for an address that cannot be); faps: the FAPs the
// decoder sets (plain OSC sends them). tokenIssued is called (on the VTube Studio output's thread) with a token
// VTube Studio issues, for the settings to keep.
std::vector<std::unique_ptr<LiveOutput>> openOutputs(const pipeline::OutputSettings& options,
                                                     const std::vector<int>& faps,
                                                     std::function<void(const std::string&)> tokenIssued = {});

}  // namespace th::outputs
