#include "render/face_renderer.h"

#include <glad/gl.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"
#include "gl_program.h"
#include "render/backdrop.h"
#include "render/fxaa.h"
#include "render/occlusion.h"
#include "render/simplify.h"
#include "render/surfaces.h"
#include "shader_sources.h"

namespace th::render {
namespace {

// The variants face.frag is compiled in (see its head comment).
enum class Program : int { kSkin = 0, kSclera, kIris, kPlain };
constexpr int kNumPrograms = 4;
constexpr const char* kProgramDefine[kNumPrograms] = {"SKIN", "SCLERA", "IRIS", "PLAIN"};

Program programOf(Surface s) {
  switch (s) {
    case Surface::kSkin:
      return Program::kSkin;
    case Surface::kSclera:
      return Program::kSclera;
    case Surface::kIris:
      return Program::kIris;
    default:
      return Program::kPlain;
  }
}

// The order of drawing: opaque surfaces first (the backdrop follows them, see render()); then the sclera,
// whose clear cornea is blended over the iris; the lashes and the see-through eye layers last.
int drawRank(Surface s) {
  switch (s) {
    case Surface::kSkin:
      return 0;
    case Surface::kOther:
      return 1;
    case Surface::kTeeth:
      return 2;
    case Surface::kGums:
      return 3;
    case Surface::kIris:
      return 4;
    case Surface::kSclera:
      return 5;
    case Surface::kLashes:
      return 6;
    case Surface::kEyeLayer:
      return 7;
  }
  return 8;
}

bool isBlended(Surface s) {
  return s == Surface::kSclera || s == Surface::kLashes || s == Surface::kEyeLayer;
}

// Cards (lashes) and thin layers are seen from both sides; closed surfaces only from outside.
bool isTwoSided(Surface s) {
  return s == Surface::kLashes || s == Surface::kEyeLayer;
}

Eigen::Vector3f srgbToLinear(const Eigen::Vector3f& c) {
  Eigen::Vector3f out;
  for (int k = 0; k < 3; ++k)
    out[k] = c[k] <= 0.04045f ? c[k] / 12.92f : std::pow((c[k] + 0.055f) / 1.055f, 2.4f);
  return out;
}

float cosDegrees(float degrees) {
  return std::cos(degrees * std::numbers::pi_v<float> / 180.0f);
}

void setVector(GLint location, const Eigen::Vector3f& v) {
  glUniform3f(location, v.x(), v.y(), v.z());
}

// Which surfaces' triangles block a receiving surface's sky (ambient occlusion). The see-through layers and
// the lash cards block nothing; the mouth's inside (teeth, gums, tongue) is blocked only by itself: with the
// neutral face's closed lips counted, the front teeth would stay dark when the mouth opens.
std::uint32_t occludersOf(Surface receiver) {
  const auto bit = [](Surface s) { return 1U << static_cast<unsigned>(s); };
  switch (receiver) {
    case Surface::kTeeth:
    case Surface::kGums:
      return bit(Surface::kTeeth) | bit(Surface::kGums);
    case Surface::kLashes:
    case Surface::kEyeLayer:
      return 0;
    default:
      return bit(Surface::kSkin) | bit(Surface::kOther) | bit(Surface::kSclera) | bit(Surface::kIris) |
             bit(Surface::kTeeth) | bit(Surface::kGums);
  }
}

// The material of a draw, from the appearance (known surfaces) or the MTL file (others).
struct Shading {
  Eigen::Vector3f albedo = Eigen::Vector3f::Constant(0.5f);  // linear
  Eigen::Vector3f specular = Eigen::Vector3f::Constant(0.04f);
  float shininess = 16.0f;
  float opacity = 1.0f;
};

Shading shadingOf(Surface surface, const face::Material* material, const Appearance& look) {
  Shading s;
  switch (surface) {
    case Surface::kSkin:
      s.albedo = srgbToLinear(look.skin);
      // Skin reflects about 3 % at normal incidence; a little more here stands in for its oily sheen.
      s.specular = Eigen::Vector3f::Constant(0.05f);
      s.shininess = 28.0f;
      break;
    case Surface::kSclera:
      s.albedo = srgbToLinear(look.sclera);
      s.specular = Eigen::Vector3f::Constant(0.04f);
      s.shininess = 120.0f;
      break;
    case Surface::kIris:
      s.albedo = srgbToLinear(look.iris);
      s.specular = Eigen::Vector3f::Zero();  // the cornea above it shines instead
      s.shininess = 30.0f;
      break;
    case Surface::kTeeth:
      s.albedo = srgbToLinear(look.teeth);
      s.specular = Eigen::Vector3f::Constant(0.05f);
      s.shininess = 60.0f;
      break;
    case Surface::kGums:
      s.albedo = srgbToLinear(look.gums);
      s.specular = Eigen::Vector3f::Constant(0.05f);
      s.shininess = 80.0f;  // wet
      break;
    case Surface::kLashes:
      s.albedo = srgbToLinear(look.lashes);
      s.specular = Eigen::Vector3f::Constant(0.02f);
      s.shininess = 20.0f;
      break;
    case Surface::kEyeLayer:
    case Surface::kOther:
      if (material != nullptr) {
        s.albedo = material->diffuse;
        s.specular = material->specular.cwiseMin(0.08f);
        s.shininess = std::max(material->shininess, 1.0f);
      }
      s.opacity = surface == Surface::kEyeLayer ? 0.25f : 1.0f;
      break;
  }
  return s;
}

}  // namespace

struct FaceRenderer::Draw {
  Surface surface = Surface::kOther;
  std::size_t firstIndex = 0;
  GLsizei count = 0;
  std::size_t visibleFirst = 0;  // this frame's front-facing triangles, in visibleIndices_ (see render())
  GLsizei visibleCount = 0;
  GLuint lowest = 0;  // vertex index range, so the driver need not scan the indices
  GLuint highest = 0;
  int eye = -1;  // sclera and iris: index into eyes_
  Shading shading;
};

struct FaceRenderer::Eye : EyeRig {
  int side = 0;             // 0: the face's left (+x, FAP 29), 1: its right (FAP 30)
  float pupilScale = 1.0f;  // the pupil's radius relative to rest
};

struct FaceRenderer::Gl {
  GLuint vao = 0;
  GLuint emptyVao = 0;
  GLuint dynamicBuffer = 0;  // position + normal, per frame
  GLuint staticBuffer = 0;   // openness + (lip weight or opacity)
  GLuint indexBuffer = 0;    // the front-facing triangles, per frame
  GLuint backgroundProgram = 0;
  GLuint msaaFramebuffer = 0;
  GLuint msaaColour = 0;
  GLuint msaaDepth = 0;
  GLuint resolveFramebuffer = 0;
  GLuint resolveColour = 0;
  GLuint resolveDepth = 0;  // only without MSAA or FXAA, when drawing straight into the resolve target
  bool resolved = false;    // the resolve target holds the last render

