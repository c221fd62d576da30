#include "render/avatar_renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "render/frame_targets.h"
#include "render/gl_program.h"
#include "render/materials.h"
#include "render/shader_sources.h"

namespace th::render {

namespace {

struct PrimitiveBuffers {
  GLuint vao = 0;
  GLuint dynamicBuffer = 0;  // positions and normals, 6 floats a vertex, per frame
  GLuint uvBuffer = 0;
  GLuint indexBuffer = 0;
  GLsizei indices = 0;
  int material = -1;
  int mesh = 0;
  int primitive = 0;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  // of the last positions, for sorting the blended ones
};

std::string withLighting(const char* stage) {
  return std::string("#version 330 core\n") + shaders::kLighting_glsl + "#line 2\n" + stage;
}

}  // namespace

struct AvatarRenderer::Gl {
  GLuint program = 0;
  GLint viewProjection = -1, cameraPosition = -1, lightDirection = -1, lightColour = -1, skyAmbient = -1,
        groundAmbient = -1, exposure = -1, baseColour = -1, baseTexture = -1, hasTexture = -1, emissive = -1,
        metallic = -1, roughness = -1, unlit = -1, alphaMode = -1, alphaCutoff = -1;
  GLuint backgroundProgram = 0;
  GLint top = -1, bottom = -1, aspect = -1;
  GLuint emptyVao = 0;
  std::vector<PrimitiveBuffers> primitives;
  std::vector<GLuint> textures;
  FrameTargets targets;
  bool resolved = true;

  void releaseTargets() { targets.release(); }
  void releaseAll() {
    releaseTargets();
    for (PrimitiveBuffers& p : primitives) {
      glDeleteVertexArrays(1, &p.vao);
      const GLuint buffers[] = {p.dynamicBuffer, p.uvBuffer, p.indexBuffer};
      glDeleteBuffers(3, buffers);
    }
    primitives.clear();
    if (!textures.empty()) glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
    textures.clear();
    glDeleteVertexArrays(1, &emptyVao);
    glDeleteProgram(program);
    glDeleteProgram(backgroundProgram);
    emptyVao = program = backgroundProgram = 0;
  }
};

AvatarRenderer::AvatarRenderer(GlContext& context, const avatar::Avatar& avatar, AvatarRenderOptions options)
    : context_(context), avatar_(avatar), options_(std::move(options)), gl_(std::make_unique<Gl>()) {
  if (options_.width <= 0 || options_.height <= 0)
    throw Error("AvatarRenderer: the image size must be positive, not " + std::to_string(options_.width) + "x" +
                std::to_string(options_.height));
  context_.makeCurrent();
  Gl& g = *gl_;
  try {
    const std::string vertex = withLighting(shaders::kAvatar_vert), fragment = withLighting(shaders::kAvatar_frag);
    g.program = linkProgram(vertex.c_str(), fragment.c_str(), "avatar");
    const auto at = [&](const char* name) { return glGetUniformLocation(g.program, name); };
    g.viewProjection = at("uViewProjection");
    g.cameraPosition = at("uCameraPosition");
    g.lightDirection = at("uLightDirection");
    g.lightColour = at("uLightColour");
    g.skyAmbient = at("uSkyAmbient");
    g.groundAmbient = at("uGroundAmbient");
    g.exposure = at("uExposure");
    g.baseColour = at("uBaseColour");
    g.baseTexture = at("uBaseTexture");
    g.hasTexture = at("uHasTexture");
    g.emissive = at("uEmissive");
    g.metallic = at("uMetallic");
    g.roughness = at("uRoughness");
    g.unlit = at("uUnlit");
    g.alphaMode = at("uAlphaMode");
    g.alphaCutoff = at("uAlphaCutoff");
    g.backgroundProgram = linkProgram(shaders::kBackground_vert, shaders::kBackground_frag, "background");
    g.top = glGetUniformLocation(g.backgroundProgram, "uTop");
    g.bottom = glGetUniformLocation(g.backgroundProgram, "uBottom");
    g.aspect = glGetUniformLocation(g.backgroundProgram, "uAspect");
    glGenVertexArrays(1, &g.emptyVao);

    for (const avatar::Texture& texture : avatar.textures) {
      GLuint id = 0;
      if (texture.width > 0 && texture.height > 0) {
        glGenTextures(1, &id);
        glBindTexture(GL_TEXTURE_2D, id);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        // glTF's images run from the top row with v = 0 there: uploaded as they are, v samples them the same way.
        glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, texture.width, texture.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     texture.rgba.data());
        glGenerateMipmap(GL_TEXTURE_2D);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        const GLint wrap = texture.repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
      }
      g.textures.push_back(id);
    }
    for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
      for (std::size_t p = 0; p < avatar.meshes[m].primitives.size(); ++p) {
        const avatar::Primitive& primitive = avatar.meshes[m].primitives[p];
        PrimitiveBuffers b;
        b.mesh = static_cast<int>(m);
        b.primitive = static_cast<int>(p);
        b.material = primitive.material;
        b.indices = static_cast<GLsizei>(primitive.indices.size());
        glGenVertexArrays(1, &b.vao);
        glBindVertexArray(b.vao);
        glGenBuffers(1, &b.dynamicBuffer);
        glBindBuffer(GL_ARRAY_BUFFER, b.dynamicBuffer);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(primitive.positions.cols() * 6 * sizeof(float)), nullptr,
                     GL_DYNAMIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
        glGenBuffers(1, &b.uvBuffer);
        glBindBuffer(GL_ARRAY_BUFFER, b.uvBuffer);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(primitive.uv.size() * sizeof(float)), primitive.uv.data(),
                     GL_STATIC_DRAW);
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);
        glGenBuffers(1, &b.indexBuffer);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.indexBuffer);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(primitive.indices.size() * sizeof(std::uint32_t)),
                     primitive.indices.data(), GL_STATIC_DRAW);
        glBindVertexArray(0);
        g.primitives.push_back(b);
      }
    }
    createTargets();
    std::vector<avatar::DeformedMesh> rest;
    avatar::deformAvatar(avatar, avatar::restPose(avatar), rest);
    setMeshes(rest);
  } catch (...) {
    g.releaseAll();
    throw;
  }
}

