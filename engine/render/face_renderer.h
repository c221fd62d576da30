// Draws a face mesh (ICT FaceKit's materials: skin, eyes, teeth, gums and tongue, eyelashes) with OpenGL 3.3
// core into a multisampled framebuffer of its own, then reads it back (off-screen) or blits it to a window.
//
//   th::render::OffscreenContext context;
//   const th::face::Mesh mesh = th::face::loadObjMesh(th::face::ictFaceDirectory() / "generic_neutral_mesh.obj");
//   th::render::FaceRenderer renderer(context, mesh, {.width = 1280, .height = 720});
//   const th::render::OrbitCamera camera = th::render::frameHead(mesh.positions, 1280.0 / 720.0);
//   th::render::Image frame;
//   for (const Eigen::Matrix3Xd& positions : animation) {   // 3 x V, the mesh's vertex order
//     renderer.setPositions(positions);                      // normals recomputed, vertices uploaded
//     renderer.render(camera);
//     renderer.readPixels(frame);                            // RGB8, top row first; no allocation after the first
//   }
//
// (render/animated_face.h draws the face model's frames through one of these.)
//
// The constructor (about a second) uploads the topology and the materials, and measures per-vertex detail
// once on the mesh as given, at rest: ambient occlusion (96 depth views on the GPU), the lips' weight, the
// lashes' fade; per frame only positions and normals change (normals are recomputed on the CPU, so any
// deformation is lit right). Lights are fixed to the camera, so an orbiting viewer always sees a studio-lit
// face. Cost: llvmpipe pays several times a frame's cost for 4x MSAA; for long exports at 720p, {.samples =
// 1, .fxaa = true} looks nearly as smooth at a fraction of it (bench/render_bench.cpp has the numbers).
//
// Thread contract: a renderer belongs to its context's thread; the context must outlive it. Every call makes
// the context current first, so several renderers and contexts may alternate on one thread.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "face/mesh.h"
#include "render/camera.h"
#include "render/fxaa.h"
#include "render/gl_context.h"
#include "render/image.h"
#include "render/normals.h"
#include "render/raw_frame.h"
#include "render/yuv.h"

