#include "render/materials.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "gl_program.h"
#include "render/face_renderer.h"
#include "render/occlusion.h"
#include "render/simplify.h"
#include "shader_sources.h"

namespace th::render {
namespace {

// The order of drawing: opaque surfaces first (the backdrop follows them, see FaceRenderer::render()); then
// the sclera, whose clear cornea is blended over the iris; the lashes and the see-through eye layers last.
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

float cosDegrees(float degrees) {
  return std::cos(degrees * std::numbers::pi_v<float> / 180.0f);
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

// Each sclera and iris draw takes the eye nearest to it.
void assignEyes(const face::Mesh& mesh, DrawList& list) {
  if (!list.eyes.empty()) {
    float meanX = 0.0f;
    for (const Eye& eye : list.eyes) meanX += eye.centre.x() / static_cast<float>(list.eyes.size());
    for (Eye& eye : list.eyes) eye.side = eye.centre.x() >= meanX ? 0 : 1;
  }
  for (Draw& draw : list.draws) {
    if ((draw.surface != Surface::kSclera && draw.surface != Surface::kIris) || list.eyes.empty()) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t i = draw.firstIndex; i < draw.firstIndex + static_cast<std::size_t>(draw.count); ++i)
      mean += mesh.positions.col(list.indices[i]);
    const Eigen::Vector3f centre = (mean / static_cast<double>(draw.count)).cast<float>();
    int best = 0;
    for (std::size_t e = 1; e < list.eyes.size(); ++e)
      if ((list.eyes[e].centre - centre).norm() < (list.eyes[static_cast<std::size_t>(best)].centre - centre).norm())
        best = static_cast<int>(e);
    draw.eye = best;
  }
}

}  // namespace

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

bool touchesBrows(const face::Mesh& mesh, const std::array<int, 3>& triangle) {
  if (mesh.uv.cols() != mesh.numVertices()) return false;
  return std::any_of(triangle.begin(), triangle.end(), [&](int v) {
    const float u = mesh.uv(0, v);
    const float w = mesh.uv(1, v);
    return u >= 0.0f && u <= 1.0f && std::abs(u - 0.5f) < 0.3f && w > 0.75f && w < 0.84f;
  });
}

bool isBlended(Surface s) {
  return s == Surface::kSclera || s == Surface::kLashes || s == Surface::kEyeLayer;
}

bool isTwoSided(Surface s) {
  return s == Surface::kLashes || s == Surface::kEyeLayer;
}

Eigen::Vector3f srgbToLinear(const Eigen::Vector3f& c) {
  Eigen::Vector3f out;
  for (int k = 0; k < 3; ++k) out[k] = c[k] <= 0.04045f ? c[k] / 12.92f : std::pow((c[k] + 0.055f) / 1.055f, 2.4f);
  return out;
}

DrawList buildDrawList(const face::Mesh& mesh, const SurfaceMap& map, const Appearance& look, bool simplifyEyeballs) {
  DrawList list;
  // Triangles sorted into draw calls: by drawing rank, then material; the skin round the brows apart.
  std::vector<std::size_t> order(mesh.triangles.size());
  std::vector<bool> brow(mesh.triangles.size());
  for (std::size_t t = 0; t < order.size(); ++t) {
    order[t] = t;
    brow[t] = map.ofTriangle[t] == Surface::kSkin && touchesBrows(mesh, mesh.triangles[t]);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const int ra = drawRank(map.ofTriangle[a]);
    const int rb = drawRank(map.ofTriangle[b]);
    if (ra != rb) return ra < rb;
    if (mesh.triangleMaterial[a] != mesh.triangleMaterial[b])
      return mesh.triangleMaterial[a] < mesh.triangleMaterial[b];
    return brow[a] < brow[b];
  });
  std::vector<std::uint32_t>& indices = list.indices;
  indices.reserve(order.size() * 3);
  std::vector<std::uint32_t> material;
  for (std::size_t i = 0; i < order.size();) {
    const int materialIndex = mesh.triangleMaterial[order[i]];
    const Surface surface = map.ofTriangle[order[i]];
    const bool brows = brow[order[i]];
    std::size_t j = i;
    material.clear();
    while (j < order.size() && mesh.triangleMaterial[order[j]] == materialIndex && brow[order[j]] == brows) {
      for (int v : mesh.triangles[order[j]]) material.push_back(static_cast<std::uint32_t>(v));
      ++j;
    }
    // The iris keeps more of its shape: its pupil is a hole, which a coarser disc turns into a keyhole.
    if (simplifyEyeballs && surface == Surface::kSclera)
      material = simplifyTriangles(material, mesh.positions, {.keep = 0.25f, .error = 0.01f});
    if (simplifyEyeballs && surface == Surface::kIris)
      material = simplifyTriangles(material, mesh.positions, {.keep = 0.25f, .error = 0.002f});
    Draw draw;
    draw.surface = surface;
    draw.program = brows ? Program::kBrows : programOf(surface);
    draw.firstIndex = indices.size();
    draw.count = static_cast<int>(material.size());
    indices.insert(indices.end(), material.begin(), material.end());
    const auto [lowest, highest] =
        std::minmax_element(indices.begin() + static_cast<std::ptrdiff_t>(draw.firstIndex), indices.end());
    draw.lowest = *lowest;
    draw.highest = *highest;
    draw.shading = shadingOf(
        draw.surface, materialIndex >= 0 ? &mesh.materials[static_cast<std::size_t>(materialIndex)] : nullptr, look);
    if (draw.surface != Surface::kEyeLayer || look.drawEyeLayers) list.draws.push_back(draw);
    i = j;
  }

