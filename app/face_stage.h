// What the off-screen commands share (render, poses, export, sidebyside): the face with a renderer and a
// camera framing it, a --size parser, and progress counted in video frames.
//
//   th::app::FaceStage stage({.width = 640, .height = 480});
//   const th::render::Image& image = stage.draw(faps);    // RGB, top row first; valid until the next draw
//
// Thread contract: a stage belongs to the thread that made it (its OSMesa context).
#pragma once

#include <string>
#include <utility>

#include "core/progress.h"
#include "face/face_model.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "render/image.h"

namespace th::app {

// "1280x720" → {1280, 720}; both even (H.264 in yuv420p) and within what a renderer can allocate.
std::pair<int, int> parseSize(const std::string& text);

ProgressOptions progressAt(double framesPerSecond);  // the bar shows the real-time factor

// The face, an off-screen renderer and a camera framing it.
struct FaceStage {
  face::FaceModel face;
  render::OffscreenContext context;
  render::FaceRenderer renderer;
  render::OrbitCamera camera;
  render::Image image;

  explicit FaceStage(render::RenderOptions options);
  const render::Image& draw(const face::FapFrame& faps);
  void frameMouth();  // the camera close on the lips (film strips): the face from the nose to the chin
};

}  // namespace th::app
