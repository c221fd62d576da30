// Where `live` sends the face besides its window: every output's settings, each declared by its output
// (live_output.h says how), gathered in one list. Live's flags, its settings file and the window's Outputs panel
// are made from them.
//
//   th::outputs::LiveSessionSettings settings;                       // the decoder's settings and the outputs'
//   settings.outputs.get<th::outputs::VmcSettings>().address = "127.0.0.1:39539";
//   auto outputs = settings.outputs.open({.faps = decoderFaps});    // those switched on
//
// Thread contract: values.
#pragma once

#include <memory>
#include <tuple>
#include <vector>

#include "core/options.h"
#include "outputs/live_output.h"
#include "outputs/osc_output.h"
#include "outputs/vmc_output.h"
#include "outputs/vrchat_output.h"
#include "outputs/vts_output.h"
#include "pipeline/options.h"

namespace th::outputs {

// Every output, in the order the help and the panel list them. A new output: its file, and its settings here.
using OutputKinds = std::tuple<VmcSettings, VrchatSettings, OscSettings, VtsSettings>;

struct OutputSettings {
  OutputKinds kinds;
  bool mirrorHead = false;  // VMC and VTube Studio: the avatar as the speaker's mirror image

  template <typename Kind>
  Kind& get() {
    return std::get<Kind>(kinds);
  }
  template <typename Kind>
  const Kind& get() const {
    return std::get<Kind>(kinds);
  }
  // Each output's options under its prefix, then those they share.
  void visitOptions(OptionVisitor& v);
  // The panel's rows, every output's.
  std::vector<OutputRow> rows();
  // The outputs switched on (a non-empty address), opened; throws th::Error for an address that cannot be.
  // `context.mirrorHead` is this struct's.
  std::vector<std::unique_ptr<LiveOutput>> open(OutputContext context) const;
};

// Everything `live` offers, as its settings file holds it (one flat object, each option under its key): the
// decoder's settings and the outputs'.
struct LiveSessionSettings : pipeline::LiveSettings {
  OutputSettings outputs;
  void visitOptions(OptionVisitor& v);
  // Each option in its range (the decoder's and the outputs'); throws th::Error naming the option.
  void check();
};

}  // namespace th::outputs
