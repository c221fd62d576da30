#include "render/avatar_draw.h"

#include <algorithm>

#include "render/gl_program.h"
#include "render/shader_sources.h"

namespace th::render::avatar_draw {

// The six planes of a view-projection's frustum (Gribb and Hartmann, "Fast extraction of viewing frustum planes
// from the world-view-projection matrix", 2001): a point p is inside where every row r gives r · (p, 1) >= 0.
std::array<Eigen::Vector4f, 6> frustumPlanes(const Eigen::Matrix4f& viewProjection) {
  const Eigen::Vector4f x = viewProjection.row(0), y = viewProjection.row(1), z = viewProjection.row(2),
                        w = viewProjection.row(3);
  return {w + x, w - x, w + y, w - y, w + z, w - z};
}

// Whether a box meets the frustum: for each plane its corner farthest along the plane's normal is inside
// (conservative: a box near an edge of the frustum may pass without meeting it).
bool meetsFrustum(const Eigen::AlignedBox3f& box, const std::array<Eigen::Vector4f, 6>& planes) {
  if (box.isEmpty()) return false;
  for (const Eigen::Vector4f& plane : planes) {
    const Eigen::Vector3f corner((plane.x() >= 0.0f ? box.max() : box.min()).x(),
                                 (plane.y() >= 0.0f ? box.max() : box.min()).y(),
                                 (plane.z() >= 0.0f ? box.max() : box.min()).z());
    if (plane.head<3>().dot(corner) + plane.w() < 0.0f) return false;
  }
  return true;
}

// The smallest region holding both (an empty one holds nothing).
PixelRegion unite(const PixelRegion& a, const PixelRegion& b) {
  if (a.width <= 0 || a.height <= 0) return b;
  if (b.width <= 0 || b.height <= 0) return a;
  const int left = std::min(a.left, b.left), top = std::min(a.top, b.top);
  const int right = std::max(a.left + a.width, b.left + b.width), bottom = std::max(a.top + a.height, b.top + b.height);
  return {left, top, right - left, bottom - top};
}

void measure(Cluster& cluster, const std::vector<std::uint32_t>& indices, const Eigen::Matrix3Xf& positions) {
  cluster.bounds.setEmpty();
  for (std::uint32_t i = cluster.first; i < cluster.first + cluster.count; ++i)
    cluster.bounds.extend(positions.col(indices[i]));
}

std::string withLighting(const char* stage, const std::string& defines) {
  return std::string("#version 330 core\n") + defines + shaders::kLighting_glsl + "#line 2\n" + stage;
}

// A primitive's material; glTF's default (white, opaque, metallic 1, roughness 1) where it names none.
const avatar::Material& materialOf(const avatar::Avatar& avatar, int material) {
  static const avatar::Material plain;
  return material >= 0 && material < static_cast<int>(avatar.materials.size())
             ? avatar.materials[static_cast<std::size_t>(material)]
             : plain;
}

int variantOf(const avatar::Material& material, bool textured) {
  const int alpha = material.alpha == avatar::AlphaMode::kOpaque ? 0
                    : material.alpha == avatar::AlphaMode::kMask ? 1
                                                                 : 2;
  return alpha * 8 + (material.roughness == 1.0f ? 4 : 0) + (textured ? 2 : 0) + (material.unlit ? 1 : 0);
}

void linkVariant(int variant, AvatarProgram& program) {
  const int shading = variant % kDepthOnly;
  const std::string defines = "#define ALPHA_MODE " + std::to_string(shading / 8) + "\n#define ROUGH " +
                              std::to_string(shading / 4 % 2) + "\n#define TEXTURED " +
                              std::to_string(shading / 2 % 2) + "\n#define UNLIT " + std::to_string(shading % 2) +
                              "\n#define DEPTH_ONLY " + std::to_string(variant / kDepthOnly) + "\n";
  const std::string vertex = withLighting(shaders::kAvatar_vert),
                    fragment = withLighting(shaders::kAvatar_frag, defines);
  program.id = linkProgram(vertex.c_str(), fragment.c_str(), "avatar");
  const auto at = [&](const char* name) { return glGetUniformLocation(program.id, name); };
  program.viewProjection = at("uViewProjection");
  program.cameraPosition = at("uCameraPosition");
  program.lightDirection = at("uLightDirection");
  program.lightColour = at("uLightColour");
  program.skyAmbient = at("uSkyAmbient");
  program.groundAmbient = at("uGroundAmbient");
  program.exposure = at("uExposure");
  program.baseColour = at("uBaseColour");
  program.baseTexture = at("uBaseTexture");
  program.emissive = at("uEmissive");
  program.metallic = at("uMetallic");
  program.roughness = at("uRoughness");
  program.alphaCutoff = at("uAlphaCutoff");
}

}  // namespace th::render::avatar_draw
