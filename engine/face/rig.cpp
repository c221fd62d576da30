#include "face/rig.h"

#include <string>

#include "core/error.h"

namespace th::face::rig {

NeutralFace neutralFace(const Mesh& mesh, const FapUnits& units) {
  NeutralFace neutral{.mesh = mesh,
                      .rest = mesh.positions,
                      .units = units,
                      .mw = units.mw * 1024,
                      .mns = units.mns * 1024,
                      .es = units.es * 1024,
                      .irisd = units.irisd * 1024,
                      .face = mesh.verticesOf("M_Face"),
                      .skin = {}};
  if (neutral.face.empty()) throw Error("face model: the mesh has no M_Face material (the skin)");
  neutral.skin = neutral.face;
  for (int v : mesh.verticesOf("M_BackHead")) neutral.skin.push_back(v);
  std::sort(neutral.skin.begin(), neutral.skin.end());
  neutral.skin.erase(std::unique(neutral.skin.begin(), neutral.skin.end()), neutral.skin.end());
  return neutral;
}

void addDirectField(const NeutralFace& neutral, const FeaturePointMap& points, int number,
                    const std::vector<std::pair<int, double>>& weights, LinearFields& fields) {
  const FapDefinition& fap = fapDefinition(number);
  const Eigen::Vector3d centre = neutral.at(points, fap.featurePoint);
  double atPoint = 0.0;
  const std::vector<int>& pointVertices = points.vertices(fap.featurePoint);
  for (int p : pointVertices)
    for (const auto& [v, w] : weights)
      if (v == p) atPoint += w;
  atPoint /= static_cast<double>(pointVertices.size());
  if (!(atPoint > 0.5))
    throw Error("face model: FAP " + std::to_string(number) + "'s field does not carry its feature point");
  const Eigen::Vector3d unit = neutral.units.of(fap.unit) / atPoint * directionOf(fap);
  double reach = 0.0;
  for (const auto& [v, w] : weights) {
    fields.entries[static_cast<std::size_t>(number)].push_back({v, (w * unit).cast<float>()});
    reach = std::max(reach, (neutral.rest.col(v) - centre).norm());
  }
  fields.reach[static_cast<std::size_t>(number)] = reach;
}

}  // namespace th::face::rig
