// Ambient occlusion per vertex, measured once for a mesh at rest: how much of the sky a vertex sees. It
// darkens the mouth's inside, the nostrils, the eye sockets behind the eyeballs and the ears' creases, which
// direct light without shadows would leave lit. Internal to the renderer (public for its tests).
//
//   context.makeCurrent();
//   Eigen::VectorXf open =
//       th::render::computeOpenness(mesh.positions, normals, mesh.triangles, triangleGroup, occludedBy, {});
//
// The mesh is drawn depth-only, orthographically, from `directions` directions spread evenly over the sphere
// (on the GPU: llvmpipe does this far faster than rays on the CPU). A vertex counts as seen from a direction
// when nothing lies in front of it in that view; the directions of its normal's hemisphere are weighted by
// the cosine, as diffuse light from a uniform sky would be. Thread contract: needs the calling thread's
// current GL 3.3 context; leaves framebuffer 0 bound.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace th::render {

struct OcclusionOptions {
  int directions = 96;
  int resolution = 512;     // of each depth view, square
  double bias = 0.03;       // mesh units a vertex may lie behind the nearest surface and still count as seen
  int smoothingPasses = 1;  // neighbour averages over triangles, to hide the sampling's texel steps
};

// 1 = open sky, 0 = enclosed. `triangleGroup` values are 0..31; `occludedBy[v]` has bit g set when triangles
// of group g may block vertex v's view (0: the vertex is not measured and gets 1).
Eigen::VectorXf computeOpenness(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xf& normals,
                                const std::vector<std::array<int, 3>>& triangles, const std::vector<int>& triangleGroup,
                                const std::vector<std::uint32_t>& occludedBy, const OcclusionOptions& options = {});

// The same, remembered on disk: the measurement takes about a second (two sets of 96 views of the whole head
// on llvmpipe), and a mesh's openness never changes, so each program that draws the face would otherwise pay
// it again. The file is named by a 64-bit hash of everything the result depends on (positions, triangles,
// groups, masks, options and this code's format version): a changed mesh or option gets a new file, never a
// stale one. A missing, unreadable or damaged file is measured again and rewritten (atomically); a folder
// that cannot be written only costs the time. `folder` empty: no cache.
Eigen::VectorXf computeOpennessCached(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xf& normals,
                                      const std::vector<std::array<int, 3>>& triangles,
                                      const std::vector<int>& triangleGroup,
                                      const std::vector<std::uint32_t>& occludedBy, const std::filesystem::path& folder,
                                      const OcclusionOptions& options = {});

// Where computed per-mesh detail is kept: $TALKINGHEAD_CACHE if set (empty: nowhere), else
// $XDG_CACHE_HOME/talkinghead, else ~/.cache/talkinghead; empty if none of these can be named.
std::filesystem::path detailCacheFolder();

}  // namespace th::render
