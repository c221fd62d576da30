#include "render/simplify.h"

#include <meshoptimizer.h>

#include <string>
#include <unordered_map>

#include "core/error.h"

namespace th::render {

std::vector<std::uint32_t> simplifyTriangles(const std::vector<std::uint32_t>& triangles,
                                             const Eigen::Matrix3Xd& positions, const SimplifyOptions& options) {
  if (triangles.size() % 3 != 0)
    throw Error("simplifyTriangles: " + std::to_string(triangles.size()) + " indices are not whole triangles");
  // The surface's own vertices, compactly: meshoptimizer measures the error against the extent of the
  // vertices it is given, which must be this surface's, not the whole head's.
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  std::vector<std::uint32_t> global;
  std::vector<std::uint32_t> localTriangles;
  localTriangles.reserve(triangles.size());
  for (const std::uint32_t v : triangles) {
    if (v >= static_cast<std::uint32_t>(positions.cols()))
      throw Error("simplifyTriangles: vertex " + std::to_string(v) + " of " + std::to_string(positions.cols()));
    const auto [at, added] = local.try_emplace(v, static_cast<std::uint32_t>(global.size()));
    if (added) global.push_back(v);
    localTriangles.push_back(at->second);
  }
  std::vector<float> xyz(global.size() * 3);
  for (std::size_t i = 0; i < global.size(); ++i)
    for (int k = 0; k < 3; ++k) xyz[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(positions(k, global[i]));
  const std::size_t target = static_cast<std::size_t>(static_cast<float>(triangles.size() / 3) * options.keep) * 3;
  std::vector<std::uint32_t> simplified(localTriangles.size());
  const std::size_t count =
      meshopt_simplify(simplified.data(), localTriangles.data(), localTriangles.size(), xyz.data(), global.size(),
                       3 * sizeof(float), target, options.error, meshopt_SimplifyLockBorder, nullptr);
  simplified.resize(count);
  for (std::uint32_t& v : simplified) v = global[v];
  return simplified;
}

}  // namespace th::render
