// Every option `live` offers has twins: a command-line option, a key in the window's settings file, and (unless
// it is a file path or the seed) a widget in the panel. They are made from one declaration each
// (pipeline/options.h, and each output's own: outputs/output_settings.h), and this checks that they agree: the same
// name, the same range or choices, the same default; and that the presets set only options that exist, to values in
// range.
#include <gtest/gtest.h>
#include <imgui.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_options.h"
#include "core/error.h"
#include "core/options.h"
#include "live/panel.h"
#include "live/settings_file.h"
#include "outputs/output_settings.h"
#include "pipeline/live_presets.h"
#include "pipeline/options.h"

namespace {

using th::OptionSpec;
using LiveSettings = th::outputs::LiveSessionSettings;  // everything `live` offers

struct Declared {
  OptionSpec spec;
  std::string kind;  // bool, int, unsigned, double, string
  bool onByDefault = false;
};

// Every option of a struct, in declaration order.
class Lister final : public th::OptionVisitor {
 public:
  std::vector<Declared> options;
  void option(bool& value, const OptionSpec& spec) override { options.push_back({spec, "bool", value}); }
  void option(int&, const OptionSpec& spec) override { options.push_back({spec, "int"}); }
  void option(unsigned&, const OptionSpec& spec) override { options.push_back({spec, "unsigned"}); }
  void option(double&, const OptionSpec& spec) override { options.push_back({spec, "double"}); }
  void option(std::string&, const OptionSpec& spec) override { options.push_back({spec, "string"}); }
};

std::vector<Declared> liveOptions() {
  LiveSettings settings;
  Lister lister;
  settings.visitOptions(lister);
  return lister.options;
}

// Parses a `live`-like command that has every option; true if CLI11 accepts the arguments.
bool parses(const std::vector<std::string>& arguments) {
  LiveSettings given;
  CLI::App app;
  th::app::addOptions(app, given);
  std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
  try {
    app.parse(reversed);
    return true;
  } catch (const CLI::ParseError&) {
    return false;
  }
}

// A value as typed: whole numbers for the whole-number options.
std::string text(double value, const std::string& kind) {
  if (kind != "double") return std::to_string(static_cast<long long>(value));
  std::ostringstream out;
  out << value;
  return out.str();
}

// A value as a settings file holds it: integers for the whole-number options.
th::Json jsonValue(double value, const std::string& kind) {
  if (kind != "double") return th::Json(static_cast<long long>(value));
  return th::Json(value);
}

TEST(OptionTwins, EveryOptionHasItsCommandLineTwinWithItsRangeAndChoices) {
  for (const Declared& option : liveOptions()) {
    const std::string name(option.spec.name);
    SCOPED_TRACE(name);
    if (option.kind == "bool") {
      EXPECT_TRUE(parses({th::app::flagOf(option.spec, option.onByDefault)}));
      continue;
    }
    const std::string flag = "--" + name;
    if (!option.spec.choices.empty()) {
      for (std::string_view choice : option.spec.choices) EXPECT_TRUE(parses({flag, std::string(choice)})) << choice;
      EXPECT_FALSE(parses({flag, "no-such-choice"}));
      continue;
    }
    if (std::isfinite(option.spec.min)) {
      EXPECT_TRUE(parses({flag, text(option.spec.min, option.kind)}));
      EXPECT_FALSE(parses({flag, text(option.spec.min - 1.0, option.kind)})) << "below the range";
    }
    if (std::isfinite(option.spec.max)) {
      EXPECT_TRUE(parses({flag, text(option.spec.max, option.kind)}));
      EXPECT_FALSE(parses({flag, text(option.spec.max + 1.0, option.kind)})) << "above the range";
    }
  }
}

TEST(OptionTwins, EveryOptionHasItsSettingsKeyWithTheSameRange) {
  // The defaults written and read back are the defaults.
  const th::Json defaults = th::optionsToJson(LiveSettings{});
  LiveSettings back;
  th::optionsFromJson(defaults, back, "live.json");
  EXPECT_EQ(th::optionsToJson(back), defaults);
  for (const Declared& option : liveOptions()) {
    const std::string key = th::settingsKey(option.spec.name);
    SCOPED_TRACE(key);
    ASSERT_TRUE(defaults.contains(key));
    LiveSettings settings;
    if (!option.spec.choices.empty()) {
      for (std::string_view choice : option.spec.choices)
        EXPECT_NO_THROW(th::optionsFromJson(th::Json{{key, std::string(choice)}}, settings, "live.json")) << choice;
      EXPECT_THROW(th::optionsFromJson(th::Json{{key, "no-such-choice"}}, settings, "live.json"), th::Error);
      continue;
    }
    if (option.kind == "bool" || option.kind == "string") continue;
    if (std::isfinite(option.spec.min)) {
      EXPECT_NO_THROW(
          th::optionsFromJson(th::Json{{key, jsonValue(option.spec.min, option.kind)}}, settings, "live.json"));
      try {
        th::optionsFromJson(th::Json{{key, jsonValue(option.spec.min - 1.0, option.kind)}}, settings, "live.json");
        ADD_FAILURE() << "below the range was taken";
      } catch (const th::Error& error) {
        EXPECT_NE(std::string(error.what()).find("live.json"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
      }
    }
    if (std::isfinite(option.spec.max)) {
      EXPECT_NO_THROW(
          th::optionsFromJson(th::Json{{key, jsonValue(option.spec.max, option.kind)}}, settings, "live.json"));
      EXPECT_THROW(
          th::optionsFromJson(th::Json{{key, jsonValue(option.spec.max + 1.0, option.kind)}}, settings, "live.json"),
          th::Error);
    }
  }
}

TEST(OptionTwins, EveryPanelWidgetHasTheOptionsRangeOrChoices) {
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(1280, 720);
  io.IniFilename = nullptr;
  unsigned char* pixels = nullptr;
  int width = 0, height = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &width, &height);  // the font atlas, which a frame needs
  LiveSettings settings;
  std::vector<th::app::WidgetRecord> widgets;
  ImGui::NewFrame();
  ImGui::Begin("settings");
  th::app::settingsWidgets(settings, &widgets);
  ImGui::End();
  ImGui::Render();
  ImGui::DestroyContext();

  std::map<std::string, th::app::WidgetRecord> byName;
  for (const th::app::WidgetRecord& widget : widgets)
    EXPECT_TRUE(byName.emplace(widget.name, widget).second) << widget.name;
  std::size_t offered = 0;
  for (const Declared& option : liveOptions()) {
    const std::string name(option.spec.name);
    SCOPED_TRACE(name);
    const auto found = byName.find(name);
    const bool wanted = option.spec.panel && (option.kind != "string" || !option.spec.choices.empty());
    if (!wanted) {
      EXPECT_EQ(found, byName.end()) << "a widget for an option not offered in the panel";
      continue;
    }
    ++offered;
    ASSERT_NE(found, byName.end()) << "no widget";
    const th::app::WidgetRecord& widget = found->second;
    if (option.kind == "bool") {
      EXPECT_EQ(widget.kind, "checkbox");
    } else if (option.kind == "string") {
      EXPECT_EQ(widget.kind, "combo");
      EXPECT_EQ(widget.choices, std::vector<std::string>(option.spec.choices.begin(), option.spec.choices.end()));
    } else {
      EXPECT_EQ(widget.kind, "slider");
      EXPECT_EQ(widget.min, option.spec.min);
      EXPECT_EQ(widget.max, option.spec.max);
    }
  }
  EXPECT_EQ(widgets.size(), offered) << "every widget is an option's";
}

TEST(OptionTwins, TypedOptionsOverrideTheSavedOnesAndNothingElse) {
  LiveSettings saved;
  saved.streaming.lag = 12;
  saved.idle.blinksPerMinute = 30.0;
  saved.models.head = "paper";
  LiveSettings given;
  CLI::App app;
  th::app::addOptions(app, given);
  app.parse(std::vector<std::string>{"2", "--window", "--no-idle", "9", "--lag"});  // CLI11 takes them reversed
  th::app::copyTypedOptions(app, given, saved);
  EXPECT_EQ(saved.streaming.lag, 9);
  EXPECT_EQ(saved.streaming.window, 2);
  EXPECT_FALSE(saved.idle.idle);
  EXPECT_EQ(saved.idle.blinksPerMinute, 30.0) << "not typed: kept";
  EXPECT_EQ(saved.models.head, "paper") << "not typed: kept";
}

TEST(OptionTwins, PresetsSetOptionsThatExistToValuesInRange) {
  for (const th::pipeline::LivePreset& preset : th::pipeline::kLivePresets) {
    SCOPED_TRACE(std::string(preset.name));
    LiveSettings settings;
    EXPECT_NO_THROW(th::pipeline::applyLivePreset(settings, preset.name));
    EXPECT_EQ(settings.live.preset, preset.name);
    EXPECT_NO_THROW(settings.check());
  }
  LiveSettings settings;
  EXPECT_THROW(th::pipeline::applyLivePreset(settings, "no-such-preset"), th::Error);
  EXPECT_THROW(th::setOption(settings, "no-such-option", "1"), th::Error);
  EXPECT_THROW(th::setOption(settings, "window-frames", "0"), th::Error);
  EXPECT_THROW(th::setOption(settings, "window-frames", "two"), th::Error);
}

// An option renamed to carry its unit answers to its former name everywhere it is read: the command line, setOption
// (presets) and a settings file written before; files are written under the new name only.
TEST(OptionTwins, AFormerNameSetsTheSameOptionAndFilesAreWrittenUnderTheNewOne) {
  LiveSettings former;
  CLI::App formerApp;
  th::app::addOptions(formerApp, former);
  formerApp.parse(std::vector<std::string>{"0.2", "--vmc-neck-length", "90", "--min-f0", "3", "--window"});
  LiveSettings current;
  CLI::App currentApp;
  th::app::addOptions(currentApp, current);
  currentApp.parse(std::vector<std::string>{"0.2", "--vmc-neck-length-m", "90", "--min-f0-hz", "3", "--window-frames"});
  EXPECT_EQ(former.streaming.window, 3);
  EXPECT_EQ(former.live.minF0, 90.0);
  EXPECT_EQ(former.outputs.get<th::outputs::VmcSettings>().neckLength, 0.2);
  EXPECT_EQ(th::optionsToJson(former), th::optionsToJson(current));

  LiveSettings set;
  th::setOption(set, "lag", "7");
  EXPECT_EQ(set.streaming.lag, 7);
  EXPECT_THROW(th::setOption(set, "lag", "-1"), th::Error) << "the former name is checked like the new one";

  const th::Json written = th::optionsToJson(set);
  EXPECT_TRUE(written.contains("lag_frames"));
  EXPECT_FALSE(written.contains("lag"));

  const std::filesystem::path path = std::filesystem::temp_directory_path() / "option_twins_former.json";
  std::ofstream(path) << R"({"window": 4, "max_f0": 400, "min_f0_hz": 70, "min_f0": 80})";
  const LiveSettings read = th::app::loadLiveSettings(path);
  std::filesystem::remove(path);
  EXPECT_EQ(read.streaming.window, 4);
  EXPECT_EQ(read.live.maxF0, 400.0);
  EXPECT_EQ(read.live.minF0, 70.0) << "the new name wins over the former";
}

TEST(OptionTwins, ASettingsFileWithABadValueNamesTheFileAndTheKey) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "option_twins_settings.json";
  std::ofstream(path) << R"({"head_variation": 9})";
  try {
    static_cast<void>(th::app::loadLiveSettings(path));
    ADD_FAILURE() << "a bad value was taken";
  } catch (const th::Error& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("head_variation"), std::string::npos) << error.what();
  }
  std::ofstream(path) << R"({"min_f0": 300, "max_f0": 200})";
  EXPECT_THROW(th::app::loadLiveSettings(path), th::Error) << "min-f0-hz must be below max-f0-hz";
  std::filesystem::remove(path);
}

}  // namespace
