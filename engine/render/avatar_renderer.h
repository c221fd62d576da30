// Draws a user's character (avatar/avatar_model.h) with OpenGL 3.3 core: its textures and glTF
// metallic-roughness materials (VRM's MToon as unlit colour), under the studio lights and over the backdrop
// the face has, into a multisampled framebuffer of its own, read back like the face's (render/raw_frame.h).
// The character is posed and skinned on the CPU (avatar/avatar_pose.h); each frame only its positions and
// normals are uploaded.
//
//   th::render::OffscreenContext context;
//   th::render::AnimatedAvatar character(avatar, context, {.width = 1280, .height = 720});
//   const th::render::Image& image = character.draw(faps, visemeProbabilities);   // or nullptr
//
// Draw order: opaque and alpha-tested surfaces first, then the blended ones back to front (by each
// primitive's centre). The camera frames the head: the vertices its head bone (or a bone under it) moves most.
// Thread contract: belongs to its context's thread; the context and the avatar must outlive it.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "face/fap.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "render/image.h"
#include "render/raw_frame.h"

namespace th::render {

struct AvatarRenderOptions {
  int width = 640;
  int height = 480;
  int samples = 4;    // MSAA; 1 disables it
  bool fxaa = false;  // with samples = 1, smooth edges on the CPU as the face's renderer does
  Eigen::Vector3f backgroundTop{0.36f, 0.40f, 0.46f};  // sRGB, the face's backdrop
  Eigen::Vector3f backgroundBottom{0.13f, 0.14f, 0.17f};
  Lighting lighting{};
};

class AvatarRenderer {
 public:
  // Makes `context` current, uploads the meshes (at rest) and the textures. Throws th::Error if a shader does
  // not compile or the framebuffer is incomplete.
  AvatarRenderer(GlContext& context, const avatar::Avatar& avatar, AvatarRenderOptions options = {});
  ~AvatarRenderer();
  AvatarRenderer(const AvatarRenderer&) = delete;
  AvatarRenderer& operator=(const AvatarRenderer&) = delete;

  // The posed meshes (as many as the avatar's, each with its primitives); with `moving`, only the primitives
  // with a moving vertex are uploaded again.
  void setMeshes(const std::vector<avatar::DeformedMesh>& meshes, const avatar::MovingVertices* moving = nullptr);
  void render(const OrbitCamera& camera);
  void readRaw(RawFrame& frame);
  void finish(RawFrame& frame, Image& image) const;
  void finish(RawFrame& frame, Yuv420Image& image, bool bt709) const;
  void readPixels(Image& image);
  // Resolves the last render() and copies it, over the backdrop, to the window's back buffer (framebuffer 0),
  // scaled to its size, from column `left` on.
  void present(std::pair<int, int> framebufferSize, int left = 0);
  void resize(int width, int height);

  const AvatarRenderOptions& options() const { return options_; }
  int samples() const { return samples_; }

 private:
  struct Gl;
  void createTargets();
  void resolve();

  GlContext& context_;
  const avatar::Avatar& avatar_;
  AvatarRenderOptions options_;
  std::unique_ptr<Gl> gl_;
  int samples_ = 1;
  FrameBackdrop backdrop_;
  RawFrame raw_;
  std::vector<float> upload_;
};

// A portrait framing of the character's head: the vertices of its face mesh (the one with the most morph
// targets) that its head bone or a bone under it moves most, their bounding box with room for the neck, seen
// from 8° above.
OrbitCamera frameAvatarHead(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes,
                            double aspect);

// Where the mouth is drawn now: the mean of the vertices its opening target (jawOpen, else viseme_aa, else VRM's
// aa) moves most; NaN without one.
Eigen::Vector3f avatarMouthCentre(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes);

// The character as every program shows it: rig, renderer and a camera on the head, posed by one frame at a time.
class AnimatedAvatar {
 public:
  AnimatedAvatar(const avatar::Avatar& avatar, GlContext& context, const AvatarRenderOptions& options = {});
  // The character posed by `faps` (and the mouth classes' probabilities, if any: visemes).
  void pose(const face::FapFrame& faps, const float* classProbabilities);
  void pose(const avatar::AvatarInput& input);
  // An animation at a time (its visemes too, where it has them).
  const Image& draw(const face::FapTrack& animation, double seconds);
  void render() { renderer_.render(camera_); }
  const Image& draw(const face::FapFrame& faps, const float* classProbabilities);
  void resize(int width, int height);
  // The camera close on the lips (film strips): the mouth and the chin, where its opening target moves them;
  // the head stays framed if it has none.
  void frameMouth();

  const avatar::Avatar& avatar() const { return avatar_; }
  const avatar::AvatarRig& rig() const { return rig_; }
  AvatarRenderer& renderer() { return renderer_; }
  OrbitCamera& camera() { return camera_; }

 private:
  const avatar::Avatar& avatar_;
  avatar::AvatarRig rig_;
  avatar::MovingVertices moving_;
  AvatarRenderer renderer_;
  avatar::AvatarPose pose_;
  std::vector<avatar::DeformedMesh> meshes_;
  OrbitCamera camera_;
  Image image_;
};

}  // namespace th::render
