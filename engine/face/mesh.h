// Face meshes: an OBJ file (positions, texture coordinates, triangles, a material per triangle) read with
// tinyobjloader, and
// blend shapes that share its vertex order.
//
//   th::face::Mesh neutral = th::face::loadObjMesh("assets/ict-facekit/generic_neutral_mesh.obj");
//   Eigen::Matrix3Xd open = th::face::loadObjPositions("assets/ict-facekit/jawOpen.obj", neutral.numVertices());
//   std::vector<int> teeth = neutral.verticesOf("M_Teeth");
//
// Positions keep the file's order of `v` lines (blend shapes and landmark indices refer to it); polygons are
// triangulated. Errors (th::Error) name the file and what is wrong.
// Thread contract: a Mesh is a value.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace th::face {

struct Material {
  std::string name;
  Eigen::Vector3f diffuse = Eigen::Vector3f::Constant(0.6f);
  Eigen::Vector3f specular = Eigen::Vector3f::Zero();
  float shininess = 1.0f;
};

struct Mesh {
  Eigen::Matrix3Xd positions;  // 3 x V
  // 2 x V: a vertex's texture coordinates (OBJ `vt`; zero if no face gives it one). An OBJ face corner names
  // a position and a `vt` apart, so a vertex on a UV seam has several: it keeps the first its faces give, in
  // the file's order (ICT FaceKit's seams lie on the borders between its UV tiles: the face's, the back of the
  // head's, ...; within the face's tile every vertex has one).
  Eigen::Matrix2Xf uv;
  std::vector<std::array<int, 3>> triangles;  // vertex indices, counter-clockwise seen from outside
  std::vector<int> triangleMaterial;          // per triangle, index into materials (-1: none)
  std::vector<Material> materials;

  int numVertices() const { return static_cast<int>(positions.cols()); }
  int materialIndex(std::string_view name) const;  // -1 if absent
  // The vertices of the triangles drawn with that material, ascending; empty if the material is absent.
  std::vector<int> verticesOf(std::string_view materialName) const;
};

Mesh loadObjMesh(const std::filesystem::path& path);

// Area-weighted vertex normals of the triangles drawn with the given materials (outward: the triangles are
// counter-clockwise seen from outside); zero for vertices of no such triangle. Absent materials are ignored.
Eigen::Matrix3Xd vertexNormals(const Mesh& mesh, std::initializer_list<std::string_view> materials);

// The positions alone, for a blend shape of a mesh with `expectedVertices` vertices (checked).
Eigen::Matrix3Xd loadObjPositions(const std::filesystem::path& path, int expectedVertices);

}  // namespace th::face
