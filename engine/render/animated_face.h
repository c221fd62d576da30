// The face as every program shows it: the face model, a renderer and a camera framing the head, posed by one
// FAP frame at a time. Export, the live window, `show`, film strips and the golden tests draw through it.
//
//   const th::face::FaceModel model = th::face::FaceModel::buildDefault();
//   th::render::OffscreenContext context;
//   th::render::AnimatedFace face(model, context, {.width = 640, .height = 480});
//   const th::render::Image& image = face.draw(faps);   // posed, rendered, read back; valid until the next draw
//
// pose() deforms the mesh only when the frame differs from the one shown (the live window redraws the same
// pose at 60 Hz). The renderer is told where the mouth and the eyes open, so it can skip what cannot show.
// Thread contract: belongs to its context's thread; the face model and the context must outlive it.
#pragma once

#include "face/face_model.h"
#include "face/fap.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "render/image.h"

namespace th::render {

class AnimatedFace {
 public:
  AnimatedFace(const face::FaceModel& model, GlContext& context, const RenderOptions& options = {});

  // The mesh deformed by `faps` and the pupils sized (FAPs 29, 30); nothing if the frame is the one shown.
  void pose(const face::FapFrame& faps);
  // The posed face into the renderer's own target, with the camera.
  void render() { renderer_.render(camera_); }
  // pose, render, read back (RGB, top row first).
  const Image& draw(const face::FapFrame& faps);

  // A new size for the renderer, and the camera framing the head again at its aspect.
  void resize(int width, int height);
  // The camera close on the lips (film strips): the face from the nose to the chin.
  void frameMouth();

  const face::FaceModel& model() const { return model_; }
  FaceRenderer& renderer() { return renderer_; }
  OrbitCamera& camera() { return camera_; }
  const OrbitCamera& camera() const { return camera_; }

 private:
  const face::FaceModel& model_;
  FaceRenderer renderer_;
  OrbitCamera camera_;
  face::FapFrame shown_;
  bool posed_ = false;
  Image image_;
};

}  // namespace th::render
