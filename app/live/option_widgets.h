// The live panel's widgets made from the option registry (core/options.h): a checkbox for a bool, a slider
// over the option's own range for a number (logarithmic where the spec says so), a combo for a choice. The
// command line and the settings file are made from the same specs, so the three cannot disagree
// (tests/app/option_twins_test.cpp checks it).
//
//   if (th::app::optionWidgets(settings.streaming)) decoderChanged();    // inside an ImGui window
//
// Options with spec.panel = false (file paths, the seed) get no widget.
// Thread contract: the ImGui thread.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/options.h"

namespace th::app {

// What a widget was drawn for: its option, kind and range (for the tests that compare the twins).
struct WidgetRecord {
  std::string name;
  std::string kind;  // "checkbox", "slider", "combo"
  double min = 0.0;
  double max = 0.0;
  std::vector<std::string> choices;
};

// Draws the widgets; true if any value changed. `record`, if given, receives a line per widget drawn.
bool optionWidgetsFrom(const std::function<void(OptionVisitor&)>& visit, std::vector<WidgetRecord>* record = nullptr);

template <typename Options>
bool optionWidgets(Options& options, std::vector<WidgetRecord>* record = nullptr) {
  return optionWidgetsFrom([&](OptionVisitor& v) { options.visitOptions(v); }, record);
}

}  // namespace th::app
