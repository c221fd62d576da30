// The head style a --head-style option names, read or fitted for the head model that will use it.
//
//   th::pipeline::resolveHeadStyle(settings.head, settings.idle, *models.head);   // head.style: a file
//   th::pipeline::AnimateOptions options = th::pipeline::animateOptionsOf(models, settings.head, settings.idle);
//
// Thread contract: reads files; no shared state.
#pragma once

#include "animation/head_model.h"
#include "pipeline/options.h"

namespace th::pipeline {

// The style head.style names, for `model`, put in place with useHeadStyle: a style file, or a head-pose CSV with
// its WAV (animation::headStyleFromFile). Nothing when head.style is empty or its style is in place already. A
// talking video is the app's to track first (its --head-style does). Throws th::Error naming the file.
void resolveHeadStyle(HeadMotionOptions& head, IdleOptions& idle, const animation::HeadModel& model);

}  // namespace th::pipeline