namespace th::render {

class Culling;
struct DrawList;

struct Light {
  Eigen::Vector3f direction;  // towards the light, camera space: +x right, +y up, +z towards the viewer
  Eigen::Vector3f colour;     // linear
};

// A three-point studio light: a warm key from the upper left, a cool soft fill from the right, a rim light
// from behind that separates the head from the background; plus a sky/ground ambient.
struct Lighting {
  Light key{{-0.6f, 0.55f, 0.6f}, {2.0f, 1.88f, 1.7f}};
  Light fill{{0.8f, -0.1f, 0.6f}, {0.27f, 0.27f, 0.29f}};
  Light rim{{0.35f, 0.55f, -0.75f}, {1.6f, 1.6f, 1.75f}};
  Eigen::Vector3f skyAmbient{0.16f, 0.16f, 0.17f};
  Eigen::Vector3f groundAmbient{0.07f, 0.06f, 0.055f};
  float exposure = 1.0f;
};

// Colours in sRGB (0..1), as one would pick them.
struct Appearance {
  Eigen::Vector3f skin{0.85f, 0.65f, 0.56f};
  Eigen::Vector3f lips{0.62f, 0.27f, 0.27f};
  // Drawn on the skin from its texture coordinates: the eyebrows, and cropped hair on the scalp.
  Eigen::Vector3f brows{0.21f, 0.13f, 0.085f};
  Eigen::Vector3f hair{0.16f, 0.11f, 0.08f};
  Eigen::Vector3f sclera{0.93f, 0.91f, 0.88f};
  Eigen::Vector3f iris{0.36f, 0.46f, 0.52f};  // grey-blue
  Eigen::Vector3f teeth{0.93f, 0.90f, 0.82f};
  Eigen::Vector3f gums{0.72f, 0.36f, 0.38f};  // gums and tongue
  Eigen::Vector3f lashes{0.035f, 0.025f, 0.02f};
  // Angular radii of the pupil, the iris and the clear cornea, seen from the eyeball's centre (degrees). The
  // iris and cornea values are where ICT FaceKit's iris disc and corneal bulge end.
  float pupilDegrees = 8.5f;
  float irisDegrees = 24.0f;
  float corneaDegrees = 25.0f;
  // The thin layers round the eyes (tear film, eye occlusion, eye blend) are drawn only if true: made for
  // textures, they look like grey films without them.
  bool drawEyeLayers = false;
};

struct RenderOptions {
  int width = 640;
  int height = 480;
  int samples = 4;  // MSAA; 1 disables it. Clamped to what the driver offers.
  // With samples = 1: smooth the edges with FXAA on the CPU as readPixels() copies the frame out (present()
  // shows the frame without it). llvmpipe pays about three times the frame's CPU time for 4x MSAA at 720p,
  // this filter a few milliseconds: the choice for long exports at high resolutions.
  bool fxaa = false;
  // Drop the triangles that face away from the camera, and the mouth's inside where it cannot show (see
  // setMouthOpening), before GL sees them (render()): the same image, several milliseconds a frame less on
  // llvmpipe. false leaves culling to GL alone (tests compare the two).
  bool cullOnCpu = true;
  // Read and finish only a rectangle round the head: readRaw() reads, and finish() composites, filters and
  // converts only the bounding box of the head's projected vertices, 8 pixels wider on every side (FXAA
  // reaches no further) and on even pixels (Y'CbCr 4:2:0 blocks); the rest of the frame is the backdrop,
  // copied. The same image for half the work where the head fills half the frame, as at 1280x720. false:
  // the whole frame every time (tests compare the two).
  bool cropToHead = true;
  // Draw the eyeballs (sclera and iris) with fewer triangles (render/simplify.h): their look is shaded per
  // pixel, and llvmpipe pays per triangle (what it saves: docs/results.md, "Figures behind choices in the
  // code"); some pixels along the eyes' edges change (tests/render: SimplifiedEyeballsLookTheSame).
  bool simplifyEyeballs = true;
  Eigen::Vector3f backgroundTop{0.36f, 0.40f, 0.46f};     // sRGB, a neutral grey-blue
  Eigen::Vector3f backgroundBottom{0.13f, 0.14f, 0.17f};  // sRGB
  Lighting lighting{};
  Appearance appearance{};
};

class FaceRenderer {
 public:
  // Makes `context` current; uploads the mesh (at its own positions). Throws th::Error if a shader does not
  // compile (with the driver's message), the framebuffer is incomplete, or the mesh is empty.
  FaceRenderer(GlContext& context, const face::Mesh& mesh, RenderOptions options = {});
  ~FaceRenderer();
  FaceRenderer(const FaceRenderer&) = delete;
  FaceRenderer& operator=(const FaceRenderer&) = delete;