  for (EyeRig& rig : findEyes(mesh, map)) list.eyes.push_back(Eye{std::move(rig)});
  assignEyes(mesh, list);
  return list;
}

VertexDetail measureVertexDetail(const face::Mesh& mesh, const SurfaceMap& map, const Eigen::Matrix3Xf& normals) {
  VertexDetail detail;
  std::vector<int> triangleGroup(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) triangleGroup[t] = static_cast<int>(map.ofTriangle[t]);
  const auto numVertices = static_cast<std::size_t>(mesh.numVertices());
  std::vector<std::uint32_t> occludedBy(numVertices);
  for (std::size_t v = 0; v < occludedBy.size(); ++v) occludedBy[v] = occludersOf(map.ofVertex[v]);
  detail.openness =
      computeOpennessCached(mesh.positions, normals, mesh.triangles, triangleGroup, occludedBy, detailCacheFolder());
  detail.lipWeight = lipWeight(mesh, map, detail.openness);
  darkenMouthInterior(mesh, map, detail.openness);
  const Eigen::VectorXf opacity = lashOpacity(mesh, map);

  const SkinMarkings markings = skinMarkings(mesh, map);
  const bool hasUv = mesh.uv.cols() == mesh.numVertices();
  detail.interleaved.resize(numVertices * kDetailFloats);
  for (Eigen::Index v = 0; v < static_cast<Eigen::Index>(numVertices); ++v) {
    float* out = &detail.interleaved[static_cast<std::size_t>(kDetailFloats * v)];
    out[0] = detail.openness[v];
    out[1] = map.ofVertex[static_cast<std::size_t>(v)] == Surface::kSkin ? detail.lipWeight[v] : opacity[v];
    out[2] = hasUv ? mesh.uv(0, v) : 0.0f;
    out[3] = hasUv ? mesh.uv(1, v) : 0.0f;
    out[4] = markings.redness[v];
    out[5] = markings.hair[v];
    out[6] = markings.grain[v];
  }
  return detail;
}

