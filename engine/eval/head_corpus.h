// The head-motion corpora: recorded head rotations beside the prosody of the synchronous speech, frame for
// frame at 30 fps, per speaker (animation/head_data.h's HeadRecording).
//
//   th::animation::HeadRecording take = th::eval::loadBeat2Head();            // ../shared/data/beat2
//   std::vector<th::animation::HeadRecording> clips = th::eval::loadStyleTalkHeads();
//
// Sets: BEAT2's speaker "scott" (63.5 s; neck+head rotations relative to the torso, from motion capture) and
// StyleTalk's 6 clips of Obama, KristiNoem and andrew (117 s; head pose of a 3DMM fitted to the video, smoothed
// over a frame to take out the fit's frame-to-frame jitter).
// Thread contract: pure functions of files.
#pragma once

#include <filesystem>
#include <vector>

#include "animation/head_data.h"

namespace th::eval {

// The BEAT2 take in the shared data folder (speaker "scott").
animation::HeadRecording loadBeat2Head(const animation::ProsodyOptions& prosody = {});

// Every `NAME_headpose_30fps.csv` with its `NAME.wav` in talking/styletalk, by name; the speaker is the name
// before "_clip" (Obama_clip2 → Obama).
std::vector<animation::HeadRecording> loadStyleTalkHeads(const animation::ProsodyOptions& prosody = {});

}  // namespace th::eval
