#include "render/face_renderer.h"

#include <glad/gl.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "gl_program.h"
#include "render/backdrop.h"
#include "render/culling.h"
#include "render/frame_targets.h"
#include "render/fxaa.h"
#include "render/materials.h"
#include "render/surfaces.h"
#include "shader_sources.h"

namespace th::render {
namespace {

void checkInputs(const face::Mesh& mesh, const RenderOptions& options) {
  if (mesh.numVertices() == 0 || mesh.triangles.empty()) throw Error("FaceRenderer: the mesh is empty");
  if (mesh.triangleMaterial.size() != mesh.triangles.size())
    throw Error("FaceRenderer: the mesh needs one material index per triangle");
  if (options.width <= 0 || options.height <= 0)
    throw Error("FaceRenderer: the image size must be positive, not " + std::to_string(options.width) + "x" +
                std::to_string(options.height));
}

}  // namespace

struct FaceRenderer::Gl {
  GLuint vao = 0;
  GLuint emptyVao = 0;
  GLuint dynamicBuffer = 0;  // position + normal, per frame
  GLuint staticBuffer = 0;   // openness + (lip weight or opacity) + texture coordinates + skin markings
  GLuint indexBuffer = 0;    // the front-facing triangles, per frame
  GLuint backgroundProgram = 0;
  FrameTargets targets;
  bool resolved = false;  // the resolve target holds the last render

  FaceProgram face[kNumPrograms] = {};
  struct {
    GLint top, bottom, aspect;
  } background{};

  void release() { targets.release(); }
  void releaseAll() {
    release();
    for (FaceProgram& p : face) glDeleteProgram(p.id);
    glDeleteProgram(backgroundProgram);
    glDeleteBuffers(1, &dynamicBuffer);
    glDeleteBuffers(1, &staticBuffer);
    glDeleteBuffers(1, &indexBuffer);
    glDeleteVertexArrays(1, &vao);
    glDeleteVertexArrays(1, &emptyVao);
  }
};

FaceRenderer::FaceRenderer(GlContext& context, const face::Mesh& mesh, RenderOptions options)
    : context_(context), options_(std::move(options)), numVertices_(mesh.numVertices()), normalSolver_(mesh) {
  checkInputs(mesh, options_);
  const SurfaceMap map = classifySurfaces(mesh);
  drawList_ = std::make_unique<DrawList>(buildDrawList(mesh, map, options_.appearance, options_.simplifyEyeballs));
  culling_ = std::make_unique<Culling>(*drawList_, numVertices_, options_.cullOnCpu);

  context_.makeCurrent();
  gl_ = std::make_unique<Gl>();
  try {
    // Per-vertex detail from the mesh at rest.
    normalSolver_.compute(mesh.positions, normals_);
    VertexDetail detail = measureVertexDetail(mesh, map, normals_);
    openness_ = std::move(detail.openness);
    lipWeight_ = std::move(detail.lipWeight);
    createPrograms();
    createBuffers(detail.interleaved);
    createTargets();
    setPositions(mesh.positions);
  } catch (...) {
    gl_->releaseAll();
    throw;
  }
}

// The face's program variants (render/materials.h: Program) and the backdrop's.
void FaceRenderer::createPrograms() {
  Gl& g = *gl_;
  for (int p = 0; p < kNumPrograms; ++p) linkFaceProgram(static_cast<Program>(p), g.face[p]);
  g.backgroundProgram = linkProgram(shaders::kBackground_vert, shaders::kBackground_frag, "background");
  g.background = {glGetUniformLocation(g.backgroundProgram, "uTop"),
                  glGetUniformLocation(g.backgroundProgram, "uBottom"),
                  glGetUniformLocation(g.backgroundProgram, "uAspect")};
}

// The vertex arrays and buffers: positions and normals (per frame), the per-vertex detail and texture
// coordinates (`detail`, kDetailFloats a vertex: render/materials.h, VertexDetail::interleaved), the triangles
// drawn (per frame).
void FaceRenderer::createBuffers(const std::vector<float>& detail) {
  Gl& g = *gl_;
  glGenVertexArrays(1, &g.vao);
  glGenVertexArrays(1, &g.emptyVao);
  glBindVertexArray(g.vao);
  glGenBuffers(1, &g.dynamicBuffer);
  glBindBuffer(GL_ARRAY_BUFFER, g.dynamicBuffer);
  vertexData_.resize(static_cast<std::size_t>(numVertices_) * 6);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertexData_.size() * sizeof(float)), nullptr, GL_STREAM_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<const void*>(3 * sizeof(float)));  // GL's offset-as-pointer idiom
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glGenBuffers(1, &g.staticBuffer);
  glBindBuffer(GL_ARRAY_BUFFER, g.staticBuffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(detail.size() * sizeof(float)), detail.data(), GL_STATIC_DRAW);
  constexpr GLsizei stride = kDetailFloats * sizeof(float);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, nullptr);
  glVertexAttribPointer(3, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(2 * sizeof(float)));
  glVertexAttribPointer(4, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(4 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glEnableVertexAttribArray(3);
  glEnableVertexAttribArray(4);
  glGenBuffers(1, &g.indexBuffer);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.indexBuffer);
  const std::size_t numIndices = drawList_->indices.size();
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(numIndices * sizeof(std::uint32_t)), nullptr,
               GL_STREAM_DRAW);
  glBindVertexArray(0);
}

