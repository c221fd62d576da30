// What the off-screen commands share (render, poses, strip, export, sidebyside) besides render::OffscreenHead
// (render/head.h): a --size parser, and progress counted in video frames.
#pragma once

#include <string>
#include <utility>

#include "core/progress.h"

namespace th::app {

// "1280x720" → {1280, 720}; both even (H.264 in yuv420p) and within what a renderer can allocate.
std::pair<int, int> parseSize(const std::string& text);

ProgressOptions progressAt(double framesPerSecond);  // the bar shows the real-time factor

}  // namespace th::app
