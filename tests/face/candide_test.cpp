// Candide-3 as an independent reference for the FAP table: its per-FAP displacements point the way our table
// says each FAP moves, and its FAPU tags agree with our units.
#include "face/candide.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>

#include "core/error.h"
#include "core/temporary_file.h"
#include "face/fap.h"

namespace {

TEST(Candide, LoadsTheMeshAndItsFaps) {
  const th::face::Candide candide = th::face::loadCandide(th::face::candideFile());
  EXPECT_EQ(candide.mesh.numVertices(), 113);
  EXPECT_EQ(candide.mesh.triangles.size(), 184u);
  EXPECT_EQ(candide.faps.size(), 54u);  // FAPs 3-42 and 51-64 (no tongue, head or ears)
  const th::face::CandideFap& jaw = candide.faps.at(3);
  EXPECT_EQ(jaw.unit, "MNS");
  EXPECT_EQ(jaw.displacements.size(), 3u);
}

TEST(Candide, AgreesWithOurFapTableOnDirectionsAndUnits) {
  const th::face::Candide candide = th::face::loadCandide(th::face::candideFile());
  int compared = 0;
  for (const auto& [number, fap] : candide.faps) {
    const th::face::FapDefinition& ours = th::face::fapDefinition(number);
    const Eigen::Vector3d direction(ours.direction[0], ours.direction[1], ours.direction[2]);
    if (direction.norm() == 0.0) continue;  // pupil size: no direction
    Eigen::Vector3d main = Eigen::Vector3d::Zero();
    for (const auto& [vertex, displacement] : fap.displacements)
      if (vertex == fap.mainVertex()) main = displacement;
    if (ours.unit == th::face::Fapu::kAngle) {
      // Candide moves the eyeball's vertices; we turn it about `direction`: a point in front of the centre
      // (+z) moves along direction × z.
      EXPECT_GT(direction.cross(Eigen::Vector3d::UnitZ()).dot(main), 0.0) << ours.name;
    } else if (number == 18) {
      // Candide moves the chin boss down for depress_chin; Annex C describes it as an "upward and compressing
      // movement of the chin (like in sadness)", positive up, which we keep.
      EXPECT_LT(direction.dot(main.normalized()), -0.7) << "Candide's FAP 18 changed";
    } else {
      EXPECT_GT(direction.dot(main.normalized()), 0.7) << ours.name;
    }
    // Candide tags FAP 15 (shift_jaw) with MNS; ISO/IEC 14496-2 Annex C gives MW, which we keep.
    if (number == 15) {
      EXPECT_EQ(fap.unit, "MNS") << "Candide's FAP 15 changed";
    } else if (!fap.unit.empty()) {
      EXPECT_EQ(fap.unit, th::face::fapuName(ours.unit)) << ours.name;
    }
    ++compared;
  }
  EXPECT_EQ(compared, 52);
}

TEST(Candide, BrokenFilesAreOneLineErrors) {
  const th::TemporaryFolder folder;
  const auto path = folder.path() / "broken.wfm";
  std::ofstream(path) << "# VERTEX LIST:\n2\n0 0 0\n1 x 0\n";
  try {
    th::face::loadCandide(path);
    FAIL();
  } catch (const th::Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("broken.wfm: line 4"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
  std::ofstream(path) << "just text\n";
  EXPECT_THROW(th::face::loadCandide(path), th::Error);
  EXPECT_THROW(th::face::loadCandide(folder.path() / "missing.wfm"), th::Error);
}

}  // namespace
