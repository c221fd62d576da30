// Scoring an F0 track against a reference (FFE, GPE, VDE, fine error), the way pitch-tracking papers do.
//
//   th::features::PitchScore score;
//   score.add(reference /* Hz, 0 = unvoiced */, estimate /* same times */);
//   score.ffe();   // (voicing errors + gross errors) / all frames
//
// Definitions (Chu & Alwan 2009, "Reducing F0 frame error of F0 tracking algorithms under noisy conditions"):
//   VDE = frames whose voicing decision differs / all frames;
//   GPE = frames voiced in both with |f - f_ref| > 20 % f_ref / frames voiced in both;
//   FFE = (voicing errors + gross pitch errors) / all frames;
//   fine error = mean and standard deviation of 1200 log2(f / f_ref) (cents) over voiced-both frames without
//   a gross error.
// Thread contract: plain value type.
#pragma once

#include <filesystem>
#include <span>
#include <vector>

namespace th::eval {

struct F0Track {
  std::vector<double> timesSeconds;  // increasing
  std::vector<double> f0Hz;          // 0 = unvoiced
};

// The track's value at each time: the nearest frame's value, or unvoiced if no frame lies within
// maxDistanceSeconds (frames past the end of a track count as unvoiced).
std::vector<double> sampleTrackAt(const F0Track& track, std::span<const double> timesSeconds,
                                  double maxDistanceSeconds);

// One value per line in Hz, frame i at i * frameShiftSeconds (the FDA .f0ref format).
F0Track readReferenceF0(const std::filesystem::path& path, double frameShiftSeconds);

class PitchScore {
 public:
  void add(std::span<const double> referenceHz, std::span<const double> estimateHz);
  void merge(const PitchScore& other);

  long long frames() const { return frames_; }
  double vde() const { return ratio(voicingErrors_, frames_); }
  double gpe() const { return ratio(grossErrors_, voicedBoth_); }
  double ffe() const { return ratio(voicingErrors_ + grossErrors_, frames_); }
  double fineMeanCents() const;
  double fineStdCents() const;
  double fineMeanAbsCents() const;
  // The two kinds of voicing error, over all frames.
  double missedVoicing() const { return ratio(missedVoicing_, frames_); }
  double falseVoicing() const { return ratio(voicingErrors_ - missedVoicing_, frames_); }

 private:
  static double ratio(long long numerator, long long denominator) {
    return denominator > 0 ? static_cast<double>(numerator) / static_cast<double>(denominator) : 0.0;
  }
  long long frames_ = 0;
  long long voicingErrors_ = 0;
  long long missedVoicing_ = 0;  // reference voiced, estimate unvoiced
  long long voicedBoth_ = 0;
  long long grossErrors_ = 0;
  long long fineCount_ = 0;
  double fineSum_ = 0.0;
  double fineSquares_ = 0.0;
  double fineAbsSum_ = 0.0;
};

}  // namespace th::eval
