// Smooth vertex normals of a deforming triangle mesh, recomputed every frame from the current positions.
//
//   th::render::VertexNormals normals(mesh);                 // once per topology: finds the seam vertices
//   Eigen::Matrix3Xf n(3, mesh.numVertices());
//   normals.compute(deformedPositions, n);                   // per frame, no allocation
//
// A vertex normal is the sum of the cross products of its triangles' edges (so larger triangles weigh more,
// "area-weighted"), normalised. Meshes made for texturing often split a vertex where the UV map has a seam:
// the copies share a position but not triangles, and would each get a one-sided normal, a visible crease.
// Vertices that coincide in the mesh given to the constructor and belong to the same material are therefore
// welded: they get the normal of their union. Vertices of different materials are never welded (an eyelid and
// the tear film layer lying on it must keep their own normals). ICT FaceKit's positions have no UV seams
// (tinyobjloader keeps the `v` list), but its eyelash cards do have coincident vertices. Thread contract: a
// VertexNormals is immutable after construction; compute() may run on several threads at once with different
// outputs.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "face/mesh.h"

namespace th::render {

class VertexNormals {
 public:
  // Welds coincident vertices (within `tolerance`, in mesh units) of the same material.
  explicit VertexNormals(const face::Mesh& mesh, double tolerance = 1e-6);
  // No welding, or an explicit one: `weldTo[v]` is the vertex whose normal v shares (v itself when alone; the
  // target must map to itself). Empty `weldTo` means no welding.
  VertexNormals(int numVertices, std::vector<std::array<int, 3>> triangles, std::vector<int> weldTo = {});

  int numVertices() const { return numVertices_; }
  int numWelded() const { return static_cast<int>(welded_.size()); }  // vertices that share another's normal

  // `positions` is 3 x numVertices(); `normals` is resized if needed. Vertices on no triangle, or only on
  // degenerate ones, get +z (towards the viewer), which keeps them harmless in shading.
  void compute(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xf& normals) const;

 private:
  int numVertices_ = 0;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<std::array<int, 2>> welded_;  // {vertex, the vertex it shares the normal of}
};

// For each vertex, the lowest-index vertex at the same position (within tolerance) among those of the same
// material; itself when there is none. A vertex's material is that of the first triangle that uses it.
std::vector<int> findCoincidentVertices(const face::Mesh& mesh, double tolerance);

}  // namespace th::render
