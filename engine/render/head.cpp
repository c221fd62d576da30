#include "render/head.h"

#include "render/animated_avatar.h"
#include "render/animated_face.h"

namespace th::render {

const Image& Head::draw(const face::FapFrame& faps, const float* visemeProbabilities) {
  pose(faps, visemeProbabilities);
  render();
  readPixels(image_);
  return image_;
}

const Image& Head::draw(const face::FapTrack& animation, double seconds) {
  poseAt(animation, seconds);
  render();
  readPixels(image_);
  return image_;
}

void Head::drawIntoWindow(WindowContext& window, int left) {
  if (samples() <= 1) {
    renderToWindow(left);
    return;
  }
  render();
  window.makeCurrent();
  present(window.framebufferSize(), left);
}

std::unique_ptr<Head> makeHead(const avatar::Avatar* character, GlContext& context, const HeadOptions& options,
                               const face::FaceModel* face) {
  if (character != nullptr)
    return std::make_unique<AnimatedAvatar>(
        *character, context,
        AvatarRenderOptions{
            .width = options.width, .height = options.height, .samples = options.samples, .fxaa = options.fxaa});
  const RenderOptions faceOptions{
      .width = options.width, .height = options.height, .samples = options.samples, .fxaa = options.fxaa};
  if (face != nullptr) return std::make_unique<AnimatedFace>(*face, context, faceOptions);
  return std::make_unique<AnimatedFace>(std::make_shared<const face::FaceModel>(face::FaceModel::buildDefault()),
                                        context, faceOptions);
}

}  // namespace th::render
