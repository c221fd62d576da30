// Draws a user's character (avatar/avatar_model.h) with OpenGL 3.3 core: its textures and glTF
// metallic-roughness materials (VRM's MToon as unlit colour), under the studio lights and over the backdrop
// the face has, into a multisampled framebuffer of its own, read back like the face's (render/raw_frame.h),
// or straight into a window (renderToWindow).
// The character is posed and skinned on the CPU (avatar/avatar_pose.h); each frame only the vertices that
// moved are uploaded.
//
// render/animated_avatar.h poses it and holds the camera: the character as a Head.
//
// Draw order: opaque and alpha-tested surfaces first, then the blended ones back to front (by each
// primitive's centre). The camera frames the head: the vertices its head bone (or a bone under it) moves most.
// What the camera cannot see is not drawn (AvatarRenderOptions::cull): each primitive's triangles are cut into
// clusters of 128 in their order, each with the bounding box of its vertices as posed (kept for the clusters
// no vertex of which moves, measured again each frame for the others), and only the clusters whose box meets
// the view are given to GL: a whole-body character framed on its head is mostly off-screen. llvmpipe's cost
// is then the pixels it shades: the opaque clusters go from the nearest to the farthest, after a pass that
// writes their depth alone, so that each pixel is shaded once; each kind of material has a shader of its own
// (llvmpipe runs both sides of a branch). With one sample, the opaque clusters no vertex of which moves (the
// shoulders, the arms) are drawn once for a camera into a target of their own and copied, colour and depth,
// under each frame. The frame is read back and finished only within the boxes' projection (8 pixels wider:
// FXAA's reach); the rest is the backdrop.
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
  // Draw only the clusters of triangles in view, the opaque ones from the nearest and their depth first (each
  // pixel shaded once), keep what never moves from frame to frame, and read back only the pixels they may
  // cover: the same picture (but where two surfaces lie at exactly the same depth) for a fraction of the work.
  // false: every triangle in the file's order each frame, the whole frame read back (tests compare the two).
  bool cull = true;
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

  // Which vertices later setMeshes(…, moving) calls may move (avatar::movingVertices): only the clusters that
  // hold one are measured again each frame. Without it, every cluster of a primitive with a moving vertex is.
  void setMovingVertices(const avatar::MovingVertices& moving);
  // The posed meshes (as many as the avatar's, each with its primitives); with `moving`, only its vertices are
  // uploaded again (the others must be as the last call left them).
  void setMeshes(const std::vector<avatar::DeformedMesh>& meshes, const avatar::MovingVertices* moving = nullptr);
  // Into the renderer's own target, over a transparent background (the backdrop goes under it in finish() or
  // present()).
  void render(const OrbitCamera& camera);
  // The backdrop and the character straight into the current context's framebuffer 0 (a window with a depth
  // buffer, WindowOptions::depth), at this renderer's size, without MSAA or FXAA: what render() + present()
  // show at one sample, without the copy and the backdrop's blending. The renderer's own target is left as it
  // was. `left`: where the picture starts, in pixels from the window's left edge (a side panel beside it); the
  // colour beside the picture is left as it was, the window's depth buffer is cleared.
  void renderToWindow(const OrbitCamera& camera, int left = 0);
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
  int trianglesDrawn() const { return trianglesDrawn_; }     // given to GL by the last render() (not the kept ones)
  const PixelRegion& drawnRegion() const { return drawn_; }  // what the last render() may have drawn in

 private:
  struct Gl;
  void createTargets();
  void resolve();
  // What a pass draws: every cluster, the opaque ones no vertex of which moves (the still layer, kept between
  // frames), or the rest.
  enum class Layer { kAll, kStill, kMoving };
  // The clusters of `layer` in view of `viewProjection` into this frame's draw order (the opaque ones' from
  // the nearest to `eye`), and the pixels they may cover (drawn_).
  void selectVisible(const Eigen::Matrix4f& viewProjection, const Eigen::Vector3f& eye, Layer layer);
  // Into the bound framebuffer, after its clear; with the backdrop between the opaque and the blended surfaces
  // if asked.
  void drawCharacter(const OrbitCamera& camera, bool withBackdrop, Layer layer = Layer::kAll);
  // The still layer for `camera` into its own target, unless it holds it already; then copied (colour and
  // depth) into the single-sample target.
  void drawStillLayer(const OrbitCamera& camera);
  void drawBackdropBehind();
  void setSceneUniforms(const Eigen::Matrix4f& view, const Eigen::Matrix4f& viewProjection, const Eigen::Vector3f& eye);

  GlContext& context_;
  const avatar::Avatar& avatar_;
  AvatarRenderOptions options_;
  std::unique_ptr<Gl> gl_;
  int samples_ = 1;
  FrameBackdrop backdrop_;
  RawFrame raw_;
  std::vector<float> upload_;
  PixelRegion drawn_;
  int trianglesDrawn_ = 0;
};

}  // namespace th::render
