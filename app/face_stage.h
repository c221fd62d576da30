// What the off-screen commands share (render, poses, strip, sidebyside): a head (our default face, or the user's
// character) drawn into an off-screen context, a --size parser, and progress counted in video frames.
//
//   th::app::OffscreenHead stage(character ? &*character : nullptr, {.width = 640, .height = 480});
//   const th::render::Image& frame = stage.head->draw(animation, seconds);   // RGB, top row first
//
// Thread contract: an OffscreenHead belongs to the thread that made it (its OSMesa context).
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "avatar/avatar_model.h"
#include "core/progress.h"
#include "render/gl_context.h"
#include "render/head.h"

namespace th::app {

// "1280x720" → {1280, 720}; both even (H.264 in yuv420p) and within what a renderer can allocate.
std::pair<int, int> parseSize(const std::string& text);

ProgressOptions progressAt(double framesPerSecond);  // the bar shows the real-time factor

// An off-screen context and a head drawn in it: the character (which must outlive this) where there is one,
// else our default face.
struct OffscreenHead {
  render::OffscreenContext context;
  std::unique_ptr<render::Head> head;

  OffscreenHead(const avatar::Avatar* character, const render::HeadOptions& options)
      : head(render::makeHead(character, context, options)) {}
};

}  // namespace th::app
