// The framebuffers a renderer draws into: a multisampled one (colour and depth) resolved into a single-sample
// one, or with one sample only the latter (with its own depth). The face's and the characters' renderers share
// them. Internal to the renderer.
// Thread contract: needs the calling thread's current GL 3.3 context.
#pragma once

#include <glad/gl.h>

#include <string>

#include "render/raw_frame.h"

namespace th::render {

struct FrameTargets {
  GLuint msaaFramebuffer = 0;
  GLuint msaaColour = 0;
  GLuint msaaDepth = 0;
  GLuint resolveFramebuffer = 0;
  GLuint resolveColour = 0;
  GLuint resolveDepth = 0;  // only with one sample, when drawing straight into the resolve target

  // Makes them at the size with up to `samples` (clamped to what the driver offers) and returns the count in
  // use; throws th::Error("WHO: the WxH framebuffer ... is incomplete").
  int create(int width, int height, int samples, const std::string& who);
  void release();
  // The multisampled target copied into the resolve target.
  void resolve(int width, int height) const;
  // The resolve target's pixels in `region` (of a width x height frame) read back into `frame` (RGBA).
  void read(int width, int height, const PixelRegion& region, RawFrame& frame) const;
};

}  // namespace th::render
