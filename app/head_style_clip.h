// --head-style in the app: the clip a person's head style comes from, a talking video among them (tracked here,
// which the engine's pipeline cannot do), and the one line that says what the style is.
//
//   resolveHeadStyleClip(arguments.head, arguments.idle, arguments.models, std::cerr);
//   pipeline::AnimateOptions options = pipeline::animateOptionsOf(arguments.models, arguments.head, arguments.idle);
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "animation/head_model.h"
#include "animation/head_style.h"
#include "pipeline/options.h"

namespace th::app {

// The style of a clip for `model`: a talking video is tracked (its sound: its own track, or the WAV of its name
// beside it) and the head model fitted to the person's motion; a style file or a head-pose CSV with its WAV is
// read as animation::headStyleFromFile reads it. Tracking reports its progress to `log`. Errors are one line naming
// the clip (no face found, too short, no speech, ...).
animation::HeadStyle headStyleOfClip(const std::filesystem::path& clip, const animation::HeadModel& model,
                                     std::ostream& log);

// head.style's style, for the head model `models` names, put in place (pipeline::useHeadStyle) and described on
// `log` in one line. Nothing when head.style is empty, the head is off, or the style is in place already.
void resolveHeadStyleClip(pipeline::HeadMotionOptions& head, pipeline::IdleOptions& idle,
                          const pipeline::ModelOptions& models, std::ostream& log);

// "scott.mp4, 47.6 s: spread 4.3 / 7.1 / 4.2 deg, ... ; the model styled: ..."
std::string describeHeadStyle(const animation::HeadStyle& style);

// Where `talkinghead style` keeps the styles it makes and the live panel offers them: $XDG_CONFIG_HOME/
// talkinghead/head-styles, else ~/.config/talkinghead/head-styles; empty if neither is known.
std::filesystem::path headStyleFolder();
// The style files in that folder, by name (none if it is missing).
std::vector<std::filesystem::path> listHeadStyles();

}  // namespace th::app
