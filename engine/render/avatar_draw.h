// Internal to the avatar renderer (render/avatar_renderer.cpp): its draw lists, the clusters of triangles it culls
// by, and its shader variants. Not an API: what AvatarRenderer draws with, kept apart so that the renderer reads
// as what it does each frame.
// Thread contract: values and pure functions, but linkVariant (GL: the renderer's context current).
#pragma once

#include <glad/gl.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "avatar/avatar_model.h"
#include "render/raw_frame.h"

namespace th::render::avatar_draw {

constexpr std::uint32_t kClusterTriangles = 128;

// A run of a primitive's triangles (in the file's order) and the box round their vertices as last posed.
struct Cluster {
  std::uint32_t first = 0;  // into the primitive's indices
  std::uint32_t count = 0;  // indices, three a triangle
  Eigen::AlignedBox3f bounds;
  bool moves = true;  // holds a vertex that setMeshes(…, moving) may move
};

struct PrimitiveBuffers {
  GLuint vao = 0;
  GLuint dynamicBuffer = 0;  // positions and normals, 6 floats a vertex, per frame
  GLuint uvBuffer = 0;
  GLuint indexBuffer = 0;
  GLsizei indices = 0;
  int material = -1;
  int mesh = 0;
  int primitive = 0;
  bool blended = false;
  GLuint texture = 0;                                // the base colour's, 0: none
  int variant = 0;                                   // of the fragment shader (variantOf)
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  // of the last positions, for sorting the blended ones
  std::vector<Cluster> clusters;
};

// Consecutive runs of one primitive's triangles, drawn with one glMultiDrawElements: DrawOrder's runs
// [firstRun, firstRun + runs).
struct Batch {
  const PrimitiveBuffers* primitive = nullptr;
  std::size_t firstRun = 0;
  std::size_t runs = 0;
};

// This frame's draws: the opaque and alpha-tested clusters in view from the nearest to the farthest (each pixel
// keeps the nearest fragment whatever the order, and llvmpipe shades nothing behind depth already drawn), then
// the blended primitives' clusters in view, each primitive in its file's order (its blending depends on it)
// and the primitives from the farthest to the nearest.
struct DrawOrder {
  std::vector<GLsizei> counts;       // per run, indices
  std::vector<const void*> offsets;  // per run, into the index buffer (GL's offset-as-pointer idiom)
  std::vector<Batch> batches;
  std::vector<std::tuple<float, const PrimitiveBuffers*, const Cluster*>> opaque;  // squared distance, ...

  void clear() {
    counts.clear();
    offsets.clear();
    batches.clear();
    opaque.clear();
  }
  // A cluster after the last one added: joins the last run, or the last batch, or starts a batch.
  void add(const PrimitiveBuffers* primitive, const Cluster& cluster) {
    const auto offset =
        reinterpret_cast<const void*>(static_cast<std::uintptr_t>(cluster.first) * sizeof(std::uint32_t));
    if (!batches.empty() && batches.back().primitive == primitive) {
      const auto end = reinterpret_cast<std::uintptr_t>(offsets.back()) + counts.back() * sizeof(std::uint32_t);
      if (end == reinterpret_cast<std::uintptr_t>(offset)) {
        counts.back() += static_cast<GLsizei>(cluster.count);
        return;
      }
      ++batches.back().runs;
    } else {
      batches.push_back({primitive, counts.size(), 1});
    }
    counts.push_back(static_cast<GLsizei>(cluster.count));
    offsets.push_back(offset);
  }
};

// The fragment shader's variants (shaders/avatar.frag): by alpha mode, roughness 1, texture and unlit shading
// (alpha mode * 8 + rough * 4 + textured * 2 + unlit); each also as a depth-only pass (kDepthOnly further on).
constexpr int kDepthOnly = 3 * 2 * 2 * 2;
constexpr int kNumVariants = 2 * kDepthOnly;

struct AvatarProgram {
  GLuint id = 0;
  GLint viewProjection = -1, cameraPosition = -1, lightDirection = -1, lightColour = -1, skyAmbient = -1,
        groundAmbient = -1, exposure = -1, baseColour = -1, baseTexture = -1, emissive = -1, metallic = -1,
        roughness = -1, alphaCutoff = -1;
};

// The six planes of a view-projection's frustum (Gribb and Hartmann, "Fast extraction of viewing frustum planes
// from the world-view-projection matrix", 2001): a point p is inside where every row r gives r · (p, 1) >= 0.
std::array<Eigen::Vector4f, 6> frustumPlanes(const Eigen::Matrix4f& viewProjection);

// Whether a box meets the frustum: for each plane its corner farthest along the plane's normal is inside
// (conservative: a box near an edge of the frustum may pass without meeting it).
bool meetsFrustum(const Eigen::AlignedBox3f& box, const std::array<Eigen::Vector4f, 6>& planes);

// The smallest region holding both (an empty one holds nothing).
PixelRegion unite(const PixelRegion& a, const PixelRegion& b);

// The box round the cluster's vertices at `positions`.
void measure(Cluster& cluster, const std::vector<std::uint32_t>& indices, const Eigen::Matrix3Xf& positions);

// A GLSL stage's source after the version line, `defines` and the shared lighting code (shaders/lighting.glsl).
std::string withLighting(const char* stage, const std::string& defines = {});

// A primitive's material; glTF's default (white, opaque, metallic 1, roughness 1) where it names none.
const avatar::Material& materialOf(const avatar::Avatar& avatar, int material);

// The fragment shader variant that draws the material (add kDepthOnly for its depth-only pass).
int variantOf(const avatar::Material& material, bool textured);

// The variant's program, compiled and linked, its uniforms located (GL: the renderer's context current).
void linkVariant(int variant, AvatarProgram& program);

}  // namespace th::render::avatar_draw