FaceRenderer::~FaceRenderer() {
  if (!gl_) return;
  try {
    context_.makeCurrent();
  } catch (...) {
    return;  // the context has gone wrong: there is nothing to release the objects with
  }
  gl_->releaseAll();
}

void FaceRenderer::createTargets() {
  Gl& g = *gl_;
  const GLsizei w = options_.width;
  const GLsizei h = options_.height;
  samples_ = g.targets.create(w, h, options_.samples, "FaceRenderer");
  g.resolved = false;
  backdrop_ = makeBackdrop(w, h, options_.backgroundTop, options_.backgroundBottom);
  drawn_ = {0, 0, w, h};  // nothing read yet: a new target holds anything
}

void FaceRenderer::resize(int width, int height) {
  if (width <= 0 || height <= 0)
    throw Error("FaceRenderer: the image size must be positive, not " + std::to_string(width) + "x" +
                std::to_string(height));
  if (width == options_.width && height == options_.height) return;
  context_.makeCurrent();
  gl_->release();
  options_.width = width;
  options_.height = height;
  createTargets();
}

void FaceRenderer::setPositions(const Eigen::Matrix3Xd& positions) {
  if (positions.cols() != numVertices_)
    throw Error("FaceRenderer: " + std::to_string(positions.cols()) + " positions for a mesh of " +
                std::to_string(numVertices_) + " vertices");
  normalSolver_.compute(positions, normals_);
  for (Eye& eye : drawList_->eyes) eye.track(positions);
  float* out = vertexData_.data();
  for (Eigen::Index v = 0; v < numVertices_; ++v, out += 6) {
    out[0] = static_cast<float>(positions(0, v));
    out[1] = static_cast<float>(positions(1, v));
    out[2] = static_cast<float>(positions(2, v));
    out[3] = normals_(0, v);
    out[4] = normals_(1, v);
    out[5] = normals_(2, v);
  }
  context_.makeCurrent();
  glBindBuffer(GL_ARRAY_BUFFER, gl_->dynamicBuffer);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(vertexData_.size() * sizeof(float)), vertexData_.data());
}

void FaceRenderer::setMouthOpening(std::vector<int> innerLipVertices) {
  culling_->setMouthOpening(std::move(innerLipVertices));
}

void FaceRenderer::setEyeOpenings(std::vector<int> leftLidVertices, std::vector<int> rightLidVertices) {
  culling_->setEyeOpenings(std::move(leftLidVertices), std::move(rightLidVertices));
}

// This frame's triangles (render/culling.h), into the index buffer.
void FaceRenderer::selectVisible(const Eigen::Vector3f& eye, const Eigen::Matrix4f& viewProjection) {
  culling_->select(*drawList_, vertexData_, eye, viewProjection, options_.width, options_.height);
  trianglesDrawn_ = culling_->numTriangles();
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gl_->indexBuffer);  // (the VAO is not bound: this binds no VAO state)
  glBindVertexArray(gl_->vao);
  const std::vector<std::uint32_t>& indices = culling_->indices();
  glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(culling_->numIndices() * sizeof(indices[0])),
                  indices.data());
  glBindVertexArray(0);
}

void FaceRenderer::setPupilScale(const std::array<double, 2>& scale) {
  for (Eye& eye : drawList_->eyes)
    eye.pupilScale = static_cast<float>(std::max(0.0, scale[static_cast<std::size_t>(eye.side)]));
}

void FaceRenderer::render(const OrbitCamera& camera) {
  context_.makeCurrent();
  Gl& g = *gl_;
  glBindFramebuffer(GL_FRAMEBUFFER, samples_ > 1 ? g.targets.msaaFramebuffer : g.targets.resolveFramebuffer);
  glViewport(0, 0, options_.width, options_.height);
  // Transparent: the backdrop goes under the head afterwards (render/backdrop.h). The whole target: llvmpipe
  // clears a tile with a memset, where a clear held to the head's region (a scissor) would be drawn as a quad,
  // at twice the cost. Only the region is read back and finished (RenderOptions::cropToHead).
  glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  drawFace(camera);
  g.resolved = samples_ == 1;
}

void FaceRenderer::renderToWindow(const OrbitCamera& camera, int left) {
  context_.makeCurrent();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  // The viewport clips the backdrop's screen-covering triangle and the head alike: nothing is drawn beside it.
  glViewport(left, 0, options_.width, options_.height);
  // The backdrop after the head's opaque surfaces, only where they left the far plane; the see-through parts
  // after it. The same picture as render() + present(): those parts blend "over" what is below, which is
  // the backdrop here and transparent black there (then composited under the backdrop): premultiplied "over"
  // gives the same either way.
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  drawFace(camera, true);
}

