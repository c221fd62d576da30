// How each surface of the face is shaded. The face's triangles sorted into draw calls (by drawing order, then
// material), each with its program variant, its colours and gloss (from the Appearance, or the MTL file for
// surfaces the renderer does not know) and the eye it is shaded round; the per-vertex detail measured once on
// the mesh at rest (ambient openness, the lips' weight, the lashes' fade); the face programs and their
// uniforms. Internal to the renderer: FaceRenderer owns the GL objects and draws what this describes.
//
//   const th::render::SurfaceMap map = th::render::classifySurfaces(mesh);
//   th::render::DrawList list = th::render::buildDrawList(mesh, map, appearance, true);
//   context.makeCurrent();
//   const th::render::VertexDetail detail = th::render::measureVertexDetail(mesh, map, normals);
//   linkFaceProgram(Program::kSkin, programs[0]);                    // ... one per variant
//   setFrameUniforms(programs, view, viewProjection, eye, lighting, appearance);   // per frame
//   setDrawUniforms(programs[0], list.draws[0], list.eyes, appearance);   // per draw, its program in use
//
// Thread contract: values and pure functions, but for measureVertexDetail() and the programs' functions,
// which need the calling thread's current GL 3.3 context.
#pragma once

#include <glad/gl.h>

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "face/mesh.h"
#include "render/surfaces.h"

namespace th::render {

struct Appearance;
struct Lighting;

// The variants face.frag is compiled in (see its head comment). kBrows is the skin round the eyebrows, which
// are drawn per pixel: the rest of the skin need not pay for them.
enum class Program : int { kSkin = 0, kSclera, kIris, kPlain, kBrows };
inline constexpr int kNumPrograms = 5;
inline constexpr const char* kProgramDefine[kNumPrograms] = {"SKIN", "SCLERA", "IRIS", "PLAIN", "BROWS"};

Program programOf(Surface s);

// Whether a skin triangle may hold eyebrow: a vertex of it lies in the brows' box in ICT FaceKit's face UV tile
// (face.frag, browCover(), draws them within it). False if the mesh has no texture coordinates.
bool touchesBrows(const face::Mesh& mesh, const std::array<int, 3>& triangle);

bool isBlended(Surface s);

// Cards (lashes) and thin layers are seen from both sides; closed surfaces only from outside.
bool isTwoSided(Surface s);

Eigen::Vector3f srgbToLinear(const Eigen::Vector3f& c);

// The material of a draw, from the appearance (known surfaces) or the MTL file (others).
struct Shading {
  Eigen::Vector3f albedo = Eigen::Vector3f::Constant(0.5f);  // linear
  Eigen::Vector3f specular = Eigen::Vector3f::Constant(0.04f);
  float shininess = 16.0f;
  float opacity = 1.0f;
};

// One draw call: a run of DrawList::indices of one material.
struct Draw {
  Surface surface = Surface::kOther;
  std::size_t firstIndex = 0;
  int count = 0;             // indices, 3 a triangle
  std::uint32_t lowest = 0;  // vertex index range, so the driver need not scan the indices
  std::uint32_t highest = 0;
  int eye = -1;  // sclera and iris: index into DrawList::eyes
  Program program = Program::kPlain;
  Shading shading;
};

// An eye the sclera and iris are shaded round, tracked per frame (EyeRig::track).
struct Eye : EyeRig {
  int side = 0;             // 0: the face's left (+x, FAP 29), 1: its right (FAP 30)
  float pupilScale = 1.0f;  // the pupil's radius relative to rest
};

struct DrawList {
  std::vector<std::uint32_t> indices;  // every triangle, in draw order (draws index into it)
  std::vector<Draw> draws;
  std::vector<Eye> eyes;  // tracked at the mesh's rest positions
};

// The mesh's triangles sorted into draws: by drawing rank, then material. The thin eye layers are left out
// unless `look` asks for them; `simplifyEyeballs`: the sclera and iris with fewer triangles
// (RenderOptions::simplifyEyeballs).
DrawList buildDrawList(const face::Mesh& mesh, const SurfaceMap& map, const Appearance& look, bool simplifyEyeballs);

// Per-vertex detail from the mesh at rest (`normals`: its normals there).
struct VertexDetail {
  Eigen::VectorXf openness;   // ambient openness, 0..1 (darkened inside the mouth)
  Eigen::VectorXf lipWeight;  // render/surfaces.h: lipWeight()
  // What the static vertex buffer holds, kDetailFloats a vertex: openness, then the lip weight on skin or the
  // opacity elsewhere (one channel serves both: no vertex is skin and lash at once), then the texture
  // coordinates (zero if the mesh has none), then the skin's markings (render/surfaces.h: SkinMarkings:
  // redness, hair, grain).
  std::vector<float> interleaved;
};
inline constexpr int kDetailFloats = 7;

// Ambient openness is measured on the GPU (render/occlusion.h), or read from the detail cache.
VertexDetail measureVertexDetail(const face::Mesh& mesh, const SurfaceMap& map, const Eigen::Matrix3Xf& normals);

// A variant of the face program, and where its uniforms are.
struct FaceProgram {
  GLuint id = 0;
  GLint viewProjection, cameraPosition, lightDirection, lightColour, skyAmbient, groundAmbient, exposure;
  GLint albedo, lipAlbedo, browTint, hairAlbedo, specular, shininess, opacity, eyeCentre, eyeAxis, eyeCosines,
      irisColour, scleraColour;
};

// Compiles and links `program` into `f` and finds its uniforms; throws th::Error with the driver's message
// (render/gl_program.h), leaving `f` as it was. Needs the calling thread's current GL context.
void linkFaceProgram(Program program, FaceProgram& f);

// Per-frame uniforms, the same in every face program: the camera, the lights (fixed to the camera, see
// Lighting) and the colours every variant shares.
void setFrameUniforms(std::span<const FaceProgram> programs, const Eigen::Matrix4f& view,
                      const Eigen::Matrix4f& viewProjection, const Eigen::Vector3f& eyePosition, const Lighting& light,
                      const Appearance& look);

// A draw's material, into `f` (the program in use): its shading, and on the eyeballs its eye and pupil.
void setDrawUniforms(const FaceProgram& f, const Draw& draw, const std::vector<Eye>& eyes, const Appearance& look);

}  // namespace th::render