  struct FaceProgram {
    GLuint id = 0;
    GLint viewProjection, cameraPosition, lightDirection, lightColour, skyAmbient, groundAmbient, exposure;
    GLint albedo, lipAlbedo, specular, shininess, opacity, eyeCentre, eyeAxis, eyeCosines, irisColour,
        scleraColour;
  };
  FaceProgram face[kNumPrograms] = {};
  struct {
    GLint top, bottom, aspect;
  } background{};

  void release() {
    glDeleteFramebuffers(1, &msaaFramebuffer);
    glDeleteRenderbuffers(1, &msaaColour);
    glDeleteRenderbuffers(1, &msaaDepth);
    glDeleteFramebuffers(1, &resolveFramebuffer);
    glDeleteRenderbuffers(1, &resolveColour);
    glDeleteRenderbuffers(1, &resolveDepth);
    msaaFramebuffer = msaaColour = msaaDepth = resolveFramebuffer = resolveColour = resolveDepth = 0;
  }
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
  if (numVertices_ == 0 || mesh.triangles.empty()) throw Error("FaceRenderer: the mesh is empty");
  if (mesh.triangleMaterial.size() != mesh.triangles.size())
    throw Error("FaceRenderer: the mesh needs one material index per triangle");
  if (options_.width <= 0 || options_.height <= 0)
    throw Error("FaceRenderer: the image size must be positive, not " + std::to_string(options_.width) + "x" +
                std::to_string(options_.height));
  const Appearance& look = options_.appearance;
  const SurfaceMap map = classifySurfaces(mesh);

