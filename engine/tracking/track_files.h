// A talking video's track and sound written beside each other (`talkinghead track VIDEO -o TRACK.csv`): the 68
// landmarks in every frame, the face model fitted to them (head rotation, jaw and lip FAPs) as CSV (track.h), and
// the video's sound as a 16-bit WAV. Both are written or neither.
//
//   th::tracking::writeTrackFiles({.video = "clip.mp4", .output = "clip.csv"}, std::cout, std::cerr);
//
// Thread contract: one call at a time (the tracking runs on threads of its own).
#pragma once

#include <ostream>
#include <string>

namespace th::tracking {

struct TrackFiles {
  std::string video;   // a video with a face, and a sound track or a WAV of its name beside it
  std::string output;  // the track (.csv)
  std::string audio;   // the sound (.wav); empty: the track's name with .wav
  bool smooth = true;  // each landmark's path smoothed over 5 frames (Savitzky-Golay)
};

// The outputs are checked first and the sound read before the (longer) tracking, so that a video without sound
// is refused at once. The progress on `log`, one line of what was written on `out`.
void writeTrackFiles(const TrackFiles& request, std::ostream& out, std::ostream& log);

}  // namespace th::tracking
