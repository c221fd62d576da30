// What the weight formats share (ARKit, Oculus visemes, VRM vowels; not a public API): a table of named
// weights per frame, written as CSV (time_s, then a column per name) or JSON.
//
//   writeWeightsCsv(out, names, weights, 30.0);    // weights: one row per name, one column per frame
//
// Layouts (docs/formats.md): CSV "time_s,NAME,..." then a row per frame, times to 6 decimals and weights to 4;
// JSON {"fps": F, "names": [...], "frames": [{"time": t, "weights": [...]}, ...]} with the same digits.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <ostream>
#include <span>
#include <string_view>

namespace th::formats {

void writeWeightsCsv(std::ostream& out, std::span<const std::string_view> names, const Eigen::MatrixXd& weights,
                     double framesPerSecond);
void writeWeightsJson(std::ostream& out, std::span<const std::string_view> names, const Eigen::MatrixXd& weights,
                      double framesPerSecond);

}  // namespace th::formats