void linkFaceProgram(Program program, FaceProgram& f) {
  // Each variant: the #version line, its #define, the shared lighting code, then the stage's own source.
  const auto variant = [](const char* source, const char* define) {
    const std::string text = source;
    return std::string("#version 330 core\n#define ") + define + " 1\n" + shaders::kLighting_glsl + "#line 2\n" +
           text.substr(text.find('\n') + 1);
  };
  const char* define = kProgramDefine[static_cast<int>(program)];
  f.id = linkProgram(variant(shaders::kFace_vert, define).c_str(), variant(shaders::kFace_frag, define).c_str(),
                     (std::string("face/") + define).c_str());
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
  f.browTint = at("uBrowTint");
  f.hairAlbedo = at("uHairAlbedo");
  f.specular = at("uSpecular");
  f.shininess = at("uShininess");
  f.opacity = at("uOpacity");
  f.eyeCentre = at("uEyeCentre");
  f.eyeAxis = at("uEyeAxis");
  f.eyeCosines = at("uEyeCosines");
  f.irisColour = at("uIrisColour");
  f.scleraColour = at("uScleraColour");
}

void setFrameUniforms(std::span<const FaceProgram> programs, const Eigen::Matrix4f& view,
                      const Eigen::Matrix4f& viewProjection, const Eigen::Vector3f& eyePosition, const Lighting& light,
                      const Appearance& look) {
  // Lights are given in camera space: the view's inverse rotation turns them into world space.
  const Eigen::Matrix3f toWorld = view.topLeftCorner<3, 3>().transpose();
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
  for (const FaceProgram& f : programs) {
    glUseProgram(f.id);
    glUniformMatrix4fv(f.viewProjection, 1, GL_FALSE, viewProjection.data());  // Eigen is column-major, as GL
    setVector(f.cameraPosition, eyePosition);
    glUniform3fv(f.lightDirection, 3, directions);
    glUniform3fv(f.lightColour, 3, colours);
    setVector(f.skyAmbient, light.skyAmbient);
    setVector(f.groundAmbient, light.groundAmbient);
    glUniform1f(f.exposure, light.exposure);
    setVector(f.lipAlbedo, srgbToLinear(look.lips));
    setVector(f.hairAlbedo, srgbToLinear(look.hair));
    // The brows darken the finished skin colour (sRGB) by the ratio of their colour to the skin's.
    setVector(f.browTint, look.brows.cwiseQuotient(look.skin.cwiseMax(0.01f)).cwiseMin(1.0f));
    setVector(f.irisColour, srgbToLinear(look.iris));
    setVector(f.scleraColour, srgbToLinear(look.sclera));
    glUniform3f(f.eyeCosines, cosDegrees(look.pupilDegrees), cosDegrees(look.irisDegrees),
                cosDegrees(look.corneaDegrees));
  }
}

void setDrawUniforms(const FaceProgram& f, const Draw& draw, const std::vector<Eye>& eyes, const Appearance& look) {
  setVector(f.albedo, draw.shading.albedo);
  setVector(f.specular, draw.shading.specular);
  glUniform1f(f.shininess, draw.shading.shininess);
  glUniform1f(f.opacity, draw.shading.opacity);
  if (draw.eye >= 0) {
    const Eye& eye = eyes[static_cast<std::size_t>(draw.eye)];
    setVector(f.eyeCentre, eye.centre);
    setVector(f.eyeAxis, eye.axis);
    // A pupil scaled in radius on the eyeball's sphere: sin of its angle scales; it stays inside the iris.
    const float rest = std::sin(look.pupilDegrees * std::numbers::pi_v<float> / 180.0f);
    const float limit = 0.9f * std::sin(look.irisDegrees * std::numbers::pi_v<float> / 180.0f);
    const float sine = std::clamp(rest * eye.pupilScale, 0.0f, limit);
    glUniform3f(f.eyeCosines, std::sqrt(1.0f - sine * sine), cosDegrees(look.irisDegrees),
                cosDegrees(look.corneaDegrees));
  }
}

}  // namespace th::render