  // Triangles sorted into draw calls: by drawing rank, then material.
  std::vector<std::size_t> order(mesh.triangles.size());
  for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const int ra = drawRank(map.ofTriangle[a]);
    const int rb = drawRank(map.ofTriangle[b]);
    return ra != rb ? ra < rb : mesh.triangleMaterial[a] < mesh.triangleMaterial[b];
  });
  std::vector<std::uint32_t>& indices = indices_;
  indices.reserve(order.size() * 3);
  std::vector<std::uint32_t> material;
  for (std::size_t i = 0; i < order.size();) {
    const int materialIndex = mesh.triangleMaterial[order[i]];
    const Surface surface = map.ofTriangle[order[i]];
    std::size_t j = i;
    material.clear();
    while (j < order.size() && mesh.triangleMaterial[order[j]] == materialIndex) {
      for (int v : mesh.triangles[order[j]]) material.push_back(static_cast<std::uint32_t>(v));
      ++j;
    }
    // The iris keeps more of its shape: its pupil is a hole, which a coarser disc turns into a keyhole.
    if (options_.simplifyEyeballs && surface == Surface::kSclera)
      material = simplifyTriangles(material, mesh.positions, {.keep = 0.25f, .error = 0.01f});
    if (options_.simplifyEyeballs && surface == Surface::kIris)
      material = simplifyTriangles(material, mesh.positions, {.keep = 0.25f, .error = 0.002f});
    Draw draw;
    draw.surface = surface;
    draw.firstIndex = indices.size();
    draw.count = static_cast<GLsizei>(material.size());
    indices.insert(indices.end(), material.begin(), material.end());
    const auto [lowest, highest] =
        std::minmax_element(indices.begin() + static_cast<std::ptrdiff_t>(draw.firstIndex), indices.end());
    draw.lowest = *lowest;
    draw.highest = *highest;
    draw.shading = shadingOf(
        draw.surface, materialIndex >= 0 ? &mesh.materials[static_cast<std::size_t>(materialIndex)] : nullptr, look);
    if (draw.surface != Surface::kEyeLayer || look.drawEyeLayers) draws_.push_back(draw);
    i = j;
  }

  // Eyes; each sclera and iris draw takes the eye nearest to it.
  for (EyeRig& rig : findEyes(mesh, map)) eyes_.push_back(Eye{std::move(rig)});
  if (!eyes_.empty()) {
    float meanX = 0.0f;
    for (const Eye& eye : eyes_) meanX += eye.centre.x() / static_cast<float>(eyes_.size());
    for (Eye& eye : eyes_) eye.side = eye.centre.x() >= meanX ? 0 : 1;
  }
  for (Draw& draw : draws_) {
    if ((draw.surface != Surface::kSclera && draw.surface != Surface::kIris) || eyes_.empty()) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t i = draw.firstIndex; i < draw.firstIndex + static_cast<std::size_t>(draw.count); ++i)
      mean += mesh.positions.col(indices[i]);
    const Eigen::Vector3f centre = (mean / static_cast<double>(draw.count)).cast<float>();
    int best = 0;
    for (std::size_t e = 1; e < eyes_.size(); ++e)
      if ((eyes_[e].centre - centre).norm() < (eyes_[static_cast<std::size_t>(best)].centre - centre).norm())
        best = static_cast<int>(e);
    draw.eye = best;
  }

  context_.makeCurrent();
  gl_ = std::make_unique<Gl>();
  Gl& g = *gl_;
  try {
    // Per-vertex detail from the mesh at rest.
    normalSolver_.compute(mesh.positions, normals_);
    std::vector<int> triangleGroup(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      triangleGroup[t] = static_cast<int>(map.ofTriangle[t]);
    std::vector<std::uint32_t> occludedBy(static_cast<std::size_t>(numVertices_));
    for (std::size_t v = 0; v < occludedBy.size(); ++v) occludedBy[v] = occludersOf(map.ofVertex[v]);
    openness_ = computeOpennessCached(mesh.positions, normals_, mesh.triangles, triangleGroup, occludedBy,
                                      detailCacheFolder());
    lipWeight_ = th::render::lipWeight(mesh, map, openness_);
    darkenMouthInterior(mesh, map, openness_);
    const Eigen::VectorXf opacity = lashOpacity(mesh, map);

    // Programs.
    // Each variant: the #version line, its #define, the shared lighting code, then the stage's own source.
    const auto variant = [](const char* source, const char* define) {
      const std::string text = source;
      return std::string("#version 330 core\n#define ") + define + " 1\n" + shaders::kLighting_glsl +
             "#line 2\n" + text.substr(text.find('\n') + 1);
    };
    for (int p = 0; p < kNumPrograms; ++p) {
      Gl::FaceProgram& f = g.face[p];
      f.id = linkProgram(variant(shaders::kFace_vert, kProgramDefine[p]).c_str(),
                         variant(shaders::kFace_frag, kProgramDefine[p]).c_str(),
                         (std::string("face/") + kProgramDefine[p]).c_str());
      const auto at = [&](const char* name) { return glGetUniformLocation(f.id, name); };
      f.viewProjection = at("uViewProjection");
      f.cameraPosition = at("uCameraPosition");
      f.lightDirection = at("uLightDirection");
      f.lightColour = at("uLightColour");
      f.skyAmbient = at("uSkyAmbient");
      f.groundAmbient = at("uGroundAmbient");
      f.exposure = at("uExposure");
      f.albedo = at("uAlbedo");
      f.lipAlbedo = at("uLipAlbedo");
      f.specular = at("uSpecular");
      f.shininess = at("uShininess");
      f.opacity = at("uOpacity");
      f.eyeCentre = at("uEyeCentre");
      f.eyeAxis = at("uEyeAxis");
      f.eyeCosines = at("uEyeCosines");
      f.irisColour = at("uIrisColour");
      f.scleraColour = at("uScleraColour");
    }
    g.backgroundProgram = linkProgram(shaders::kBackground_vert, shaders::kBackground_frag, "background");
    g.background = {glGetUniformLocation(g.backgroundProgram, "uTop"),
                    glGetUniformLocation(g.backgroundProgram, "uBottom"),
                    glGetUniformLocation(g.backgroundProgram, "uAspect")};

    // Buffers.
    glGenVertexArrays(1, &g.vao);
    glGenVertexArrays(1, &g.emptyVao);
    glBindVertexArray(g.vao);
    glGenBuffers(1, &g.dynamicBuffer);
    glBindBuffer(GL_ARRAY_BUFFER, g.dynamicBuffer);
    vertexData_.resize(static_cast<std::size_t>(numVertices_) * 6);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertexData_.size() * sizeof(float)), nullptr,
                 GL_STREAM_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          reinterpret_cast<const void*>(3 * sizeof(float)));  // GL's offset-as-pointer idiom
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    // Detail: openness, then the lip weight on skin or the opacity elsewhere (one channel serves both: no
    // vertex is skin and lash at once).
    std::vector<float> detail(static_cast<std::size_t>(numVertices_) * 2);
    for (Eigen::Index v = 0; v < numVertices_; ++v) {
      detail[static_cast<std::size_t>(2 * v)] = openness_[v];
      detail[static_cast<std::size_t>(2 * v + 1)] =
          map.ofVertex[static_cast<std::size_t>(v)] == Surface::kSkin ? lipWeight_[v] : opacity[v];
    }
    glGenBuffers(1, &g.staticBuffer);
    glBindBuffer(GL_ARRAY_BUFFER, g.staticBuffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(detail.size() * sizeof(float)), detail.data(),
                 GL_STATIC_DRAW);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);
    glEnableVertexAttribArray(2);
    glGenBuffers(1, &g.indexBuffer);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.indexBuffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                 nullptr, GL_STREAM_DRAW);
    visibleIndices_.resize(indices.size());
    glBindVertexArray(0);

    createTargets();
    setPositions(mesh.positions);
  } catch (...) {
    g.releaseAll();
    throw;
  }
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
  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  samples_ = std::clamp(options_.samples, 1, std::max(1, maxSamples));
  const GLsizei w = options_.width;
  const GLsizei h = options_.height;
  const std::string size = std::to_string(w) + "x" + std::to_string(h);

  glGenFramebuffers(1, &g.resolveFramebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, g.resolveFramebuffer);
  glGenRenderbuffers(1, &g.resolveColour);
  glBindRenderbuffer(GL_RENDERBUFFER, g.resolveColour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g.resolveColour);
  if (samples_ == 1) {
    glGenRenderbuffers(1, &g.resolveDepth);
    glBindRenderbuffer(GL_RENDERBUFFER, g.resolveDepth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.resolveDepth);
  }
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("FaceRenderer: the " + size + " framebuffer is incomplete");

  if (samples_ > 1) {
    glGenFramebuffers(1, &g.msaaFramebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, g.msaaFramebuffer);
    glGenRenderbuffers(1, &g.msaaColour);
    glBindRenderbuffer(GL_RENDERBUFFER, g.msaaColour);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g.msaaColour);
    glGenRenderbuffers(1, &g.msaaDepth);
    glBindRenderbuffer(GL_RENDERBUFFER, g.msaaDepth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.msaaDepth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw Error("FaceRenderer: the " + size + " framebuffer with " + std::to_string(samples_) +
                  " samples is incomplete");
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  g.resolved = false;
  backdrop_ = backdropPixels(w, h, options_.backgroundTop, options_.backgroundBottom);
  std::vector<std::uint8_t> opaque(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4, 255);
  for (std::size_t i = 0; i * 3 < backdrop_.size(); ++i) std::copy_n(&backdrop_[3 * i], 3, &opaque[4 * i]);
  rgbaToYuv420(opaque.data(), w, h, false, backdropYuv_[0]);
  rgbaToYuv420(opaque.data(), w, h, true, backdropYuv_[1]);
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
  for (Eye& eye : eyes_) eye.track(positions);
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
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(vertexData_.size() * sizeof(float)),
                  vertexData_.data());
}

