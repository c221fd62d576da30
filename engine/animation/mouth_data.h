// The mouth model's data: per frame at 30 fps, the visual parameters (BEAT2's jaw opening and 100 FLAME
// expression coefficients, or tracked FAPs) and the speech frames of the synchronous recording.
//
//   th::animation::MouthRecording take = th::eval::loadBeat2Mouth();     // the loaders: eval/mouth_corpus.h
//   auto [train, test] = th::animation::splitByTime(take, 0.75);
//   Eigen::MatrixXd audio = th::features::stackContext(train.speech.mfcc, 3);   // 11·7 x T
//
// Frame i of both streams is at i / 30 s, as for the head (head_data.h); the longer stream is cut to the
// shorter. The jaw opening is the x component of the SMPL-X jaw axis-angle (degrees; positive opens).
// Thread contract: pure functions of files.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <span>
#include <utility>

#include "animation/time_split.h"
#include "features/online_features.h"

namespace th::animation {

// The mouth's frame rate: the animation's (animate.h).
inline constexpr double kMouthFramesPerSecond = 30.0;

// What the mouth model hears, per animation frame (30 fps): c1..c11 and the frame's level. Frame i is centred at
// i / 30 s (features/online_features.h).
struct SpeechFrames {
  Eigen::MatrixXd mfcc;        // 11 x T: c1..c11 (features/mfcc.h conventions)
  Eigen::RowVectorXd levelDb;  // T: dB re full scale, floored 60 dB below the loudest frame so far
  int numFrames() const { return static_cast<int>(mfcc.cols()); }
  SpeechFrames middleFrames(Eigen::Index first, Eigen::Index count) const;
};

struct MouthRecording {
  double framesPerSecond = 30.0;
  double startSeconds = 0.0;
  Eigen::MatrixXd visual;  // d x T: BEAT2's jaw opening (degrees) and expression coefficients e0..e99, or FAPs
  SpeechFrames speech;     // T frames
  int numFrames() const { return static_cast<int>(visual.cols()); }
};

// Speech frames alone, for synthesis and speech-only training: from 16 kHz samples, or from any recording (audio
// files through libsndfile, the audio track of videos such as GRID's .mpg through FFmpeg).
SpeechFrames speechFramesOf(std::span<const float> samples16k);
// The MFCCs and levels of feature rows already computed (features/online_features.h), c1..c11 from the rows.
SpeechFrames speechFramesOf(const features::FeatureMatrix& rows);
SpeechFrames speechFramesOf(const std::filesystem::path& recording);

// Frames [begin, begin + count) of a recording (time_split.h's splitByTime cuts a take in two with it).
MouthRecording framesOf(const MouthRecording& take, int begin, int count);

}  // namespace th::animation
