// A live output: where the face's frames go besides the window, to another program. Each output takes the frame
// the face shows and sends it without blocking the caller (a lost receiver never stalls the face); what it could
// not send is counted.
//
//   auto outputs = settings.outputs.open({.faps = decoderFaps, .tokenIssued = tokenSaver});   // output_settings.h
//   for (auto& output : outputs) output->send(avatar);          // each frame the face shows
//   output->status();                                           // for the panel and the run's summary
//
// A new output is one file and a line. The file holds its LiveOutput and its Settings: a struct with its options
// and their defaults, declared once, under its prefix (as Kaldi's Register takes a prefix: VmcSettings' "names"
// is `--vmc-names`, its address, the option named "", is `--vmc`), which makes the rows of the window's Outputs
// panel and opens the output:
//
//   struct MySettings {
//     static constexpr std::string_view kPrefix = "my";
//     std::string address;                     // empty: off
//     void visitOptions(OptionVisitor& v);     // v.option(address, {.name = "", .implicitValue = ...}) ...
//     void addRows(std::vector<OutputRow>& rows);
//     void open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const;
//   };
//
// The line adds MySettings to OutputKinds (output_settings.h): live's flags, its settings file and the panel
// then have it (tests/outputs/output_settings_test.cpp keeps this true).
// The outputs: VMC (vmc_output.h), VRChat (vrchat_output.h), plain OSC (osc_output.h), VTube Studio
// (vts_output.h).
// Thread contract: send() and status() from one thread (the display's); an output may run a thread of its own.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/options.h"
#include "outputs/avatar_frame.h"

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

// What every output is opened with besides its own settings.
struct OutputContext {
  std::vector<int> faps;    // the FAPs the decoder sets (plain OSC sends them)
  bool mirrorHead = false;  // the avatar turns as the speaker's mirror image (VMC, VTube Studio)
  // Called (on the VTube Studio output's thread) with a token VTube Studio issues, for the settings to keep.
  std::function<void(const std::string&)> tokenIssued;
};

// A row of the window's Outputs panel: a checkbox that sets an output's address (off: empty).
struct OutputRow {
  std::string_view title;           // "VMC (VMagicMirror, EVMC4U, Warudo, VMC4B)"
  std::string_view name;            // its OutputStatus::name, "VMC"
  std::string* address;             // the settings' field
  std::string_view defaultAddress;  // switched on: this
};

// The port of a default address ("127.0.0.1:39539" → 39539): the one an address naming only a host gets.
int defaultPortOf(std::string_view defaultAddress);

}  // namespace th::outputs