AvatarRenderer::~AvatarRenderer() {
  context_.makeCurrent();
  gl_->releaseAll();
}

void AvatarRenderer::createTargets() {
  Gl& g = *gl_;
  const GLsizei w = options_.width, h = options_.height;
  samples_ = g.targets.create(w, h, options_.samples, "AvatarRenderer");
  g.resolved = true;
  backdrop_ = makeBackdrop(w, h, options_.backgroundTop, options_.backgroundBottom);
}

void AvatarRenderer::resize(int width, int height) {
  if (width <= 0 || height <= 0)
    throw Error("AvatarRenderer: the image size must be positive, not " + std::to_string(width) + "x" +
                std::to_string(height));
  if (width == options_.width && height == options_.height) return;
  context_.makeCurrent();
  gl_->releaseTargets();
  options_.width = width;
  options_.height = height;
  createTargets();
}

void AvatarRenderer::setMeshes(const std::vector<avatar::DeformedMesh>& meshes, const avatar::MovingVertices* moving) {
  if (meshes.size() != avatar_.meshes.size())
    throw Error("AvatarRenderer: " + std::to_string(meshes.size()) + " meshes for a character of " +
                std::to_string(avatar_.meshes.size()));
  context_.makeCurrent();
  for (PrimitiveBuffers& b : gl_->primitives) {
    if (moving != nullptr &&
        moving->vertices[static_cast<std::size_t>(b.mesh)][static_cast<std::size_t>(b.primitive)].empty())
      continue;
    const avatar::DeformedMesh& mesh = meshes[static_cast<std::size_t>(b.mesh)];
    const Eigen::Matrix3Xf& positions = mesh.positions[static_cast<std::size_t>(b.primitive)];
    const Eigen::Matrix3Xf& normals = mesh.normals[static_cast<std::size_t>(b.primitive)];
    const Eigen::Index vertices = positions.cols();
    upload_.resize(static_cast<std::size_t>(vertices) * 6);
    for (Eigen::Index v = 0; v < vertices; ++v) {
      float* out = upload_.data() + static_cast<std::size_t>(v) * 6;
      for (int k = 0; k < 3; ++k) {
        out[k] = positions(k, v);
        out[3 + k] = normals(k, v);
      }
    }
    b.centre = vertices > 0 ? Eigen::Vector3f(positions.rowwise().mean()) : Eigen::Vector3f::Zero();
    glBindBuffer(GL_ARRAY_BUFFER, b.dynamicBuffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(upload_.size() * sizeof(float)), upload_.data());
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void AvatarRenderer::render(const OrbitCamera& camera) {
  context_.makeCurrent();
  Gl& g = *gl_;
  const float aspect = static_cast<float>(options_.width) / static_cast<float>(options_.height);
  const Eigen::Matrix4f view = camera.view();
  const Eigen::Matrix4f viewProjection = camera.projection(aspect) * view;
  const Eigen::Vector3f eye = camera.eye();
  glBindFramebuffer(GL_FRAMEBUFFER, samples_ > 1 ? g.targets.msaaFramebuffer : g.targets.resolveFramebuffer);
  glViewport(0, 0, options_.width, options_.height);
  glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(g.program);
  glUniformMatrix4fv(g.viewProjection, 1, GL_FALSE, viewProjection.data());
  setVector(g.cameraPosition, eye);
  const Lighting& light = options_.lighting;
  const Eigen::Matrix3f toWorld = view.topLeftCorner<3, 3>().transpose();
  const Light* lights[3] = {&light.key, &light.fill, &light.rim};
  float directions[9], colours[9];
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3f d = (toWorld * lights[i]->direction.normalized()).normalized();
    for (int k = 0; k < 3; ++k) {
      directions[3 * i + k] = d[k];
      colours[3 * i + k] = lights[i]->colour[k];
    }
  }
  glUniform3fv(g.lightDirection, 3, directions);
  glUniform3fv(g.lightColour, 3, colours);
  setVector(g.skyAmbient, light.skyAmbient);
  setVector(g.groundAmbient, light.groundAmbient);
  glUniform1f(g.exposure, light.exposure);
  glUniform1i(g.baseTexture, 0);
  glActiveTexture(GL_TEXTURE0);

  // Opaque and alpha-tested surfaces, then the blended ones from the farthest to the nearest.
  std::vector<const PrimitiveBuffers*> order;
  order.reserve(g.primitives.size());
  for (const PrimitiveBuffers& b : g.primitives) order.push_back(&b);
  const auto blended = [&](const PrimitiveBuffers* b) {
    return b->material >= 0 && b->material < static_cast<int>(avatar_.materials.size()) &&
           avatar_.materials[static_cast<std::size_t>(b->material)].alpha == avatar::AlphaMode::kBlend;
  };
  std::stable_sort(order.begin(), order.end(), [&](const PrimitiveBuffers* a, const PrimitiveBuffers* b) {
    if (blended(a) != blended(b)) return !blended(a);
    if (!blended(a)) return false;
    return (a->centre - eye).squaredNorm() > (b->centre - eye).squaredNorm();
  });
  const avatar::Material plain;
  for (const PrimitiveBuffers* b : order) {
    const avatar::Material& material = b->material >= 0 && b->material < static_cast<int>(avatar_.materials.size())
                                           ? avatar_.materials[static_cast<std::size_t>(b->material)]
                                           : plain;
    const bool blend = material.alpha == avatar::AlphaMode::kBlend;
    if (blend) {
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied
      glDepthMask(GL_FALSE);
    } else {
      glDisable(GL_BLEND);
      glDepthMask(GL_TRUE);
    }
    if (material.doubleSided)
      glDisable(GL_CULL_FACE);
    else {
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
    }
    glUniform4fv(g.baseColour, 1, material.baseColour.data());
    const int texture = material.baseColourTexture;
    const bool textured = texture >= 0 && texture < static_cast<int>(g.textures.size()) &&
                          g.textures[static_cast<std::size_t>(texture)] != 0;
    glUniform1i(g.hasTexture, textured ? 1 : 0);
    glBindTexture(GL_TEXTURE_2D, textured ? g.textures[static_cast<std::size_t>(texture)] : 0);
    setVector(g.emissive, material.emissive);
    glUniform1f(g.metallic, material.metallic);
    glUniform1f(g.roughness, material.roughness);
    glUniform1i(g.unlit, material.unlit ? 1 : 0);
    glUniform1i(g.alphaMode, material.alpha == avatar::AlphaMode::kOpaque ? 0
                             : material.alpha == avatar::AlphaMode::kMask ? 1
                                                                          : 2);
    glUniform1f(g.alphaCutoff, material.alphaCutoff);
    glBindVertexArray(b->vao);
    glDrawElements(GL_TRIANGLES, b->indices, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  g.resolved = samples_ == 1;
}

void AvatarRenderer::resolve() {
  Gl& g = *gl_;
  if (g.resolved) return;
  g.targets.resolve(options_.width, options_.height);
  g.resolved = true;
}

void AvatarRenderer::readRaw(RawFrame& frame) {
  context_.makeCurrent();
  resolve();
  frame.width = options_.width;
  frame.height = options_.height;
  frame.region = {0, 0, options_.width, options_.height};
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl_->targets.resolveFramebuffer);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  frame.rgba.resize(static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height) * 4);
  glReadPixels(0, 0, frame.width, frame.height, GL_RGBA, GL_UNSIGNED_BYTE, frame.rgba.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void AvatarRenderer::finish(RawFrame& frame, Image& image) const {
  finishFrame(frame, backdrop_, samples_ == 1 && options_.fxaa, image, "AvatarRenderer");
}

void AvatarRenderer::finish(RawFrame& frame, Yuv420Image& image, bool bt709) const {
  finishFrame(frame, backdrop_, samples_ == 1 && options_.fxaa, image, bt709, "AvatarRenderer");
}

void AvatarRenderer::readPixels(Image& image) {
  readRaw(raw_);
  finish(raw_, image);
}

void AvatarRenderer::present(std::pair<int, int> framebufferSize, int left) {
  context_.makeCurrent();
  resolve();
  Gl& g = *gl_;
  // The backdrop under the character with GL's "under" blending, then the frame to the window.
  glBindFramebuffer(GL_FRAMEBUFFER, g.targets.resolveFramebuffer);
  glViewport(0, 0, options_.width, options_.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
  glUseProgram(g.backgroundProgram);
  setVector(g.top, options_.backgroundTop);
  setVector(g.bottom, options_.backgroundBottom);
  glUniform1f(g.aspect, static_cast<float>(options_.width) / static_cast<float>(options_.height));
  glBindVertexArray(g.emptyVao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, g.targets.resolveFramebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  const bool same = framebufferSize.first - left == options_.width && framebufferSize.second == options_.height;
  glBlitFramebuffer(0, 0, options_.width, options_.height, left, 0, framebufferSize.first, framebufferSize.second,
                    GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

OrbitCamera frameAvatarHead(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes,
                            double aspect) {
  // The head bone and every node under it.
  std::vector<bool> underHead(avatar.nodes.size(), false);
  const int head = avatar.bones[avatar::kHead];
  for (const int n : avatar.drawOrder) {
    const int parent = avatar.nodes[static_cast<std::size_t>(n)].parent;
    underHead[static_cast<std::size_t>(n)] = n == head || (parent >= 0 && underHead[static_cast<std::size_t>(parent)]);
  }
  // The face: the mesh with the most morph targets (hair, hats and long hair would widen the box); every mesh
  // when none has targets.
  // Of meshes with as many targets (the eyes and teeth often share the face's list), the largest.
  std::size_t face = avatar.meshes.size();
  std::pair<std::size_t, Eigen::Index> most{0, 0};
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    Eigen::Index vertices = 0;
    for (const avatar::Primitive& primitive : avatar.meshes[m].primitives) vertices += primitive.positions.cols();
    const std::pair<std::size_t, Eigen::Index> size{avatar.meshes[m].targetNames.size(), vertices};
    if (size.first > 0 && size > most) {
      most = size;
      face = m;
    }
  }
  Eigen::Vector3f low = Eigen::Vector3f::Constant(1e30f), high = -low;
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    if (face < avatar.meshes.size() && m != face) continue;
    const avatar::MeshInstance& mesh = avatar.meshes[m];
    const avatar::Skin* skin = mesh.skin >= 0 ? &avatar.skins[static_cast<std::size_t>(mesh.skin)] : nullptr;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const avatar::Primitive& primitive = mesh.primitives[p];
      const Eigen::Matrix3Xf& positions = meshes[m].positions[p];
      for (Eigen::Index v = 0; v < positions.cols(); ++v) {
        bool onHead = head < 0;  // no head bone: frame the whole character
        if (!onHead && skin != nullptr && primitive.joints.cols() == positions.cols()) {
          Eigen::Index strongest = 0;
          primitive.weights.col(v).maxCoeff(&strongest);
          const int joint = skin->joints[primitive.joints(strongest, v)];
          onHead = underHead[static_cast<std::size_t>(joint)];
        } else if (!onHead && skin == nullptr) {
          onHead = underHead[static_cast<std::size_t>(mesh.node)];
        }
        if (!onHead) continue;
        low = low.cwiseMin(positions.col(v));
        high = high.cwiseMax(positions.col(v));
      }
    }
  }
  if (!(low.array() <= high.array()).all()) {  // nothing on the head: the whole character
    for (const avatar::DeformedMesh& mesh : meshes)
      for (const Eigen::Matrix3Xf& positions : mesh.positions) {
        if (positions.cols() == 0) continue;
        low = low.cwiseMin(positions.rowwise().minCoeff());
        high = high.cwiseMax(positions.rowwise().maxCoeff());
      }
  }
  const float height = std::max(high.y() - low.y(), 1e-3f);
  const float width = std::max(high.x() - low.x(), 1e-3f);
  OrbitCamera camera;
  camera.pitchDegrees = 8.0f;
  // The head and a little of the neck below it, the face slightly above the centre.
  const float shown = 1.6f * std::max(height, width / static_cast<float>(aspect));
  camera.target = {0.5f * (low.x() + high.x()), low.y() + 0.42f * height, 0.5f * (low.z() + high.z())};
  const float halfFov = 0.5f * camera.fovYDegrees * static_cast<float>(M_PI) / 180.0f;
  camera.distance = 0.5f * shown / std::tan(halfFov);
  camera.nearPlane = 0.05f * camera.distance;
  camera.farPlane = 20.0f * camera.distance;
  if (avatar.facesMinusZ()) camera.yawDegrees = 180.0f;
  return camera;
}

AnimatedAvatar::AnimatedAvatar(const avatar::Avatar& avatar, GlContext& context, const AvatarRenderOptions& options)
    : avatar_(avatar),
      rig_(avatar::rigAvatar(avatar)),
      moving_(avatar::movingVertices(avatar, rig_)),
      renderer_(context, avatar, options),
      pose_(avatar::restPose(avatar)) {
  avatar::deformAvatar(avatar_, pose_, meshes_);
  camera_ = frameAvatarHead(avatar_, meshes_, static_cast<double>(options.width) / options.height);
}

void AnimatedAvatar::pose(const face::FapFrame& faps, const float* classProbabilities) {
  pose(avatar::avatarInputOf(faps, classProbabilities));
}

const Image& AnimatedAvatar::draw(const face::FapTrack& animation, double seconds) {
  pose(avatar::avatarInputAt(animation, seconds));
  render();
  renderer_.readPixels(image_);
  return image_;
}

void AnimatedAvatar::pose(const avatar::AvatarInput& input) {
  avatar::poseAvatar(avatar_, rig_, input, pose_);
  avatar::deformAvatar(avatar_, pose_, meshes_, &moving_);
  renderer_.setMeshes(meshes_, &moving_);
}

const Image& AnimatedAvatar::draw(const face::FapFrame& faps, const float* classProbabilities) {
  pose(faps, classProbabilities);
  render();
  renderer_.readPixels(image_);
  return image_;
}

void AnimatedAvatar::resize(int width, int height) {
  renderer_.resize(width, height);
  std::vector<avatar::DeformedMesh> rest;
  avatar::deformAvatar(avatar_, avatar::restPose(avatar_), rest);
  camera_ = frameAvatarHead(avatar_, rest, static_cast<double>(width) / height);
}

}  // namespace th::render

namespace th::render {

Eigen::Vector3f avatarMouthCentre(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes) {
  // The mouth's opening target, as the rig would pick it: ARKit's jawOpen, the aa viseme, VRM's aa.
  std::vector<avatar::TargetBind> opening;
  for (const char* name : {"jawOpen", "viseme_aa"}) {
    for (std::size_t m = 0; m < avatar.meshes.size(); ++m)
      if (const int t = avatar.meshes[m].targetIndex(name); t >= 0)
        opening.push_back({.mesh = static_cast<int>(m), .target = t});
    // The first name with a target that moves something.
    const bool moves = std::any_of(opening.begin(), opening.end(), [&](const avatar::TargetBind& bind) {
      for (const avatar::Primitive& primitive : avatar.meshes[static_cast<std::size_t>(bind.mesh)].primitives)
        if (primitive.targetPositions[static_cast<std::size_t>(bind.target)].cwiseAbs().maxCoeff() > 0.0f) return true;
      return false;
    });
    if (moves) break;
    opening.clear();
  }
  if (opening.empty())
    if (const auto found = avatar.expressions.find("aa"); found != avatar.expressions.end()) opening = found->second;
  // The vertices it moves most (the lips and the chin), where they are drawn now.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double count = 0.0;
  for (const avatar::TargetBind& bind : opening) {
    const avatar::MeshInstance& mesh = avatar.meshes[static_cast<std::size_t>(bind.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const Eigen::Matrix3Xf& moved = mesh.primitives[p].targetPositions[static_cast<std::size_t>(bind.target)];
      float most = 0.0f;
      for (Eigen::Index v = 0; v < moved.cols(); ++v) most = std::max(most, moved.col(v).norm());
      if (most <= 0.0f) continue;
      const Eigen::Matrix3Xf& drawn = meshes[static_cast<std::size_t>(bind.mesh)].positions[p];
      for (Eigen::Index v = 0; v < moved.cols(); ++v)
        if (moved.col(v).norm() > 0.3f * most) {
          sum += drawn.col(v).cast<double>();
          count += 1.0;
        }
    }
  }
  return count > 0.0 ? Eigen::Vector3f((sum / count).cast<float>()) : Eigen::Vector3f::Constant(NAN);
}

void AnimatedAvatar::frameMouth() {
  const Eigen::Vector3f mouth = avatarMouthCentre(avatar_, meshes_);
  if (!mouth.allFinite()) return;  // no mouth target: the head stays framed
  camera_.target = mouth;
  camera_.distance *= 0.3f;
}

}  // namespace th::render
