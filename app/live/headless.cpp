#include "live/headless.h"

#include <cstdio>
#include <iostream>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/animation_format.h"
#include "interrupt.h"
#include "live/settings_file.h"
#include "pipeline/options.h"

namespace th::app {

void runHeadless(const HeadlessArguments& arguments, const outputs::LiveSessionSettings& settings) {
  if (arguments.input.empty() && arguments.speed != 1.0)
    throw Error("live: --speed is for --input files; a device runs in real time");
  if (!arguments.dump.empty()) {
    formats::animationFormatFor(arguments.dump);
    checkOutputTarget(arguments.dump);
  }
  auto models = std::make_shared<const pipeline::AnimationModels>(pipeline::loadModels(settings));
  InterruptGuard interrupts;
  const auto keepToken = [&arguments](const std::string& token) {
    if (arguments.settingsPath.empty()) return;
    outputs::LiveSessionSettings kept = loadLiveSettings(arguments.settingsPath);
    kept.outputs.get<outputs::VtsSettings>().token = token;
    saveLiveSettings(arguments.settingsPath, kept);
    std::printf("  VTube Studio's token kept in %s\n", arguments.settingsPath.string().c_str());
  };
  outputs::runHeadless(arguments, settings, std::move(models),
                       {.stopRequested = [] { return InterruptGuard::requested(); }, .keepToken = keepToken}, std::cout,
                       std::cerr);
}

}  // namespace th::app