void FaceRenderer::checkVertices(const std::vector<int>& vertices, const char* what) const {
  for (int v : vertices)
    if (v < 0 || v >= numVertices_)
      throw Error(std::string("FaceRenderer: ") + what + " vertex " + std::to_string(v) +
                  " is not one of the mesh's " + std::to_string(numVertices_));
}

void FaceRenderer::setMouthOpening(std::vector<int> innerLipVertices) {
  checkVertices(innerLipVertices, "mouth opening");
  openings_[0] = std::move(innerLipVertices);
}

void FaceRenderer::setEyeOpenings(std::vector<int> leftLidVertices, std::vector<int> rightLidVertices) {
  checkVertices(leftLidVertices, "eye opening");
  checkVertices(rightLidVertices, "eye opening");
  openings_[1] = std::move(leftLidVertices);
  openings_[2] = std::move(rightLidVertices);
}

// llvmpipe pays for every triangle it is given (vertex fetch, assembly, set-up, binning) even when it culls it
// or the depth test hides all of it. Two kinds of triangles are dropped here, on the CPU, for less:
// - those facing away from the camera, with the test GL applies (a triangle faces the viewer when the eye lies
//   on the outer side of its plane); edge-on ones (they cover no pixel) are kept for GL to decide. Two-sided
//   surfaces keep every triangle.
// - the mouth's inside (teeth, gums and tongue) and the eyeballs (sclera, iris), where they lie outside their
//   opening on screen: they are enclosed by the lips and cheeks, or the lids and the socket, so any of them
//   that shows is seen through the opening, whose projection lies within the bounding rectangle of the
//   projected lip or lid line, and within the ellipse inscribed in it: the opening is an almond or an oval
//   through the line's extreme points (the eye's corners and lid middles), which lie on that rectangle's
//   sides, not in its corners. The ellipse is widened by a quarter and 8 pixels (the line curves between its
//   vertices). With the lips nearly closed this drops most of the teeth and gums; it always drops the
//   eyeballs' parts behind the lids.
// Both only drop what GL would not draw: tests compare the images with and without this.
void FaceRenderer::selectVisible(const Eigen::Vector3f& eye, const Eigen::Matrix4f& viewProjection) {
  const float* vertex = vertexData_.data();
  const auto at = [&](std::uint32_t v) { return Eigen::Map<const Eigen::Vector3f>(vertex + 6 * std::size_t{v}); };
  const auto project = [&](std::uint32_t v, Eigen::Array2f& ndc) {
    const Eigen::Vector4f clip = viewProjection * at(v).homogeneous();
    if (clip.w() <= 1e-6f) return false;
    ndc = clip.head<2>().array() / clip.w();
    return true;
  };
  // Each opening's bounding rectangle, then ellipse, in normalised device coordinates; none if a vertex of
  // its line is behind the camera.
  struct Opening {
    bool valid = false;
    Eigen::Array2f low, high;  // the bounding rectangle
    Eigen::Array2f centre, inverseRadii;  // the ellipse
  };
  std::array<Opening, 3> openings;
  for (std::size_t o = 0; o < openings_.size(); ++o) {
    Opening& r = openings[o];
    r.valid = options_.cullOnCpu && !openings_[o].empty();
    r.low = Eigen::Array2f::Constant(1e30f);
    r.high = Eigen::Array2f::Constant(-1e30f);
    for (int v : openings_[o]) {
      Eigen::Array2f ndc = Eigen::Array2f::Zero();
      if (!project(static_cast<std::uint32_t>(v), ndc)) {
        r.valid = false;
        break;
      }
      r.low = r.low.min(ndc);
      r.high = r.high.max(ndc);
    }
    if (r.valid) {
      const Eigen::Array2f pixel(2.0f / static_cast<float>(options_.width), 2.0f / static_cast<float>(options_.height));
      const Eigen::Array2f radii = 0.5f * (r.high - r.low) * 1.25f + 8.0f * pixel;
      r.centre = 0.5f * (r.low + r.high);
      r.inverseRadii = radii.inverse();
      r.low = r.centre - radii;
      r.high = r.centre + radii;
    }
  }
  // Whether a triangle's bounding box (in normalised device coordinates) reaches into the opening's ellipse:
  // the box's point nearest the centre, in coordinates where the ellipse is a unit circle.
  const auto reaches = [](const Opening& r, const Eigen::Array2f& lo, const Eigen::Array2f& hi) {
    if ((hi < r.low).any() || (lo > r.high).any()) return false;
    const Eigen::Array2f nearest = r.centre.max(lo).min(hi);
    return ((nearest - r.centre) * r.inverseRadii).square().sum() <= 1.0f;
  };
  std::size_t written = 0;
  trianglesDrawn_ = 0;
  for (Draw& draw : draws_) {
    draw.visibleFirst = written;
    const std::uint32_t* triangle = indices_.data() + draw.firstIndex;
    const std::uint32_t* end = triangle + draw.count;
    // The opening this draw is seen through, if any: the mouth's, or its eye's.
    const Opening* opening = nullptr;
    if (draw.surface == Surface::kTeeth || draw.surface == Surface::kGums)
      opening = &openings[0];
    else if ((draw.surface == Surface::kSclera || draw.surface == Surface::kIris) && draw.eye >= 0)
      opening = &openings[1 + static_cast<std::size_t>(eyes_[static_cast<std::size_t>(draw.eye)].side)];
    if (opening != nullptr && !opening->valid) opening = nullptr;
    if (isTwoSided(draw.surface) || !options_.cullOnCpu) {
      std::copy(triangle, end, visibleIndices_.begin() + static_cast<std::ptrdiff_t>(written));
      written += static_cast<std::size_t>(draw.count);
    } else {
      for (; triangle != end; triangle += 3) {
        const Eigen::Vector3f a = at(triangle[0]);
        const Eigen::Vector3f ab = at(triangle[1]) - a;
        const Eigen::Vector3f ac = at(triangle[2]) - a;
        const Eigen::Vector3f toEye = eye - a;
        // Relative margin: rounding must never drop a triangle GL would draw.
        if (ab.cross(ac).dot(toEye) < -1e-4f * ab.norm() * ac.norm() * toEye.norm()) continue;
        if (opening != nullptr) {
          Eigen::Array2f p0 = Eigen::Array2f::Zero(), p1 = p0, p2 = p0;
          if (project(triangle[0], p0) && project(triangle[1], p1) && project(triangle[2], p2)) {
            const Eigen::Array2f lo = p0.min(p1).min(p2);
            const Eigen::Array2f hi = p0.max(p1).max(p2);
            if (!reaches(*opening, lo, hi)) continue;
          }
        }
        std::copy(triangle, triangle + 3, visibleIndices_.begin() + static_cast<std::ptrdiff_t>(written));
        written += 3;
      }
    }
    draw.visibleCount = static_cast<GLsizei>(written - draw.visibleFirst);
    trianglesDrawn_ += draw.visibleCount / 3;
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gl_->indexBuffer);  // (the VAO is not bound: this binds no VAO state)
  glBindVertexArray(gl_->vao);
  glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(written * sizeof(std::uint32_t)),
                  visibleIndices_.data());
  glBindVertexArray(0);
}

