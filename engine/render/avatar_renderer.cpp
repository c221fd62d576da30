#include "render/avatar_renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>

#include "core/error.h"
#include "render/avatar_draw.h"
#include "render/culling.h"
#include "render/frame_targets.h"
#include "render/gl_program.h"
#include "render/materials.h"
#include "render/shader_sources.h"

namespace th::render {

namespace {

using namespace avatar_draw;  // the draw lists and shader variants (avatar_draw.h)

// A texture with its mipmaps (0: an empty image, drawn untextured).
GLuint uploadAvatarTexture(const avatar::Texture& texture) {
  GLuint id = 0;
  if (texture.width > 0 && texture.height > 0) {
    glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // glTF's images run from the top row with v = 0 there: uploaded as they are, v samples them the same way.
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, texture.width, texture.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 texture.rgba.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    // Trilinear: bilinear filtering in the nearest mipmap level saved the VRoid character a tenth of its frame,
    // but its level switches along a surface where the derivatives cross a power of two, and the same frame
    // drawn at another offset (the live window's, beside the panel) changed by up to 7 levels there.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    const GLint wrap = texture.repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  }
  return id;
}

// Primitive p of mesh m: its buffers (positions and normals rewritten each frame, UVs and indices once) and its
// culling clusters, whose bounds are measured when the meshes are set.
PrimitiveBuffers primitiveBuffersOf(const avatar::Avatar& avatar, std::size_t m, std::size_t p) {
  const avatar::Primitive& primitive = avatar.meshes[m].primitives[p];
  PrimitiveBuffers b;
  b.mesh = static_cast<int>(m);
  b.primitive = static_cast<int>(p);
  b.material = primitive.material;
  b.indices = static_cast<GLsizei>(primitive.indices.size());
  b.blended = primitive.material >= 0 && primitive.material < static_cast<int>(avatar.materials.size()) &&
              avatar.materials[static_cast<std::size_t>(primitive.material)].alpha == avatar::AlphaMode::kBlend;
  const auto indices = static_cast<std::uint32_t>(primitive.indices.size() / 3 * 3);
  for (std::uint32_t first = 0; first < indices; first += 3 * kClusterTriangles)
    b.clusters.push_back({.first = first,
                          .count = std::min(3 * kClusterTriangles, indices - first),
                          .bounds = Eigen::AlignedBox3f(),
                          .moves = true});
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
  return b;
}

}  // namespace

struct AvatarRenderer::Gl {
  std::array<AvatarProgram, kNumVariants> programs{};  // those the materials use (id 0: not linked)
  GLuint backgroundProgram = 0;
  GLint top = -1, bottom = -1, aspect = -1;
  GLuint emptyVao = 0;
  std::vector<PrimitiveBuffers> primitives;
  DrawOrder order;
  std::vector<GLuint> textures;
  FrameTargets targets;
  bool resolved = true;
  // The opaque clusters that never move, drawn once for a camera and copied under each frame (render() with
  // one sample): a character framed on its head shows its still shoulders and arms in every frame.
  FrameTargets still;
  bool stillValid = false;
  Eigen::Matrix4f stillViewProjection = Eigen::Matrix4f::Zero();
  Eigen::Vector3f stillEye = Eigen::Vector3f::Zero();
  PixelRegion stillRegion;

  void releaseTargets() {
    targets.release();
    still.release();
    stillValid = false;
  }
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
    for (AvatarProgram& program : programs) {
      glDeleteProgram(program.id);
      program.id = 0;
    }
    glDeleteProgram(backgroundProgram);
    emptyVao = backgroundProgram = 0;
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
    g.backgroundProgram = linkProgram(shaders::kBackground_vert, shaders::kBackground_frag, "background");
    g.top = glGetUniformLocation(g.backgroundProgram, "uTop");
    g.bottom = glGetUniformLocation(g.backgroundProgram, "uBottom");
    g.aspect = glGetUniformLocation(g.backgroundProgram, "uAspect");
    glGenVertexArrays(1, &g.emptyVao);