  // New positions (3 x V, the mesh's vertex order): normals are recomputed and both are uploaded.
  void setPositions(const Eigen::Matrix3Xd& positions);
  // The mesh's inner lip line (vertex indices, any order; e.g. MPEG-4 feature points 2.2-2.9): the mouth's
  // inside is then drawn only where it can show through the opening (see render()). Empty: always drawn.
  void setMouthOpening(std::vector<int> innerLipVertices);
  // The same for the eyeballs (sclera and iris): each eye's lid line (the face's left eye first, +x).
  void setEyeOpenings(std::vector<int> leftLidVertices, std::vector<int> rightLidVertices);
  // The pupils' radii relative to rest: [0] the face's left eye (MPEG-4 FAP 29), [1] its right (FAP 30), as
  // face::FaceModel::pupilScale gives them. Kept until changed; a pupil never grows past its iris.
  void setPupilScale(const std::array<double, 2>& scale);
  // Draws the face into the multisampled target, over a transparent background (the backdrop goes under it
  // in readPixels()/finish() or present()).
  void render(const OrbitCamera& camera);
  // Resolves the last render() (MSAA or FXAA) and reads it (RGB8, top row first); `image` is resized only
  // when needed.
  void readPixels(Image& image);
  // readPixels() in two halves, for a pipeline: readRaw() on the context's thread (waits for the frame and
  // copies it out), finish() on any thread (the backdrop under the head, FXAA if on, rows top-down). finish()
  // only reads the renderer's settings: it may run on another thread while this one renders the next frame,
  // as long as nothing calls resize() meanwhile.
  void readRaw(RawFrame& frame);
  void finish(RawFrame& frame, Image& image) const;
  // The same into Y'CbCr 4:2:0 (limited range, BT.709 or BT.601), as a video encoder takes it (render/yuv.h).
  void finish(RawFrame& frame, Yuv420Image& image, bool bt709) const;
  // render() + readPixels() into a new image.
  Image renderImage(const OrbitCamera& camera);
  // Resolves the last render() and copies it to the window's back buffer (framebuffer 0), scaled to its size;
  // or, with `left`, to the columns from `left` on (a side panel beside it).
  void present(std::pair<int, int> framebufferSize, int left = 0);
  // The backdrop and the face straight into the current context's framebuffer 0 (a window with a depth buffer,
  // WindowOptions::depth), at this renderer's size, without MSAA or FXAA: what render() + present() show at one
  // sample, with neither the copy nor the backdrop's blending (on llvmpipe at 720p a quarter of the frame's
  // budget: docs/results.md, "Figures behind choices in the code").
  // The renderer's own targets are left as they were. `left`: where its picture starts, in pixels from the
  // window's left edge (a side panel beside it); the colour beside the picture is left as it was, the window's
  // depth buffer is cleared.
  void renderToWindow(const OrbitCamera& camera, int left = 0);
  // New target size (for a resized window); keeps everything else.
  void resize(int width, int height);

  const RenderOptions& options() const { return options_; }
  int samples() const { return samples_; }                       // the MSAA sample count in use
  int trianglesDrawn() const { return trianglesDrawn_; }         // given to GL by the last render()
  const PixelRegion& drawnRegion() const { return drawn_; }      // where the last render() drew
  const Eigen::Matrix3Xf& normals() const { return normals_; }   // of the last positions set
  const Eigen::VectorXf& openness() const { return openness_; }  // per-vertex ambient openness, 0..1
  const Eigen::VectorXf& lipWeight() const { return lipWeight_; }

 private:
  struct Gl;

  void createPrograms();
  void createBuffers(const std::vector<float>& detail);
  void createTargets();
  void resolve();
  void selectVisible(const Eigen::Vector3f& eye, const Eigen::Matrix4f& viewProjection);
  // Into the bound framebuffer, after its clear; with the backdrop between the opaque and the see-through
  // surfaces if asked.
  void drawFace(const OrbitCamera& camera, bool withBackdrop = false);
  enum class Backdrop { kUnder, kBehindDepth };
  void drawBackdrop(Backdrop how);  // the gradient, into the bound framebuffer

  GlContext& context_;
  RenderOptions options_;
  int numVertices_ = 0;
  int samples_ = 1;
  VertexNormals normalSolver_;
  Eigen::Matrix3Xf normals_;
  Eigen::VectorXf openness_;
  Eigen::VectorXf lipWeight_;
  std::vector<float> vertexData_;  // interleaved position + normal, reused every frame
  RawFrame raw_;                   // readPixels()' own
  FrameBackdrop backdrop_;         // for the size in use
  PixelRegion drawn_;              // where the last render() drew
  int trianglesDrawn_ = 0;
  std::unique_ptr<DrawList> drawList_;  // the draws, their materials and eyes (render/materials.h)
  std::unique_ptr<Culling> culling_;    // this frame's triangles of each draw (render/culling.h)
  std::unique_ptr<Gl> gl_;
};

}  // namespace th::render
