// Made-up speech frames for the animation stages' tests: levels around -30 dB and MFCCs of spread 5, seeded, so
// that a stage's contract can be checked without a recording.
#pragma once

#include <random>
#include <vector>

#include "animation/online_stages.h"

namespace th::test {

inline std::vector<animation::SpeechFrame> madeUpSpeech(int frames, int mfcc, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<animation::SpeechFrame> speech(static_cast<std::size_t>(frames));
  for (animation::SpeechFrame& frame : speech) {
    frame.levelDb = -30.0 + 10.0 * noise(random);
    frame.mfcc = Eigen::VectorXd::NullaryExpr(mfcc, [&] { return 5.0 * noise(random); });
  }
  return speech;
}

}  // namespace th::test
