// `talkinghead live`: speech in real time, the face out. With a window (window.h) or --headless (headless.h);
// this file parses the command line and chooses. Settings come, lowest first, from the window's settings file,
// the preset typed, then the options typed.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "audio/capture.h"
#include "character.h"
#include "cli_options.h"
#include "commands.h"
#include "core/error.h"
#include "head_style_clip.h"
#include "live/headless.h"
#include "live/settings_file.h"
#include "live/window.h"
#include "pipeline/options.h"

namespace th::app {
namespace {

struct LiveArguments {
  bool headless = false;
  bool listDevices = false;
  std::string settingsFile;  // the window's saved settings
  bool noSettings = false;
  HeadlessArguments run;  // --input, --speed, --duration, --repeat-to, --dump, --reconnect-seconds
  LiveWindowArguments window;
  outputs::LiveSessionSettings given;  // the options as typed (which ones were: CLI11's count)
};

void listDevices() {
  const audio::PortAudioSystem system;
  const std::vector<audio::AudioDevice> inputs = system.inputDevices();
  if (inputs.empty()) std::printf("no sound input devices\n");
  for (const audio::AudioDevice& d : inputs)
    std::printf("%3d  %s%s  (%s, %d channels, %.0f Hz)\n", d.index, d.name.c_str(),
                d.isDefaultInput ? "  [default]" : "", d.hostApi.c_str(), d.inputChannels, d.defaultRateHz);
}

std::filesystem::path settingsPathOf(const LiveArguments& arguments) {
  if (arguments.noSettings) return {};
  return arguments.settingsFile.empty() ? defaultLiveSettingsPath() : std::filesystem::path(arguments.settingsFile);
}

// The saved settings, then the preset typed, then every option typed.
outputs::LiveSessionSettings resolveSettings(LiveArguments& arguments, const CLI::App& command,
                                             outputs::LiveSessionSettings settings) {
  if (command.count("--preset") > 0) pipeline::applyLivePreset(settings, arguments.given.live.preset);
  copyTypedOptions(command, arguments.given, settings);
  try {
    settings.check();
  } catch (const Error& error) {
    throw Error(std::string("live: ") + error.what());
  }
  try {
    resolveHeadStyleClip(settings.head, settings.idle, settings.models, std::cerr);
  } catch (const Error& error) {
    // A style the saved settings name that is gone is left out; one typed now is an error.
    if (command.count("--head-style") > 0) throw;
    std::cerr << "talkinghead: live: the saved head style is left out: " << error.what() << '\n';
    pipeline::clearHeadStyle(settings.head, settings.idle);
  }
  return settings;
}

void runLive(LiveArguments& arguments, const CLI::App& command) {
  if (arguments.listDevices) {
    listDevices();
    return;
  }
  const bool typedDevice = command.count("--device") > 0;
  const std::string& input = arguments.run.input;
  if (!input.empty() && typedDevice)
    throw Error("live: give the sound either as --input FILE or as --device, not both");
  if (arguments.headless) {
    if (input.empty() && !typedDevice)
      throw Error("live --headless: give the sound either as --input FILE or as --device (default or a number)");
    if (!arguments.window.screenshot.empty()) throw Error("live: --screenshot is for the window, not --headless");
    if (!arguments.window.avatar.empty())
      throw Error(
          "live: --avatar is drawn in the window; --headless draws nothing (its outputs drive a character "
          "in the program that receives them)");
    // Headless reads nothing else of the window's settings, only VTube Studio's token (and keeps a new one).
    arguments.run.settingsPath = settingsPathOf(arguments);
    outputs::LiveSessionSettings base;
    if (!arguments.run.settingsPath.empty() && !arguments.given.outputs.get<outputs::VtsSettings>().address.empty())
      base.outputs.get<outputs::VtsSettings>().token =
          loadLiveSettings(arguments.run.settingsPath).outputs.get<outputs::VtsSettings>().token;
    runHeadless(arguments.run, resolveSettings(arguments, command, base));
    return;
  }
  if (!arguments.run.dump.empty()) throw Error("live: --dump is for --headless runs");
  if (arguments.run.speed != 1.0) throw Error("live: --speed is for --headless runs; the window plays in real time");
  arguments.window.input = input;
  arguments.window.duration = arguments.run.duration;
  arguments.window.settingsPath = settingsPathOf(arguments);
  runLiveWindow(arguments.window, resolveSettings(arguments, command, loadLiveSettings(arguments.window.settingsPath)));
}

}  // namespace

void addLiveCommand(CLI::App& app) {
  auto arguments = std::make_shared<LiveArguments>();
  CLI::App* live = app.add_subcommand(
      "live", "Speech in real time -> the face: a window with a panel, or --headless (frames reported or dumped)");
  live->add_flag("--headless", arguments->headless,
                 "Without a window: decode, and report or dump what a display would get");
  live->add_flag("--list-devices", arguments->listDevices, "List the sound inputs and exit");
  live->add_option("--input", arguments->run.input,
                   "Recording to play into the pipeline (WAV, FLAC, ... or a video's audio)");
  live->add_option("--speed", arguments->run.speed,
                   "--headless --input: times real time (0: as fast as the worker decodes)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  live->add_option("--duration", arguments->run.duration,
                   "Seconds to run: of the recording (0: all), or of listening (0: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e6));
  live->add_option("--repeat-to", arguments->run.repeatTo,
                   "--headless --input: play the recording over and over to this many seconds (a soak test)")
      ->check(CLI::Range(0.0, 1e6));
  live->add_option("--dump", arguments->run.dump,
                   "--headless: write the frames the display received: .csv, .json or .fap");
  live->add_option("--reconnect-seconds", arguments->run.reconnectSeconds,
                   "--headless --device: how long a lost sound input is waited for before the run fails")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  addOptions(*live, arguments->given);
  live->add_option("--settings", arguments->settingsFile,
                   "The window's settings file (default $XDG_CONFIG_HOME/talkinghead/live.json or ~/.config/...)");
  live->add_flag("--no-settings", arguments->noSettings, "Neither read nor save the window's settings");
  live->add_option("--screenshot", arguments->window.screenshot,
                   "Window: save it as PNG after --frames frames and quit");
  live->add_option("--frames", arguments->window.frames, "Window: frames before the screenshot")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  addAvatarOption(*live, arguments->window.avatar);
  live->add_option("--msaa", arguments->window.msaa,
                   "Window: MSAA samples (0: 4 on a GPU, 1 = none on a software renderer)")
      ->check(CLI::Range(0, 16))
      ->capture_default_str();
  live->add_option("--max-fps", arguments->window.maxFps,
                   "Window: the most frames a second where the display does not pace them (Xvfb); 0: as many as it can")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  live->callback([arguments, live] { runLive(*arguments, *live); });
}

}  // namespace th::app
