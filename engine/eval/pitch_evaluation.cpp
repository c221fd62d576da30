#include "eval/pitch_evaluation.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.h"

namespace th::eval {

std::vector<double> sampleTrackAt(const F0Track& track, std::span<const double> timesSeconds,
                                  double maxDistanceSeconds) {
  std::vector<double> values(timesSeconds.size(), 0.0);
  const auto& times = track.timesSeconds;
  for (size_t i = 0; i < timesSeconds.size(); ++i) {
    const double t = timesSeconds[i];
    const auto upper = std::lower_bound(times.begin(), times.end(), t);
    long best = -1;
    double bestDistance = maxDistanceSeconds;
    for (auto it : {upper, upper == times.begin() ? times.end() : upper - 1}) {
      if (it == times.end()) continue;
      const double distance = std::abs(*it - t);
      if (distance <= bestDistance) {
        bestDistance = distance;
        best = it - times.begin();
      }
    }
    if (best >= 0) values[i] = track.f0Hz[static_cast<size_t>(best)];
  }
  return values;
}

F0Track readReferenceF0(const std::filesystem::path& path, double frameShiftSeconds) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open reference F0 file");
  F0Track track;
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    double value = 0.0;
    if (!(fields >> value) || !std::isfinite(value) || value < 0.0) {
      throw fileError(path, "line " + std::to_string(lineNumber) + " is not a non-negative F0 value");
    }
    track.timesSeconds.push_back(static_cast<double>(track.f0Hz.size()) * frameShiftSeconds);
    track.f0Hz.push_back(value);
  }
  if (track.f0Hz.empty()) throw fileError(path, "no F0 values");
  return track;
}

void PitchScore::add(std::span<const double> referenceHz, std::span<const double> estimateHz) {
  if (referenceHz.size() != estimateHz.size()) throw Error("PitchScore: reference and estimate differ in length");
  for (size_t i = 0; i < referenceHz.size(); ++i) {
    const bool referenceVoiced = referenceHz[i] > 0.0;
    const bool estimateVoiced = estimateHz[i] > 0.0;
    ++frames_;
    if (referenceVoiced != estimateVoiced) {
      ++voicingErrors_;
      if (referenceVoiced) ++missedVoicing_;
      continue;
    }
    if (!referenceVoiced) continue;
    ++voicedBoth_;
    if (std::abs(estimateHz[i] - referenceHz[i]) > 0.2 * referenceHz[i]) {
      ++grossErrors_;
      continue;
    }
    const double cents = 1200.0 * std::log2(estimateHz[i] / referenceHz[i]);
    ++fineCount_;
    fineSum_ += cents;
    fineSquares_ += cents * cents;
    fineAbsSum_ += std::abs(cents);
  }
}

void PitchScore::merge(const PitchScore& other) {
  frames_ += other.frames_;
  voicingErrors_ += other.voicingErrors_;
  missedVoicing_ += other.missedVoicing_;
  voicedBoth_ += other.voicedBoth_;
  grossErrors_ += other.grossErrors_;
  fineCount_ += other.fineCount_;
  fineSum_ += other.fineSum_;
  fineSquares_ += other.fineSquares_;
  fineAbsSum_ += other.fineAbsSum_;
}

double PitchScore::fineMeanCents() const {
  return fineCount_ > 0 ? fineSum_ / static_cast<double>(fineCount_) : 0.0;
}
double PitchScore::fineMeanAbsCents() const {
  return fineCount_ > 0 ? fineAbsSum_ / static_cast<double>(fineCount_) : 0.0;
}
double PitchScore::fineStdCents() const {
  if (fineCount_ < 2) return 0.0;
  const double mean = fineMeanCents();
  return std::sqrt(std::max(0.0, fineSquares_ / static_cast<double>(fineCount_) - mean * mean));
}

}  // namespace th::eval
