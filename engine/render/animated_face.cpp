#include "render/animated_face.h"

#include <utility>
#include <vector>

namespace th::render {

AnimatedFace::AnimatedFace(const face::FaceModel& model, GlContext& context, const RenderOptions& options)
    : model_(model),
      renderer_(context, model.mesh(), options),
      camera_(frameHead(model.mesh().positions, static_cast<double>(options.width) / options.height)),
      shown_{} {
  renderer_.setMouthOpening(model.innerLipVertices());
  renderer_.setEyeOpenings(model.eyeLidVertices(0), model.eyeLidVertices(1));
}

AnimatedFace::AnimatedFace(std::shared_ptr<const face::FaceModel> model, GlContext& context,
                           const RenderOptions& options)
    : AnimatedFace(*model, context, options) {
  owned_ = std::move(model);
}

void AnimatedFace::pose(const face::FapFrame& faps) {
  if (posed_ && faps == shown_) return;
  renderer_.setPositions(model_.deform(faps));
  renderer_.setPupilScale(model_.pupilScale(faps));
  shown_ = faps;
  posed_ = true;
}

void AnimatedFace::resize(int width, int height) {
  renderer_.resize(width, height);
  camera_ = frameHead(model_.mesh().positions, static_cast<double>(width) / height);
}

void AnimatedFace::frameMouth() {
  Eigen::Vector3d lips = Eigen::Vector3d::Zero();
  const std::vector<int> inner = model_.innerLipVertices();
  for (int v : inner) lips += model_.mesh().positions.col(v);
  camera_.target = (lips / static_cast<double>(inner.size())).cast<float>();
  camera_.distance *= 0.3f;
}

}  // namespace th::render
