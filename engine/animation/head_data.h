// The head-motion training data: recorded head rotations and the prosody of the synchronous speech, frame for
// frame at 30 fps, per speaker, and the time split into a training and a held-out part.
//
//   th::animation::HeadRecording take = th::animation::loadBeat2Head();          // ../shared/data/beat2
//   std::vector<th::animation::HeadRecording> clips = th::animation::loadStyleTalkHeads();
//   auto [train, test] = th::animation::splitByTime(take, 0.75);
//
// Sets: BEAT2's speaker "scott" (63.5 s; neck+head rotations relative to the torso, from motion capture) and
// StyleTalk's 6 clips of Obama, KristiNoem and andrew (117 s; head pose of a 3DMM fitted to the video, smoothed
// over a frame to take out the fit's frame-to-frame jitter). The two
// measure rotation from different rest poses, which is why models normalise each speaker's motion (head_model.h).
// Frame i of both streams is at i / 30 s (the feature extractor centres frame i there; the pose's frame i is
// sampled there). The longer stream is cut to the shorter.
// Thread contract: pure functions of files.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "animation/prosody.h"
#include "animation/time_split.h"

namespace th::animation {

struct HeadRecording {
  std::string speaker;          // who speaks ("scott", "Obama", ...): models normalise per speaker
  std::string name;             // the clip
  double framesPerSecond = 30.0;
  double startSeconds = 0.0;    // time of column 0 in the original take
  Eigen::MatrixXd rotations;    // 3 x T: pitch, yaw, roll in degrees
  Eigen::MatrixXd prosody;      // 4 x T: ProsodyTracker output
  Eigen::RowVectorXd voiced;    // T: 1 where the pitch tracker found a voice, else 0
  Eigen::RowVectorXd levelDb;   // T: the sound's level, dB re full scale (animation/mouth_data.h's)
  int numFrames() const { return static_cast<int>(rotations.cols()); }
};

// Reads a head-pose CSV at 30 fps — columns neckhead_{pitch,yaw,roll}_deg (BEAT2) or {pitch,yaw,roll}_deg
// (StyleTalk) — and a recording of the same take. Errors name the file.
HeadRecording loadHeadRecording(const std::filesystem::path& wav, const std::filesystem::path& headPoseCsv,
                                const ProsodyOptions& prosody = {});

// The BEAT2 take in the shared data folder (speaker "scott").
HeadRecording loadBeat2Head(const ProsodyOptions& prosody = {});

// Every `NAME_headpose_30fps.csv` with its `NAME.wav` in talking/styletalk, by name; the speaker is the name
// before "_clip" (Obama_clip2 → Obama).
std::vector<HeadRecording> loadStyleTalkHeads(const ProsodyOptions& prosody = {});

// Each row smoothed with a Gaussian of sigmaFrames (edges: the edge frame repeated). d x T in, d x T out.
Eigen::MatrixXd smoothFrames(const Eigen::MatrixXd& frames, double sigmaFrames);

// Frames [begin, begin + count) of a recording (time_split.h's splitByTime cuts a take in two with it; the
// prosody of the second part was computed on the whole take, so its running normalisations start warm, as
// they would be a minute into a live session).
HeadRecording framesOf(const HeadRecording& take, int begin, int count);

}  // namespace th::animation
