// What the off-screen commands share (render, poses, strip, export, sidebyside): the default face drawn into an
// off-screen context (or the user's character instead), a --size parser, and progress counted in video frames.
//
//   th::app::OffscreenFace face({.width = 640, .height = 480});
//   const th::render::Image& image = face.animated.draw(faps);   // RGB, top row first; valid until the next draw
//   th::app::OffscreenDrawing drawing(character ? &*character : nullptr, 640, 480);   // either one
//   const th::render::Image& frame = drawing.draw(animation, seconds);
//
// Thread contract: an OffscreenFace belongs to the thread that made it (its OSMesa context).
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "avatar/avatar_model.h"
#include "core/progress.h"
#include "face/face_model.h"
#include "render/animated_face.h"
#include "render/avatar_renderer.h"
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

// Our face, or a character (avatar/avatar_model.h; it must outlive this) posed by the same animation: its
// FAPs, and its visemes where it has them.
class OffscreenDrawing {
 public:
  OffscreenDrawing(const avatar::Avatar* character, int width, int height);
  const render::Image& draw(const face::FapTrack& animation, double seconds);
  // The camera close on the lips: our face from the nose to the chin, a character's mouth and chin.
  void frameMouth();

 private:
  std::unique_ptr<OffscreenFace> face_;
  std::unique_ptr<render::OffscreenContext> context_;
  std::unique_ptr<render::AnimatedAvatar> character_;
};

}  // namespace th::app
