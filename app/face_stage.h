// What the off-screen commands share (render, poses, strip, export, sidebyside): the default face drawn into an
// off-screen context, a --size parser, and progress counted in video frames.
//
//   th::app::OffscreenFace face({.width = 640, .height = 480});
//   const th::render::Image& image = face.animated.draw(faps);   // RGB, top row first; valid until the next draw
//
// Thread contract: an OffscreenFace belongs to the thread that made it (its OSMesa context).
#pragma once

#include <string>
#include <utility>

#include "core/progress.h"
#include "face/face_model.h"
#include "render/animated_face.h"
#include "render/gl_context.h"

namespace th::app {

// "1280x720" → {1280, 720}; both even (H.264 in yuv420p) and within what a renderer can allocate.
std::pair<int, int> parseSize(const std::string& text);

ProgressOptions progressAt(double framesPerSecond);  // the bar shows the real-time factor

// The default face, an off-screen context and the face drawn in it.
struct OffscreenFace {
  face::FaceModel model = face::FaceModel::buildDefault();
  render::OffscreenContext context;
  render::AnimatedFace animated;

  explicit OffscreenFace(const render::RenderOptions& options) : animated(model, context, options) {}
};

}  // namespace th::app
