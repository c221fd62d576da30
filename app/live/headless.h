// `talkinghead live --headless`: the live pipeline without a window (outputs/headless_run.h), with Ctrl-C ending
// the input and a token VTube Studio issued kept in the settings file.
// Thread contract: call from the main thread.
#pragma once

#include <filesystem>

#include "outputs/headless_run.h"
#include "outputs/output_settings.h"

namespace th::app {

struct HeadlessArguments : outputs::HeadlessRun {
  std::filesystem::path settingsPath;  // where VTube Studio's token is kept (empty: not kept)
};

void runHeadless(const HeadlessArguments& arguments, const outputs::LiveSessionSettings& settings);

}  // namespace th::app