// The head's projected vertices' bounding box, widened and aligned as RenderOptions::cropToHead says; the
// whole frame if a vertex is behind the camera. GL fills a pixel only if its centre lies in a triangle, so
// the box rounded outwards holds every pixel drawn.
PixelRegion FaceRenderer::headRegion(const Eigen::Matrix4f& viewProjection) const {
  const int width = options_.width;
  const int height = options_.height;
  const PixelRegion whole{0, 0, width, height};
  if (!options_.cropToHead) return whole;
  float lowX = 1e30f, highX = -1e30f, lowY = 1e30f, highY = -1e30f;
  const float* vertex = vertexData_.data();
  for (int v = 0; v < numVertices_; ++v, vertex += 6) {
    const Eigen::Vector4f clip = viewProjection * Eigen::Vector4f(vertex[0], vertex[1], vertex[2], 1.0f);
    if (clip.w() <= 1e-6f) return whole;
    const float x = clip.x() / clip.w();
    const float y = clip.y() / clip.w();
    lowX = std::min(lowX, x);
    highX = std::max(highX, x);
    lowY = std::min(lowY, y);
    highY = std::max(highY, y);
  }
  constexpr int kMargin = 8;  // FXAA's reach: its edge pixels lie next to drawn ones, its samples 4.5 further
  // Normalised device coordinates to pixels, rows from the top; clamped first, so that the casts stay in range.
  const auto toPixels = [](float ndc, float size) {
    return std::clamp((ndc + 1.0f) * 0.5f * size, -1e6f, 1e6f);
  };
  const auto fw = static_cast<float>(width);
  const auto fh = static_cast<float>(height);
  const auto evenBelow = [](int v) { return v - (v % 2 + 2) % 2; };
  const int left = std::max(0, evenBelow(static_cast<int>(std::floor(toPixels(lowX, fw))) - kMargin));
  const int top = std::max(0, evenBelow(static_cast<int>(std::floor(fh - toPixels(highY, fh))) - kMargin));
  const int right = std::min(width, evenBelow(static_cast<int>(std::ceil(toPixels(highX, fw))) + kMargin + 1));
  const int bottom = std::min(height, evenBelow(static_cast<int>(std::ceil(fh - toPixels(lowY, fh))) + kMargin + 1));
  if (right <= left || bottom <= top) return {};  // the head is out of view
  return {left, top, right - left, bottom - top};
}

