// A head to draw: our face (render/animated_face.h) or a user's character (render/animated_avatar.h), posed by
// one animation frame at a time. Export, `render`, `strip`, `sidebyside`, `show` and the live window each hold
// one Head and never ask which it is.
//
//   th::render::OffscreenContext context;
//   std::unique_ptr<th::render::Head> head = th::render::makeHead(character, context, {.width = 640, .height = 480});
//   const th::render::Image& image = head->draw(frame.faps, frame.visemes);   // RGB, top row first
//
// A new kind of head is a class implementing this and a line in makeHead().
// Thread contract: belongs to its context's thread.
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "avatar/avatar_input.h"
#include "avatar/avatar_model.h"
#include "face/face_model.h"
#include "face/fap.h"
#include "face/fap_track.h"
#include "render/camera.h"
#include "render/gl_context.h"
#include "render/image.h"
#include "render/raw_frame.h"
#include "render/yuv.h"

namespace th::render {

class Head {
 public:
  virtual ~Head() = default;

  // Posed by one frame: its FAPs (the head's rotation among them) and, where the decoder gives them, the
  // Oculus visemes' probabilities (nullptr: none), which a character with viseme targets speaks with.
  virtual void pose(const face::FapFrame& faps, const float* visemeProbabilities) = 0;
  // The same with a character's weights already made of that frame (avatar::avatarInputOf, as the live display
  // makes them once a frame for the outputs too).
  virtual void pose(const face::FapFrame& faps, const avatar::AvatarInput& weights) = 0;
  // Posed by an animation at a time: its FAPs there, and its visemes where it has them.
  virtual void poseAt(const face::FapTrack& animation, double seconds) = 0;

  // The posed head into its own target, which readRaw(), readPixels() and present() take it from.
  virtual void render() = 0;
  virtual void readRaw(RawFrame& frame) = 0;
  // readRaw's frame finished (the backdrop under the head, FXAA if on) on any thread, while this one renders
  // the next frame.
  virtual void finish(RawFrame& frame, Yuv420Image& image, bool bt709) const = 0;
  virtual void readPixels(Image& image) = 0;
  // The last render() resolved and copied into the window's back buffer (framebuffer 0), scaled to its size,
  // from column `left` on.
  virtual void present(std::pair<int, int> framebufferSize, int left) = 0;
  // The posed head straight into the window's framebuffer 0 from column `left`, at one sample, without a
  // target of its own (on llvmpipe the cheapest way to a window).
  virtual void renderToWindow(int left) = 0;

  // A new size, the camera framing the head again at its aspect.
  virtual void resize(int width, int height) = 0;
  // The camera close on the lips (film strips).
  virtual void frameMouth() = 0;
  virtual OrbitCamera& camera() = 0;
  virtual int samples() const = 0;  // MSAA samples in use
  // What a panel says of it: empty for our face; a character's name and how its face is rigged.
  virtual std::string description() const = 0;

  // pose, render, read back; valid until the next draw.
  const Image& draw(const face::FapFrame& faps, const float* visemeProbabilities = nullptr);
  const Image& draw(const face::FapTrack& animation, double seconds);
  // The posed head into the window `window` (current afterwards), from column `left`: straight in at one
  // sample, else rendered and presented.
  void drawIntoWindow(WindowContext& window, int left = 0);

 private:
  Image image_;
};

// The sizes and smoothing both kinds of head take.
struct HeadOptions {
  int width = 640;
  int height = 480;
  int samples = 4;    // MSAA; 1 disables it
  bool fxaa = false;  // with samples = 1, smooth the edges on the CPU as a frame is read back
};

// The character where there is one (`character`; it must outlive the head), else our face: `face`, or the
// default face (face::FaceModel::buildDefault) held by the head when `face` is null.
std::unique_ptr<Head> makeHead(const avatar::Avatar* character, GlContext& context, const HeadOptions& options,
                               const face::FaceModel* face = nullptr);

// An off-screen context and a head drawn in it, what the commands that draw into files share (render, poses,
// strip, sidebyside): the character (which must outlive this) where there is one, else our default face. It
// belongs to the thread that made it (its OSMesa context).
//
//   th::render::OffscreenHead stage(character, {.width = 640, .height = 480});
//   const th::render::Image& frame = stage.head->draw(animation, seconds);   // RGB, top row first
struct OffscreenHead {
  OffscreenContext context;
  std::unique_ptr<Head> head;

  OffscreenHead(const avatar::Avatar* character, const HeadOptions& options)
      : head(makeHead(character, context, options)) {}
};

}  // namespace th::render
