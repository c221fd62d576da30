// Our face as a Head (render/head.h): the face model, a renderer and a camera framing the head, posed by one FAP
// frame at a time.
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

#include <memory>

#include "face/face_model.h"
#include "face/fap.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "render/head.h"
#include "render/image.h"

namespace th::render {

class AnimatedFace final : public Head {
 public:
  AnimatedFace(const face::FaceModel& model, GlContext& context, const RenderOptions& options = {});
  // The same, holding the model.
  AnimatedFace(std::shared_ptr<const face::FaceModel> model, GlContext& context, const RenderOptions& options = {});

  // The mesh deformed by `faps` and the pupils sized (FAPs 29, 30); nothing if the frame is the one shown.
  void pose(const face::FapFrame& faps);
  // Our face has no viseme targets: the FAPs alone pose it.
  void pose(const face::FapFrame& faps, const float* /*visemeProbabilities*/) override { pose(faps); }
  void pose(const face::FapFrame& faps, const avatar::AvatarInput& /*weights*/) override { pose(faps); }
  void poseAt(const face::FapTrack& animation, double seconds) override { pose(animation.at(seconds)); }
  void render() override { renderer_.render(camera_); }
  void readRaw(RawFrame& frame) override { renderer_.readRaw(frame); }
  void finish(RawFrame& frame, Yuv420Image& image, bool bt709) const override { renderer_.finish(frame, image, bt709); }
  void readPixels(Image& image) override { renderer_.readPixels(image); }
  void present(std::pair<int, int> framebufferSize, int left) override { renderer_.present(framebufferSize, left); }
  void renderToWindow(int left) override { renderer_.renderToWindow(camera_, left); }
  void resize(int width, int height) override;
  // The face from the nose to the chin.
  void frameMouth() override;
  OrbitCamera& camera() override { return camera_; }
  const OrbitCamera& camera() const { return camera_; }
  int samples() const override { return renderer_.samples(); }
  std::string description() const override { return {}; }

  const face::FaceModel& model() const { return model_; }
  FaceRenderer& renderer() { return renderer_; }

 private:
  std::shared_ptr<const face::FaceModel> owned_;  // when the face holds its model
  const face::FaceModel& model_;
  FaceRenderer renderer_;
  OrbitCamera camera_;
  face::FapFrame shown_;
  bool posed_ = false;
};

}  // namespace th::render
