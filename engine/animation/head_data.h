// The head-motion training data: BEAT2's neck+head rotations (relative to the torso) and the prosody of the
// synchronous recording, frame for frame at 30 fps, and the time split into a training and a held-out part.
//
//   th::animation::HeadRecording take = th::animation::loadBeat2Head();          // ../shared/data/beat2
//   auto [train, test] = th::animation::splitByTime(take, 0.75);
//
// Frame i of both streams is at i / 30 s (the feature extractor centres frame i there; the mocap's frame i is
// sampled there). The longer stream is cut to the shorter (the audio runs 0.6 s past the last mocap frame).
// Thread contract: pure functions of files.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <utility>

#include "animation/prosody.h"

namespace th::animation {

struct HeadRecording {
  double framesPerSecond = 30.0;
  double startSeconds = 0.0;    // time of column 0 in the original take
  Eigen::MatrixXd rotations;    // 3 x T: pitch, yaw, roll in degrees (neck+head relative to the torso)
  Eigen::MatrixXd prosody;      // 4 x T: ProsodyTracker output
  int numFrames() const { return static_cast<int>(rotations.cols()); }
};

// Reads a head-pose CSV (columns neckhead_pitch_deg, neckhead_yaw_deg, neckhead_roll_deg at 30 fps) and a
// recording of the same take. Errors name the file.
HeadRecording loadHeadRecording(const std::filesystem::path& wav, const std::filesystem::path& headPoseCsv,
                                const ProsodyOptions& prosody = {});

// The BEAT2 take in the shared data folder.
HeadRecording loadBeat2Head(const ProsodyOptions& prosody = {});

// Frames [0, fraction·T) and [fraction·T, T). The prosody of the second part was computed on the whole take,
// so its running normalisations start warm, as they would be a minute into a live session.
std::pair<HeadRecording, HeadRecording> splitByTime(const HeadRecording& take, double trainingFraction);

}  // namespace th::animation
