// What of a frame is worth the work. llvmpipe pays for every triangle it is given, even those it then culls
// or hides: the triangles facing away from the camera, and the mouth's inside and the eyeballs where they
// lie outside their openings on screen, are dropped on the CPU first (RenderOptions::cullOnCpu). The CPU
// then reads back and finishes only the pixels round the head (RenderOptions::cropToHead). Internal to the
// renderer: FaceRenderer uploads the indices kept and draws each draw's span of them.
//
//   th::render::Culling culling(list, mesh.numVertices(), true);
//   culling.setMouthOpening(innerLipVertices);
//   culling.select(list, vertexData, camera.eye(), viewProjection, width, height);   // per frame
//   upload(culling.indices().data(), culling.numIndices());
//   for (std::size_t d = 0; d < list.draws.size(); ++d) draw(list.draws[d], culling.ofDraw(d));
//   const th::render::PixelRegion region = th::render::headRegion(vertexData, viewProjection, width, height);
//
// Thread contract: a Culling belongs to one thread at a time; select() allocates nothing. headRegion() is a
// pure function.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/face_renderer.h"
#include "render/materials.h"

namespace th::render {

class Culling {
 public:
  // For `list`'s draws, over a mesh of `numVertices` vertices. `onCpu` false: every triangle is kept,
  // culling is left to GL alone.
  Culling(const DrawList& list, int numVertices, bool onCpu);

  // The lines bounding the openings the mouth's inside and the eyeballs are seen through (FaceRenderer's
  // setMouthOpening and setEyeOpenings). Empty: that surface is never dropped for lying outside it.
  void setMouthOpening(std::vector<int> innerLipVertices);
  void setEyeOpenings(std::vector<int> leftLidVertices, std::vector<int> rightLidVertices);

  // This frame's triangles of each draw of `list` (the one given to the constructor), in its order.
  // `vertexData`: the frame's vertices as uploaded, 6 floats each (position, then normal). `eye`: the
  // camera's position; `width` x `height`: the target's size in pixels.
  void select(const DrawList& list, const std::vector<float>& vertexData, const Eigen::Vector3f& eye,
              const Eigen::Matrix4f& viewProjection, int width, int height);

  // A draw's triangles kept by the last select(): indices()[first, first + count).
  struct Span {
    std::size_t first = 0;
    int count = 0;
  };
  const Span& ofDraw(std::size_t draw) const { return spans_[draw]; }
  const std::vector<std::uint32_t>& indices() const { return indices_; }  // only the first numIndices() count
  std::size_t numIndices() const { return numIndices_; }
  int numTriangles() const { return numTriangles_; }

 private:
  void checkVertices(const std::vector<int>& vertices, const char* what) const;

  int numVertices_ = 0;
  bool onCpu_ = true;
  std::array<std::vector<int>, 3> openings_;  // lines bounding the mouth's opening, the left and right eye's
  std::vector<std::uint32_t> indices_;        // this frame's front-facing ones (per frame, no allocation)
  std::vector<Span> spans_;                   // per draw
  std::size_t numIndices_ = 0;
  int numTriangles_ = 0;
};

// The pixels of a `width` x `height` frame the head may cover (RenderOptions::cropToHead), from `vertexData`
// as Culling::select takes it.
PixelRegion headRegion(const std::vector<float>& vertexData, const Eigen::Matrix4f& viewProjection, int width,
                       int height);
// The pixels of a `width` x `height` frame round a rectangle in normalised device coordinates (x and y in
// -1..1, y up), 8 pixels wider on every side (FXAA's reach) and on even pixels (Y'CbCr 4:2:0 blocks), within
// the frame; empty if it lies outside.
PixelRegion pixelRegion(float lowX, float lowY, float highX, float highY, int width, int height);

}  // namespace th::render