void FaceRenderer::setPupilScale(const std::array<double, 2>& scale) {
  for (Eye& eye : eyes_) eye.pupilScale = static_cast<float>(std::max(0.0, scale[static_cast<std::size_t>(eye.side)]));
}

void FaceRenderer::render(const OrbitCamera& camera) {
  context_.makeCurrent();
  Gl& g = *gl_;
  glBindFramebuffer(GL_FRAMEBUFFER, samples_ > 1 ? g.msaaFramebuffer : g.resolveFramebuffer);
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
  drawn_ = headRegion(viewProjection);

  // Per-frame uniforms, the same in every face program. Lights are given in camera space: the view's inverse
  // rotation turns them into world space.
  selectVisible(eyePosition, viewProjection);
  const Eigen::Matrix3f toWorld = view.topLeftCorner<3, 3>().transpose();
  const Lighting& light = options_.lighting;
  const Light* lights[3] = {&light.key, &light.fill, &light.rim};
  float directions[9];
  float colours[9];
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3f d = (toWorld * lights[i]->direction.normalized()).normalized();
    for (int k = 0; k < 3; ++k) {
      directions[3 * i + k] = d[k];
      colours[3 * i + k] = lights[i]->colour[k];
    }
  }
  const Appearance& look = options_.appearance;
  for (const Gl::FaceProgram& f : g.face) {
    glUseProgram(f.id);
    glUniformMatrix4fv(f.viewProjection, 1, GL_FALSE, viewProjection.data());  // Eigen is column-major, as GL
    setVector(f.cameraPosition, eyePosition);
    glUniform3fv(f.lightDirection, 3, directions);
    glUniform3fv(f.lightColour, 3, colours);
    setVector(f.skyAmbient, light.skyAmbient);
    setVector(f.groundAmbient, light.groundAmbient);
    glUniform1f(f.exposure, light.exposure);
    setVector(f.lipAlbedo, srgbToLinear(look.lips));
    setVector(f.irisColour, srgbToLinear(look.iris));
    setVector(f.scleraColour, srgbToLinear(look.sclera));
    glUniform3f(f.eyeCosines, cosDegrees(look.pupilDegrees), cosDegrees(look.irisDegrees),
                cosDegrees(look.corneaDegrees));
  }

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
  for (const Draw& draw : draws_) {
    if (draw.visibleCount == 0) continue;
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
    const Gl::FaceProgram& f = g.face[static_cast<int>(programOf(draw.surface))];
    glUseProgram(f.id);
    setVector(f.albedo, draw.shading.albedo);
    setVector(f.specular, draw.shading.specular);
    glUniform1f(f.shininess, draw.shading.shininess);
    glUniform1f(f.opacity, draw.shading.opacity);
    if (draw.eye >= 0) {
      const Eye& eye = eyes_[static_cast<std::size_t>(draw.eye)];
      setVector(f.eyeCentre, eye.centre);
      setVector(f.eyeAxis, eye.axis);
      // A pupil scaled in radius on the eyeball's sphere: sin of its angle scales; it stays inside the iris.
      const float rest = std::sin(look.pupilDegrees * std::numbers::pi_v<float> / 180.0f);
      const float limit = 0.9f * std::sin(look.irisDegrees * std::numbers::pi_v<float> / 180.0f);
      const float sine = std::clamp(rest * eye.pupilScale, 0.0f, limit);
      glUniform3f(f.eyeCosines, std::sqrt(1.0f - sine * sine), cosDegrees(look.irisDegrees),
                  cosDegrees(look.corneaDegrees));
    }
    glDrawRangeElements(
        GL_TRIANGLES, draw.lowest, draw.highest, draw.visibleCount, GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(draw.visibleFirst * sizeof(std::uint32_t)));  // offset-as-pointer
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
  glBindFramebuffer(GL_READ_FRAMEBUFFER, g.msaaFramebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, g.resolveFramebuffer);
  glBlitFramebuffer(0, 0, options_.width, options_.height, 0, 0, options_.width, options_.height,
                    GL_COLOR_BUFFER_BIT, GL_NEAREST);
  g.resolved = true;
}

