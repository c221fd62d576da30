// A user's character as a Head (render/head.h): its rig, a renderer (render/avatar_renderer.h) and a camera on
// its head, posed by one frame at a time. Its mouth speaks with its viseme targets where the frame has visemes
// and the character has the targets, else with the FAPs (avatar/avatar_pose.h).
//
//   th::render::OffscreenContext context;
//   th::render::AnimatedAvatar character(avatar, context, {.width = 1280, .height = 720});
//   const th::render::Image& image = character.draw(faps, visemeProbabilities);   // or nullptr
//
// Thread contract: belongs to its context's thread; the context and the avatar must outlive it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "face/fap.h"
#include "render/avatar_renderer.h"
#include "render/camera.h"
#include "render/gl_context.h"
#include "render/head.h"

namespace th::render {

// A portrait framing of the character's head: the vertices of its face mesh (the one with the most morph
// targets) that its head bone or a bone under it moves most, their bounding box with room for the neck, seen
// from 8° above.
OrbitCamera frameAvatarHead(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes,
                            double aspect);

// Where the mouth is drawn now: the mean of the vertices its opening target (jawOpen, else viseme_aa, else VRM's
// aa) moves most; NaN without one.
Eigen::Vector3f avatarMouthCentre(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes);

class AnimatedAvatar final : public Head {
 public:
  AnimatedAvatar(const avatar::Avatar& avatar, GlContext& context, const AvatarRenderOptions& options = {});

  void pose(const face::FapFrame& faps, const float* visemeProbabilities) override;
  // By the weights alone: they carry the head and the eyes too.
  void pose(const face::FapFrame& /*faps*/, const avatar::AvatarInput& weights) override { pose(weights); }
  void poseAt(const face::FapTrack& animation, double seconds) override;
  void pose(const avatar::AvatarInput& input);
  void render() override { renderer_.render(camera_); }
  void readRaw(RawFrame& frame) override { renderer_.readRaw(frame); }
  void finish(RawFrame& frame, Yuv420Image& image, bool bt709) const override { renderer_.finish(frame, image, bt709); }
  void readPixels(Image& image) override { renderer_.readPixels(image); }
  void present(std::pair<int, int> framebufferSize, int left) override { renderer_.present(framebufferSize, left); }
  void renderToWindow(int left) override { renderer_.renderToWindow(camera_, left); }
  void resize(int width, int height) override;
  // The mouth and the chin, where its opening target moves them; the head stays framed if it has none.
  void frameMouth() override;
  OrbitCamera& camera() override { return camera_; }
  int samples() const override { return renderer_.samples(); }
  // "NAME (how its face is rigged)".
  std::string description() const override;

  const avatar::Avatar& avatar() const { return avatar_; }
  const avatar::AvatarRig& rig() const { return rig_; }
  AvatarRenderer& renderer() { return renderer_; }

 private:
  const avatar::Avatar& avatar_;
  avatar::AvatarRig rig_;
  avatar::MovingVertices moving_;
  AvatarRenderer renderer_;
  avatar::AvatarPose pose_;
  std::vector<avatar::DeformedMesh> meshes_;
  OrbitCamera camera_;
};

}  // namespace th::render
