// What the renderer knows about a face mesh besides its triangles: the kind of surface of each material (by
// ICT FaceKit's material names), the eyes (tracked per frame from their iris vertices), and per-vertex detail
// computed once from the mesh at rest (lash opacity, lip weight, the mouth's darkness). Internal to the
// renderer (public for its tests).
//
//   const th::render::SurfaceMap map = th::render::classifySurfaces(mesh);
//   std::vector<th::render::EyeRig> eyes = th::render::findEyes(mesh, map);
//   eyes[0].track(positions);          // per frame: eyes[0].centre, eyes[0].axis
//
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <string_view>
#include <vector>

#include "face/mesh.h"

namespace th::render {

// Kinds of surface, shaded differently. The values index bit masks (occlusion) and order nothing.
enum class Surface : int { kSkin = 0, kSclera, kIris, kTeeth, kGums, kLashes, kEyeLayer, kOther };

// M_Face, M_BackHead -> skin; M_ScleraLeft -> sclera; M_GumsTongue -> gums; M_LacrimalFluid, M_EyeOcclusion,
// M_EyeBlend -> eye layer; and so on. Unknown names are kOther (drawn plainly with their MTL colour).
Surface surfaceOf(std::string_view materialName);

struct SurfaceMap {
  std::vector<Surface> ofMaterial;  // per material
  std::vector<Surface> ofTriangle;  // per triangle (kOther without a material)
  std::vector<Surface> ofVertex;    // per vertex: that of the first triangle using it (kOther if none)
};

SurfaceMap classifySurfaces(const face::Mesh& mesh);

// An eye, followed from its iris vertices: the centre of the eyeball and the axis through the iris disc are
// rebuilt each frame from two vertex means whose relation was measured at rest, so they follow any rigid
// motion of the eyeball (head turns, gaze blend shapes).
struct EyeRig {
  std::vector<int> all;          // the iris mesh's vertices
  std::vector<int> front;        // those on the iris disc (within 15 degrees of the axis at rest)
  double centreAlongAxis = 0.0;  // centre = mean(all) + this * (mean(front) - mean(all))
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f axis = Eigen::Vector3f::UnitZ();

  void track(const Eigen::Matrix3Xd& positions);
};

// One per iris material with enough vertices, tracked at the rest positions. The centre is a least-squares
// sphere through the iris mesh; the axis points from it to the vertex mean (the iris disc is densely
// tessellated, so the mean lies in front of the centre, on the axis).
std::vector<EyeRig> findEyes(const face::Mesh& mesh, const SurfaceMap& map);

// Per vertex: 1, except on lash cards, which fade from the lid (where they meet the skin) to their tips, and
// are lighter on the lower lid: untextured cards would otherwise read as a painted band.
Eigen::VectorXf lashOpacity(const face::Mesh& mesh, const SurfaceMap& map);

// Per vertex, 0..1: how much a skin vertex belongs to the lips' red. From geometry alone: the mouth's slit is
// where the skin folds inwards (low `openness`) in front of the teeth; the lips are bands above and below it,
// tapering to the corners. All zero if the mesh has no teeth to find the mouth by.
Eigen::VectorXf lipWeight(const face::Mesh& mesh, const SurfaceMap& map, const Eigen::VectorXf& openness);

// Per vertex, drawn on the skin from its texture coordinates (ICT FaceKit's UV tiles; zero elsewhere and
// without UVs). Measured once, so the vertex shader need not redo it every frame.
struct SkinMarkings {
  // How much redder than the skin's colour, about 0..0.6: centimetre-scale blotches, the cheeks, the nose's tip.
  Eigen::VectorXf redness;
  // How much cropped hair covers it, 0..1: above a hairline across the top of the forehead that drops at the
  // temples to sideburns in front of the ears (the face's tile, u 0..1); over the scalp from above the ears
  // round to the nape (the back of the head's tile, u 1..2, whose outer parts are the neck and shoulders and
  // whose top corners hold hidden patches inside the eye sockets).
  Eigen::VectorXf hair;
  // A random value per vertex, 0..1: the strength of the skin's sheen (broken up by pores, a few millimetres
  // apart), the hair's shade.
  Eigen::VectorXf grain;
};

SkinMarkings skinMarkings(const face::Mesh& mesh, const SurfaceMap& map);

// Darkens the inside of the mouth (teeth, gums, tongue) with depth behind the front teeth: their occlusion is
// measured among themselves only (the closed lips of a neutral mesh would black out the front teeth), and
// little light reaches the back of a real mouth.
void darkenMouthInterior(const face::Mesh& mesh, const SurfaceMap& map, Eigen::VectorXf& openness);

}  // namespace th::render