// The backdrop's gradient over the bound framebuffer: under what is there (GL's "under" blending,
// colour += (1 - alpha) * backdrop, alpha becomes 1; a second pass over the same frame changes nothing); or
// behind what is there, where the depth buffer still holds the far plane (neither colour nor depth of the
// head's opaque surfaces is touched, and llvmpipe skips shading the blocks they cover).
void FaceRenderer::drawBackdrop(Backdrop how) {
  Gl& g = *gl_;
  if (how == Backdrop::kBehindDepth) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
  } else {
    glDisable(GL_DEPTH_TEST);
  }
  glDisable(GL_CULL_FACE);
  if (how == Backdrop::kUnder) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
  } else {
    glDisable(GL_BLEND);
  }
  glUseProgram(g.backgroundProgram);
  setVector(g.background.top, options_.backgroundTop);
  setVector(g.background.bottom, options_.backgroundBottom);
  glUniform1f(g.background.aspect, static_cast<float>(options_.width) / static_cast<float>(options_.height));
  glBindVertexArray(g.emptyVao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
}

void FaceRenderer::drawFace(const OrbitCamera& camera, bool withBackdrop) {
  Gl& g = *gl_;
  const float aspect = static_cast<float>(options_.width) / static_cast<float>(options_.height);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_TRUE);
  const Eigen::Matrix4f view = camera.view();
  const Eigen::Matrix4f viewProjection = camera.projection(aspect) * view;
  const Eigen::Vector3f eyePosition = camera.eye();
  drawn_ = options_.cropToHead ? headRegion(vertexData_, viewProjection, options_.width, options_.height)
                               : PixelRegion{0, 0, options_.width, options_.height};

  selectVisible(eyePosition, viewProjection);
  setFrameUniforms(g.face, view, viewProjection, eyePosition, options_.lighting, options_.appearance);

  glBindVertexArray(g.vao);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied "over": the cornea adds its glints
  bool backdropDrawn = !withBackdrop;
  const auto drawBackdropBehind = [&] {
    drawBackdrop(Backdrop::kBehindDepth);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glBindVertexArray(g.vao);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    backdropDrawn = true;
  };
  for (std::size_t d = 0; d < drawList_->draws.size(); ++d) {
    const Draw& draw = drawList_->draws[d];
    const Culling::Span& visible = culling_->ofDraw(d);
    if (visible.count == 0) continue;
    // The backdrop after the opaque surfaces (their depth hides it), before the see-through ones (drawn over it).
    if (!backdropDrawn && isBlended(draw.surface)) drawBackdropBehind();
    if (isBlended(draw.surface))
      glEnable(GL_BLEND);
    else
      glDisable(GL_BLEND);
    if (isTwoSided(draw.surface))
      glDisable(GL_CULL_FACE);
    else
      glEnable(GL_CULL_FACE);
    // Unsorted see-through cards and layers must not hide one another; the cornea may (it is one surface).
    glDepthMask(isTwoSided(draw.surface) ? GL_FALSE : GL_TRUE);
    const FaceProgram& f = g.face[static_cast<int>(draw.program)];
    glUseProgram(f.id);
    setDrawUniforms(f, draw, drawList_->eyes, options_.appearance);
    glDrawRangeElements(GL_TRIANGLES, draw.lowest, draw.highest, visible.count, GL_UNSIGNED_INT,
                        reinterpret_cast<const void*>(visible.first * sizeof(std::uint32_t)));  // offset-as-pointer
  }
  if (!backdropDrawn) drawBackdropBehind();
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
}

void FaceRenderer::resolve() {
  Gl& g = *gl_;
  if (g.resolved) return;
  g.targets.resolve(options_.width, options_.height);
  g.resolved = true;
}

void FaceRenderer::readPixels(Image& image) {
  readRaw(raw_);
  finish(raw_, image);
}

void FaceRenderer::readRaw(RawFrame& frame) {
  context_.makeCurrent();
  resolve();
  gl_->targets.read(options_.width, options_.height, drawn_, frame);
}

void FaceRenderer::finish(RawFrame& frame, Image& image) const {
  finishFrame(frame, backdrop_, samples_ == 1 && options_.fxaa, image, "FaceRenderer");
}

void FaceRenderer::finish(RawFrame& frame, Yuv420Image& image, bool bt709) const {
  finishFrame(frame, backdrop_, samples_ == 1 && options_.fxaa, image, bt709, "FaceRenderer");
}

Image FaceRenderer::renderImage(const OrbitCamera& camera) {
  render(camera);
  Image image;
  readPixels(image);
  return image;
}

void FaceRenderer::present(std::pair<int, int> framebufferSize, int left) {
  context_.makeCurrent();
  resolve();
  // The backdrop under the head (a second present() of the same frame changes nothing).
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->targets.resolveFramebuffer);
  glViewport(0, 0, options_.width, options_.height);
  drawBackdrop(Backdrop::kUnder);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->targets.resolveFramebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  const bool same = framebufferSize.first - left == options_.width && framebufferSize.second == options_.height;
  glBlitFramebuffer(0, 0, options_.width, options_.height, left, 0, framebufferSize.first, framebufferSize.second,
                    GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace th::render
