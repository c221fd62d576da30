// The live window's settings file: every option `live` offers (pipeline/options.h's LiveSettings), saved when
// the window closes and restored when it opens; the command line's options win over the saved ones.
//
//   th::outputs::LiveSessionSettings settings = th::app::loadLiveSettings(path);   // the defaults if there is no file
//   th::app::saveLiveSettings(path, settings);
//
// The file is one JSON object, each option under its settings key (core/options.h: "head_amplitude").
// Thread contract: plain functions; one thread.
#pragma once

#include <filesystem>

#include "outputs/output_settings.h"

namespace th::app {

// The program's settings folder: $XDG_CONFIG_HOME/talkinghead, else ~/.config/talkinghead; empty if neither is
// known.
std::filesystem::path configFolder();
// live.json in it.
std::filesystem::path defaultLiveSettingsPath();
// A missing file (or an empty path) gives the defaults; a file that is not valid JSON or holds a bad value
// throws th::Error naming it and the key. Unknown keys are ignored (a newer version's file).
outputs::LiveSessionSettings loadLiveSettings(const std::filesystem::path& path);
void saveLiveSettings(const std::filesystem::path& path,
                      outputs::LiveSessionSettings settings);  // atomic; empty: nothing

}  // namespace th::app
