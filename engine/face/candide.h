// Candide-3 (J. Ahlberg, LiTH-ISY-R-2326, 2001): the low-poly face with per-FAP vertex displacements, used as
// a second mesh and as an independent reference for the FAP table's directions and units.
//
//   th::face::Candide candide = th::face::loadCandide(th::face::candideFile());
//   const th::face::CandideFap& jaw = candide.faps.at(3);   // unit "MNS", vertices 10, 32, 65 move (0, -1, 0)
//
// The .wfm text: "# VERTEX LIST:" then a count and x y z lines; "# FACE LIST:" then a count and triangles;
// "# ANIMATION UNITS LIST:" then a count of units, each a comment naming it ("# FAP 3 open_jaw" or
// "# AUV0 ..."), for FAP units an optional comment with its FAPU tag, a count, and "vertex dx dy dz" lines.
// Candide's frame is the FAP table's: +x the face's left, +y up, +z forward. Errors name the file and line.
// Thread contract: values.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "face/mesh.h"

namespace th::face {

struct CandideFap {
  std::string unit;  // the FAPU tag as written ("MNS", "MW", ...), "" where the file has none (eyeballs)
  std::vector<std::pair<int, Eigen::Vector3d>> displacements;  // vertex, displacement per unit of the FAP
  // The vertex that moves most: the feature point the FAP names.
  int mainVertex() const;
};

struct Candide {
  Mesh mesh;                       // 113 vertices, one material "Candide"
  std::map<int, CandideFap> faps;  // by FAP number
};

// assets/candide3/candide3_v3.1.6.wfm when the set-up script has copied it, else the shared data's.
std::filesystem::path candideFile();

Candide loadCandide(const std::filesystem::path& path);

}  // namespace th::face
