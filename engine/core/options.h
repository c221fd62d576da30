// Options declared once. An options struct lists each field it lets people set, with its name, range, unit and
// help, in one visitOptions(); the command line (app/cli_options.h), settings files (below), the live panel's
// widgets (app/live/panel.h) and presets are all made from that list, so they cannot disagree. In the spirit
// of Kaldi's Register()/Check().
//
//   struct Motion {
//     double headAmplitude = 1.0;      // the default is the initialiser, and only there
//     bool idle = true;
//     void visitOptions(th::OptionVisitor& v) {
//       v.option(headAmplitude, {.name = "head-amplitude", .help = "Head rotations times this", .min = 0, .max = 5});
//       v.option(idle, {.name = "idle", .help = "Blinks, gaze shifts, the head at rest in silence"});
//     }
//   };
//   th::checkOptions(motion);                            // throws "head-amplitude: 7 is outside 0..5"
//   th::setOption(motion, "head-amplitude", "1.5");     // by name, checked (presets)
//   th::Json saved = th::optionsToJson(motion);         // {"head_amplitude": 1.5, "idle": true}
//   th::optionsFromJson(saved, motion, "live.json");    // keys missing keep their values; bad ones name the file
//
// Names are kebab-case: `--head-amplitude` on the command line; `head_amplitude` in settings files. A bool that
// is on by default is switched off by `--no-NAME`, one that is off is switched on by `--NAME`. Choices are strings
// from a fixed list (`choices`). Numbers carry their unit in `unit` ("frames", "Hz", "dB"), which the help shows.
// Thread contract: plain values and functions.
#pragma once

#include <filesystem>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/json_reading.h"

namespace th {

struct OptionSpec {
  std::string_view name;  // kebab-case, unique within its struct
  std::string_view help;  // one line, for --help, the panel's tooltip and docs/cli.md
  std::string_view unit = {};
  double min = -std::numeric_limits<double>::infinity();  // numbers: the allowed range, inclusive
  double max = std::numeric_limits<double>::infinity();
  std::span<const std::string_view> choices = {};  // strings: the allowed values (empty: any text)
  bool logarithmic = false;             // the panel's slider: equal steps in ratio (wide ranges of positive values)
  bool panel = true;                    // offered in the live panel (file paths and the like are not)
  std::string_view implicitValue = {};  // strings: the value of the option given without one ("--vmc")
  // The name it had before its unit joined it ("window" for "window-frames"): still accepted on the command line,
  // by setOption and in settings files (read, never written), so that scripts and saved settings keep working.
  std::string_view formerName = {};
};

// What the adapters implement: called once per field, in declaration order, with a reference to the field.
class OptionVisitor {
 public:
  virtual ~OptionVisitor() = default;
  virtual void option(bool& value, const OptionSpec& spec) = 0;
  virtual void option(int& value, const OptionSpec& spec) = 0;
  virtual void option(unsigned& value, const OptionSpec& spec) = 0;
  virtual void option(double& value, const OptionSpec& spec) = 0;
  virtual void option(std::string& value, const OptionSpec& spec) = 0;
};

// "head-amplitude" → "head_amplitude".
std::string settingsKey(std::string_view name);
// The spec's range and choices as text: "0..5 frames", "one of full, diagonal", "" when open.
std::string describeRange(const OptionSpec& spec);

// Visitors behind the functions below (for structs, use the templates).
void checkOptionValues(const std::function<void(OptionVisitor&)>& visit);
bool setOptionByName(const std::function<void(OptionVisitor&)>& visit, std::string_view name, std::string_view text);
Json optionValuesToJson(const std::function<void(OptionVisitor&)>& visit);
void optionValuesFromJson(const std::function<void(OptionVisitor&)>& visit, const Json& document,
                          const std::filesystem::path& path);

// Every field within its range and choices; throws th::Error "NAME: VALUE is outside MIN..MAX" otherwise.
template <typename Options>
void checkOptions(Options& options) {
  checkOptionValues([&](OptionVisitor& v) { options.visitOptions(v); });
}

// Sets the field called `name` from text, checked; throws th::Error for a bad value or an unknown name.
template <typename Options>
void setOption(Options& options, std::string_view name, std::string_view text) {
  if (!setOptionByName([&](OptionVisitor& v) { options.visitOptions(v); }, name, text))
    throw Error("no option \"" + std::string(name) + "\"");
}

// A JSON object of every field, under its settings key.
template <typename Options>
Json optionsToJson(Options options) {
  return optionValuesToJson([&](OptionVisitor& v) { options.visitOptions(v); });
}

// The fields the object holds, each checked (type, range, choices); keys it does not know are ignored (a newer
// version's file). Errors name `path` and the key.
template <typename Options>
void optionsFromJson(const Json& document, Options& options, const std::filesystem::path& path) {
  optionValuesFromJson([&](OptionVisitor& v) { options.visitOptions(v); }, document, path);
}

}  // namespace th
