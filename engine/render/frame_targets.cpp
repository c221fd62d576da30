#include "render/frame_targets.h"

#include <algorithm>

#include "core/error.h"

namespace th::render {

int FrameTargets::create(int width, int height, int samples, const std::string& who) {
  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  samples = std::clamp(samples, 1, std::max(1, maxSamples));
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  glGenFramebuffers(1, &resolveFramebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, resolveFramebuffer);
  glGenRenderbuffers(1, &resolveColour);
  glBindRenderbuffer(GL_RENDERBUFFER, resolveColour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveColour);
  if (samples == 1) {
    glGenRenderbuffers(1, &resolveDepth);
    glBindRenderbuffer(GL_RENDERBUFFER, resolveDepth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, resolveDepth);
  }
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error(who + ": the " + size + " framebuffer is incomplete");
  if (samples > 1) {
    glGenFramebuffers(1, &msaaFramebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, msaaFramebuffer);
    glGenRenderbuffers(1, &msaaColour);
    glBindRenderbuffer(GL_RENDERBUFFER, msaaColour);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaaColour);
    glGenRenderbuffers(1, &msaaDepth);
    glBindRenderbuffer(GL_RENDERBUFFER, msaaDepth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaaDepth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw Error(who + ": the " + size + " framebuffer with " + std::to_string(samples) + " samples is incomplete");
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return samples;
}

void FrameTargets::release() {
  glDeleteFramebuffers(1, &msaaFramebuffer);
  glDeleteRenderbuffers(1, &msaaColour);
  glDeleteRenderbuffers(1, &msaaDepth);
  glDeleteFramebuffers(1, &resolveFramebuffer);
  glDeleteRenderbuffers(1, &resolveColour);
  glDeleteRenderbuffers(1, &resolveDepth);
  msaaFramebuffer = msaaColour = msaaDepth = resolveFramebuffer = resolveColour = resolveDepth = 0;
}

void FrameTargets::resolve(int width, int height) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, msaaFramebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveFramebuffer);
  glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void FrameTargets::read(int width, int height, const PixelRegion& region, RawFrame& frame) const {
  frame.width = width;
  frame.height = height;
  frame.region = region;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolveFramebuffer);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  frame.rgba.resize(static_cast<std::size_t>(region.width) * static_cast<std::size_t>(region.height) * 4);
  // RGBA is the renderbuffer's own layout (a plain copy in Mesa); dropping alpha later is cheaper than GL's.
  if (!frame.rgba.empty())
    glReadPixels(region.left, height - region.top - region.height, region.width, region.height, GL_RGBA,
                 GL_UNSIGNED_BYTE, frame.rgba.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace th::render