void FaceRenderer::readPixels(Image& image) {
  readRaw(raw_);
  finish(raw_, image);
}

void FaceRenderer::readRaw(RawFrame& frame) {
  context_.makeCurrent();
  resolve();
  frame.width = options_.width;
  frame.height = options_.height;
  frame.region = drawn_;
  const PixelRegion& r = frame.region;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->resolveFramebuffer);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  frame.rgba.resize(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height) * 4);
  // RGBA is the renderbuffer's own layout (a plain copy in Mesa); dropping alpha later is cheaper than GL's.
  if (!frame.rgba.empty())
    glReadPixels(r.left, frame.height - r.top - r.height, r.width, r.height, GL_RGBA, GL_UNSIGNED_BYTE,
                 frame.rgba.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// The CPU's share of a frame, over its region: the backdrop under the head, then FXAA if on (single-sample
// targets only). FXAA's luma is taken row by row as the row is composited, while it is in cache.
void FaceRenderer::prepare(RawFrame& frame) const {
  const PixelRegion& r = frame.region;
  const std::size_t regionPixels = static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
  const std::size_t pixels = static_cast<std::size_t>(options_.width) * static_cast<std::size_t>(options_.height);
  if (frame.width != options_.width || frame.height != options_.height || r.left < 0 || r.top < 0 ||
      r.width < 0 || r.height < 0 || r.left + r.width > frame.width || r.top + r.height > frame.height ||
      frame.rgba.size() != regionPixels * 4 || backdrop_.size() != pixels * 3)
    throw Error("FaceRenderer::finish: the frame is not one of this renderer's (" + std::to_string(frame.width) +
                "x" + std::to_string(frame.height) + ")");
  const bool fxaa = samples_ == 1 && options_.fxaa;
  if (fxaa) frame.fxaa.luma.resize(regionPixels);
  const std::size_t w = static_cast<std::size_t>(r.width);
  const int bottomRow = frame.height - r.top - r.height;  // the region's first row in GL's order
  for (int y = 0; y < r.height; ++y) {
    std::uint8_t* row = frame.rgba.data() + static_cast<std::size_t>(y) * w * 4;
    const std::uint8_t* under =
        backdrop_.data() + (static_cast<std::size_t>(bottomRow + y) * static_cast<std::size_t>(frame.width) +
                            static_cast<std::size_t>(r.left)) * 3;
    compositeUnder(row, under, w);
    if (fxaa) fxaaLuma(row, w, frame.fxaa.luma.data() + static_cast<std::size_t>(y) * w);
  }
  if (fxaa) fxaaWithLuma(frame.rgba.data(), r.width, r.height, frame.fxaa);
}

void FaceRenderer::finish(RawFrame& frame, Image& image) const {
  prepare(frame);
  if (image.width != frame.width || image.height != frame.height) image.resize(frame.width, frame.height);
  // Rows top-down (GL's run bottom-up): the backdrop, with the region's pixels in their place.
  const PixelRegion& r = frame.region;
  const std::size_t rowBytes = static_cast<std::size_t>(frame.width) * 3;
  for (int y = 0; y < frame.height; ++y) {
    std::uint8_t* out = image.pixel(0, y);
    std::copy_n(backdrop_.data() + static_cast<std::size_t>(frame.height - 1 - y) * rowBytes, rowBytes, out);
    if (y < r.top || y >= r.top + r.height) continue;
    const std::uint8_t* in =
        frame.rgba.data() + static_cast<std::size_t>(r.top + r.height - 1 - y) * static_cast<std::size_t>(r.width) * 4;
    out += static_cast<std::size_t>(r.left) * 3;
    for (int x = 0; x < r.width; ++x, in += 4, out += 3) {
      out[0] = in[0];
      out[1] = in[1];
      out[2] = in[2];
    }
  }
}

void FaceRenderer::finish(RawFrame& frame, Yuv420Image& image, bool bt709) const {
  prepare(frame);
  image = backdropYuv_[bt709 ? 1 : 0];  // the same size every frame: a copy into the planes already there
  rgbaToYuv420(frame.rgba.data(), frame.region.width, frame.region.height, bt709, image, frame.region.left,
               frame.region.top);
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
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->resolveFramebuffer);
  glViewport(0, 0, options_.width, options_.height);
  drawBackdrop(Backdrop::kUnder);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->resolveFramebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  const bool same = framebufferSize.first - left == options_.width && framebufferSize.second == options_.height;
  glBlitFramebuffer(0, 0, options_.width, options_.height, left, 0, framebufferSize.first,
                    framebufferSize.second, GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace th::render
