// Fewer, larger triangles over the same vertices, for surfaces whose look comes from per-pixel shading rather
// than from the density of their mesh (the eyeballs: ICT FaceKit gives each iris and cornea hundreds of
// triangles a pixel or two across at 720p, and llvmpipe pays per triangle). meshoptimizer's edge collapse
// (quadric error), with the surface's open borders kept where they are; the result indexes the original
// vertices, so the per-frame vertex data does not change.
//
//   std::vector<std::uint32_t> fewer = simplifyTriangles(indices, mesh.positions, {.keep = 0.3f});
//
// Thread contract: a pure function.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace th::render {

struct SimplifyOptions {
  float keep = 0.3f;  // the share of the triangles to aim for
  // The largest deviation allowed, as a share of the surface's own extent; the result stops short of `keep`
  // rather than exceed it.
  float error = 0.01f;
};

// `triangles`: 3 vertex indices each, into `positions` (3 x V). Returns the simplified triangles, likewise.
std::vector<std::uint32_t> simplifyTriangles(const std::vector<std::uint32_t>& triangles,
                                             const Eigen::Matrix3Xd& positions, const SimplifyOptions& options = {});

}  // namespace th::render