    for (const avatar::Texture& texture : avatar.textures) g.textures.push_back(uploadAvatarTexture(texture));
    for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
      for (std::size_t p = 0; p < avatar.meshes[m].primitives.size(); ++p) {
        g.primitives.push_back(primitiveBuffersOf(avatar, m, p));
      }
    }
    for (PrimitiveBuffers& b : g.primitives) {
      const avatar::Material& material = materialOf(avatar, b.material);
      const int texture = material.baseColourTexture;
      b.texture = texture >= 0 && texture < static_cast<int>(g.textures.size())
                      ? g.textures[static_cast<std::size_t>(texture)]
                      : 0;
      b.variant = variantOf(material, b.texture != 0);
      for (const int variant : {b.variant, b.variant + kDepthOnly}) {
        if (variant >= kDepthOnly && material.alpha != avatar::AlphaMode::kOpaque) continue;  // no depth pass
        if (g.programs[static_cast<std::size_t>(variant)].id == 0)
          linkVariant(variant, g.programs[static_cast<std::size_t>(variant)]);
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
  if (samples_ == 1 && options_.cull) g.still.create(w, h, 1, "AvatarRenderer");
  g.stillValid = false;
  g.resolved = true;
  drawn_ = {0, 0, w, h};  // nothing read yet: a new target holds anything
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

void AvatarRenderer::setMovingVertices(const avatar::MovingVertices& moving) {
  gl_->stillValid = false;
  std::vector<bool> moves;
  for (PrimitiveBuffers& b : gl_->primitives) {
    const avatar::Primitive& primitive =
        avatar_.meshes[static_cast<std::size_t>(b.mesh)].primitives[static_cast<std::size_t>(b.primitive)];
    moves.assign(static_cast<std::size_t>(primitive.positions.cols()), false);
    for (const std::uint32_t v :
         moving.vertices[static_cast<std::size_t>(b.mesh)][static_cast<std::size_t>(b.primitive)])
      moves[v] = true;
    for (Cluster& cluster : b.clusters) {
      cluster.moves = false;
      for (std::uint32_t i = cluster.first; i < cluster.first + cluster.count && !cluster.moves; ++i)
        cluster.moves = moves[primitive.indices[i]];
    }
  }
}

void AvatarRenderer::setMeshes(const std::vector<avatar::DeformedMesh>& meshes, const avatar::MovingVertices* moving) {
  if (meshes.size() != avatar_.meshes.size())
    throw Error("AvatarRenderer: " + std::to_string(meshes.size()) + " meshes for a character of " +
                std::to_string(avatar_.meshes.size()));
  context_.makeCurrent();
  for (PrimitiveBuffers& b : gl_->primitives) {
    const avatar::DeformedMesh& mesh = meshes[static_cast<std::size_t>(b.mesh)];
    const Eigen::Matrix3Xf& positions = mesh.positions[static_cast<std::size_t>(b.primitive)];
    const Eigen::Matrix3Xf& normals = mesh.normals[static_cast<std::size_t>(b.primitive)];
    const std::vector<std::uint32_t>& indices =
        avatar_.meshes[static_cast<std::size_t>(b.mesh)].primitives[static_cast<std::size_t>(b.primitive)].indices;
    const auto vertices = static_cast<std::uint32_t>(positions.cols());
    // The vertices to upload: all of them, or the moving ones in runs (gaps of a few vertices uploaded too,
    // fewer calls).
    const std::vector<std::uint32_t>* list =
        moving != nullptr ? &moving->vertices[static_cast<std::size_t>(b.mesh)][static_cast<std::size_t>(b.primitive)]
                          : nullptr;
    if (list != nullptr && list->empty()) continue;
    if (list == nullptr) gl_->stillValid = false;
    glBindBuffer(GL_ARRAY_BUFFER, b.dynamicBuffer);
    const auto upload = [&](std::uint32_t from, std::uint32_t to) {  // vertices [from, to)
      upload_.resize(static_cast<std::size_t>(to - from) * 6);
      float* out = upload_.data();
      for (std::uint32_t v = from; v < to; ++v, out += 6) {
        for (int k = 0; k < 3; ++k) {
          out[k] = positions(k, v);
          out[3 + k] = normals(k, v);
        }
      }
      glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(from * 6 * sizeof(float)),
                      static_cast<GLsizeiptr>(upload_.size() * sizeof(float)), upload_.data());
    };
    if (list == nullptr) {
      upload(0, vertices);
    } else {
      constexpr std::uint32_t kGap = 32;
      std::size_t k = 0;
      while (k < list->size()) {
        const std::uint32_t from = (*list)[k];
        std::uint32_t to = from + 1;
        while (++k < list->size() && (*list)[k] <= to + kGap) to = (*list)[k] + 1;
        upload(from, to);
      }
    }
    for (Cluster& cluster : b.clusters)
      if (list == nullptr || cluster.moves) measure(cluster, indices, positions);
    if (b.blended) b.centre = vertices > 0 ? Eigen::Vector3f(positions.rowwise().mean()) : Eigen::Vector3f::Zero();
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void AvatarRenderer::selectVisible(const Eigen::Matrix4f& viewProjection, const Eigen::Vector3f& eye, Layer layer) {
  const std::array<Eigen::Vector4f, 6> planes = frustumPlanes(viewProjection);
  float lowX = 1e30f, highX = -1e30f, lowY = 1e30f, highY = -1e30f;
  bool behind = false;  // a box reaches behind the camera: its projection says nothing
  trianglesDrawn_ = 0;
  DrawOrder& order = gl_->order;
  order.clear();
  for (const PrimitiveBuffers& b : gl_->primitives) {
    for (const Cluster& cluster : b.clusters) {
      const bool still = !b.blended && !cluster.moves;
      if ((layer == Layer::kStill && !still) || (layer == Layer::kMoving && still)) continue;
      if (options_.cull && !meetsFrustum(cluster.bounds, planes)) continue;
      if (b.blended || !options_.cull)
        order.add(&b, cluster);
      else
        order.opaque.emplace_back((cluster.bounds.center() - eye).squaredNorm(), &b, &cluster);
      trianglesDrawn_ += static_cast<int>(cluster.count / 3);
      for (int corner = 0; corner < 8 && !behind; ++corner) {
        const Eigen::Vector3f p = cluster.bounds.corner(static_cast<Eigen::AlignedBox3f::CornerType>(corner));
        const Eigen::Vector4f clip = viewProjection * p.homogeneous();
        if (clip.w() <= 1e-6f) {
          behind = true;
          break;
        }
        lowX = std::min(lowX, clip.x() / clip.w());
        highX = std::max(highX, clip.x() / clip.w());
        lowY = std::min(lowY, clip.y() / clip.w());
        highY = std::max(highY, clip.y() / clip.w());
      }
    }
  }
  // The batches added above (one a primitive: the blended ones; without culling the opaque ones too, first, in
  // the file's order), the blended from the farthest; then the opaque clusters from the nearest, moved before
  // the blended.
  std::stable_sort(order.batches.begin(), order.batches.end(), [&](const Batch& x, const Batch& y) {
    if (x.primitive->blended != y.primitive->blended) return !x.primitive->blended;
    if (!x.primitive->blended) return false;
    return (x.primitive->centre - eye).squaredNorm() > (y.primitive->centre - eye).squaredNorm();
  });
  const std::size_t blendedBatches = order.batches.size();
  std::sort(order.opaque.begin(), order.opaque.end(), [](const auto& x, const auto& y) {
    return std::get<0>(x) < std::get<0>(y) ||
           (std::get<0>(x) == std::get<0>(y) && std::get<2>(x)->first < std::get<2>(y)->first);
  });
  for (const auto& [distance, primitive, cluster] : order.opaque) order.add(primitive, *cluster);
  std::rotate(order.batches.begin(), order.batches.begin() + static_cast<std::ptrdiff_t>(blendedBatches),
              order.batches.end());
  const PixelRegion whole{0, 0, options_.width, options_.height};
  drawn_ = behind || !options_.cull ? whole : pixelRegion(lowX, lowY, highX, highY, options_.width, options_.height);
}

void AvatarRenderer::render(const OrbitCamera& camera) {
  context_.makeCurrent();
  Gl& g = *gl_;
  const bool layered = samples_ == 1 && options_.cull;
  if (layered) drawStillLayer(camera);  // (leaves the target bound, holding the still layer)
  if (!layered) {
    glBindFramebuffer(GL_FRAMEBUFFER, samples_ > 1 ? g.targets.msaaFramebuffer : g.targets.resolveFramebuffer);
    glViewport(0, 0, options_.width, options_.height);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  drawCharacter(camera, false, layered ? Layer::kMoving : Layer::kAll);
  if (layered) drawn_ = unite(drawn_, g.stillRegion);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  g.resolved = samples_ == 1;
}

void AvatarRenderer::drawStillLayer(const OrbitCamera& camera) {
  Gl& g = *gl_;
  const float aspect = static_cast<float>(options_.width) / static_cast<float>(options_.height);
  const Eigen::Matrix4f viewProjection = camera.projection(aspect) * camera.view();
  if (!g.stillValid || viewProjection != g.stillViewProjection || camera.eye() != g.stillEye) {
    glBindFramebuffer(GL_FRAMEBUFFER, g.still.resolveFramebuffer);
    glViewport(0, 0, options_.width, options_.height);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    drawCharacter(camera, false, Layer::kStill);
    g.stillRegion = drawn_;
    g.stillViewProjection = viewProjection;
    g.stillEye = camera.eye();
    g.stillValid = true;
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, g.still.resolveFramebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, g.targets.resolveFramebuffer);
  glBlitFramebuffer(0, 0, options_.width, options_.height, 0, 0, options_.width, options_.height,
                    GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_FRAMEBUFFER, g.targets.resolveFramebuffer);
  glViewport(0, 0, options_.width, options_.height);
}

void AvatarRenderer::renderToWindow(const OrbitCamera& camera, int left) {
  context_.makeCurrent();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  // The viewport clips the backdrop's screen-covering triangle and the character alike: nothing is drawn
  // beside it. The backdrop goes after the opaque surfaces, only where they left the far plane, and before the
  // blended ones: premultiplied "over" onto it gives what render() then the backdrop under gives.
  glViewport(left, 0, options_.width, options_.height);
  glDepthMask(GL_TRUE);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  drawCharacter(camera, true);
}

// The gradient where the depth buffer still holds the far plane: neither the colour nor the depth of what is
// drawn is touched, and llvmpipe skips shading the blocks it covers.
void AvatarRenderer::drawBackdropBehind() {
  Gl& g = *gl_;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glUseProgram(g.backgroundProgram);
  setVector(g.top, options_.backgroundTop);
  setVector(g.bottom, options_.backgroundBottom);
  glUniform1f(g.aspect, static_cast<float>(options_.width) / static_cast<float>(options_.height));
  glBindVertexArray(g.emptyVao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDepthFunc(GL_LESS);
}

// The camera and the lights, the same for every batch, set in every program once a frame (the lights turned into
// the world's frame: they are given relative to the camera).
void AvatarRenderer::setSceneUniforms(const Eigen::Matrix4f& view, const Eigen::Matrix4f& viewProjection,
                                      const Eigen::Vector3f& eye) {
  Gl& g = *gl_;
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
  for (const AvatarProgram& program : g.programs) {
    if (program.id == 0) continue;
    glUseProgram(program.id);
    glUniformMatrix4fv(program.viewProjection, 1, GL_FALSE, viewProjection.data());
    setVector(program.cameraPosition, eye);
    glUniform3fv(program.lightDirection, 3, directions);
    glUniform3fv(program.lightColour, 3, colours);
    setVector(program.skyAmbient, light.skyAmbient);
    setVector(program.groundAmbient, light.groundAmbient);
    glUniform1f(program.exposure, light.exposure);
    glUniform1i(program.baseTexture, 0);
  }
}

void AvatarRenderer::drawCharacter(const OrbitCamera& camera, bool withBackdrop, Layer layer) {
  Gl& g = *gl_;
  const float aspect = static_cast<float>(options_.width) / static_cast<float>(options_.height);
  const Eigen::Matrix4f view = camera.view();
  const Eigen::Matrix4f viewProjection = camera.projection(aspect) * view;
  const Eigen::Vector3f eye = camera.eye();
  selectVisible(viewProjection, eye, layer);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  setSceneUniforms(view, viewProjection, eye);
  glActiveTexture(GL_TEXTURE0);

  // One batch (selectVisible's order), with the state changed only where it differs from the last one's.
  enum class Pass { kDepth, kShade };
  const PrimitiveBuffers* last = nullptr;
  Pass lastPass = Pass::kShade;
  const auto draw = [&](const Batch& batch, Pass pass) {
    const PrimitiveBuffers* b = batch.primitive;
    const avatar::Material& material = materialOf(avatar_, b->material);
    const bool fresh = last == nullptr || lastPass != pass;
    if (fresh || materialOf(avatar_, last->material).doubleSided != material.doubleSided) {
      if (material.doubleSided)
        glDisable(GL_CULL_FACE);
      else {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
      }
    }
    const int variant = b->variant + (pass == Pass::kDepth ? kDepthOnly : 0);
    const AvatarProgram& program = g.programs[static_cast<std::size_t>(variant)];
    const bool sameProgram = !fresh && last->variant == b->variant;
    if (!sameProgram) glUseProgram(program.id);
    if (!sameProgram || last->material != b->material) {
      glUniform4fv(program.baseColour, 1, material.baseColour.data());
      setVector(program.emissive, material.emissive);
      glUniform1f(program.metallic, material.metallic);
      glUniform1f(program.roughness, material.roughness);
      glUniform1f(program.alphaCutoff, material.alphaCutoff);
    }
    if (fresh || last->texture != b->texture) glBindTexture(GL_TEXTURE_2D, b->texture);
    if (fresh || last != b) glBindVertexArray(b->vao);
    last = b;
    lastPass = pass;
    glMultiDrawElements(GL_TRIANGLES, g.order.counts.data() + batch.firstRun, GL_UNSIGNED_INT,
                        g.order.offsets.data() + batch.firstRun, static_cast<GLsizei>(batch.runs));
  };
  const auto opaqueEnd = std::find_if(g.order.batches.begin(), g.order.batches.end(),
                                      [](const Batch& batch) { return batch.primitive->blended; });
  const auto isMasked = [&](const Batch& batch) {
    return materialOf(avatar_, batch.primitive->material).alpha == avatar::AlphaMode::kMask;
  };
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  if (options_.cull) {
    // The opaque surfaces' depth first (no colour, no shading), then their colour where their depth is the one
    // kept: each pixel is shaded once, whatever lies behind it. The same vertex shader in both passes gives the
    // same depths (it declares gl_Position invariant). Then the alpha-tested ones, in one pass (a depth pass
    // would sample their textures twice).
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    for (auto batch = g.order.batches.begin(); batch != opaqueEnd; ++batch)
      if (!isMasked(*batch)) draw(*batch, Pass::kDepth);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_EQUAL);
    glDepthMask(GL_FALSE);
    for (auto batch = g.order.batches.begin(); batch != opaqueEnd; ++batch)
      if (!isMasked(*batch)) draw(*batch, Pass::kShade);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    for (auto batch = g.order.batches.begin(); batch != opaqueEnd; ++batch)
      if (isMasked(*batch)) draw(*batch, Pass::kShade);
  } else {
    for (auto batch = g.order.batches.begin(); batch != opaqueEnd; ++batch) draw(*batch, Pass::kShade);
  }
  // The backdrop where nothing opaque is (its depth still the far plane's), then the blended surfaces.
  if (withBackdrop) drawBackdropBehind();
  last = nullptr;
  glDepthFunc(GL_LESS);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied
  glDepthMask(GL_FALSE);
  for (auto batch = opaqueEnd; batch != g.order.batches.end(); ++batch) draw(*batch, Pass::kShade);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
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
  gl_->targets.read(options_.width, options_.height, drawn_, frame);
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

}  // namespace th::render
