// The head-motion training data: recorded head rotations and the prosody of the synchronous speech, frame for
// frame at 30 fps, per speaker, and the time split into a training and a held-out part.
//
//   th::animation::HeadRecording take = th::eval::loadBeat2Head();      // the corpora's loaders: eval/head_corpus.h
//   auto [train, test] = th::animation::splitByTime(take, 0.75);
//
// Sets measure rotation from different rest poses, which is why models normalise each speaker's motion
// (head_model.h). Frame i of both streams is at i / 30 s (the feature extractor centres frame i there; the pose's frame
// i is sampled there). The longer stream is cut to the shorter. Thread contract: pure functions of files.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "animation/prosody.h"
#include "animation/time_split.h"

namespace th::animation {

inline constexpr double kHeadFramesPerSecond = 30.0;  // the frame rate of every head stream here

struct HeadRecording {
  std::string speaker;  // who speaks ("scott", "Obama", ...): models normalise per speaker
  std::string name;     // the clip
  double framesPerSecond = kHeadFramesPerSecond;
  double startSeconds = 0.0;   // time of column 0 in the original take
  Eigen::MatrixXd rotations;   // 3 x T: pitch, yaw, roll in degrees
  Eigen::MatrixXd prosody;     // 4 x T: ProsodyTracker output
  Eigen::RowVectorXd voiced;   // T: 1 where the pitch tracker found a voice, else 0
  Eigen::RowVectorXd levelDb;  // T: the sound's level, dB re full scale (animation/mouth_data.h's)
  int numFrames() const { return static_cast<int>(rotations.cols()); }
};

// Each row smoothed with a Gaussian of sigmaFrames (edges: the edge frame repeated). d x T in, d x T out.
Eigen::MatrixXd smoothFrames(const Eigen::MatrixXd& frames, double sigmaFrames);

// Frames [begin, begin + count) of a recording (time_split.h's splitByTime cuts a take in two with it; the
// prosody of the second part was computed on the whole take, so its running normalisations start warm, as
// they would be a minute into a live session).
HeadRecording framesOf(const HeadRecording& take, int begin, int count);

// A take from its head rotations (3 x N, degrees, at poseFps frames a second from 0 s) and its sound (mono,
// 16 kHz): the rotations at 30 fps (taken as they are when poseFps is 30, else linear between pose frames, the
// last held no further than the pose goes) beside the prosody, voicing and level of the sound; both cut to the
// shorter. Throws th::Error naming `name` when fewer than two frames are left.
HeadRecording headRecordingOf(const Eigen::MatrixXd& rotations, double poseFps, std::span<const float> samples16k,
                              const std::string& name, const ProsodyOptions& prosody = {});

// A head-pose CSV and the recording of the same take. The rotation columns are {pitch,yaw,roll}_deg (what
// `talkinghead track` writes; StyleTalk's) or neckhead_{pitch,yaw,roll}_deg (BEAT2's); the rate is time_s's
// (30 fps without that column). A track's rows where no face was found (its `face` column 0) hold a neighbour's
// pose; fewer than half of them with a face is an error. Errors are one line naming the file.
HeadRecording readHeadRecording(const std::filesystem::path& wav, const std::filesystem::path& poseCsv,
                                const ProsodyOptions& prosody = {});

}  // namespace th::animation
