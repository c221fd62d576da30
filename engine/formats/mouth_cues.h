// Rhubarb Lip Sync's mouth cues (not a public API; the rhubarb-* and moho formats write them): the decoded
// mouth classes of a track (FapTrack::visemes) as runs of Rhubarb's shapes.
//
//   for (const MouthCue& cue : mouthCues(track)) out << centiseconds(cue.startCs) << '\t' << cue.shape << '\n';
//
// Times are in centiseconds, Rhubarb's unit: a cue starts where its first frame's interval does (frame i is
// centred at i / fps, as the speech features' frames are, and stands for half a frame either side), rounded to
// the nearest centisecond, and ends where the next starts; the last ends at the animation's end, truncated to 0.01 s,
// as Rhubarb truncates the recording's. Neighbouring classes with the same shape (DD then SS: both B) are one cue.
// Thread contract: pure functions.
#pragma once

#include <string>
#include <vector>

#include "face/fap_track.h"

namespace th::formats {

struct MouthCue {
  int startCs = 0;
  int endCs = 0;
  char shape = 'X';
};

std::vector<MouthCue> mouthCues(const face::FapTrack& track);
int durationCentiseconds(const face::FapTrack& track);
std::string centiseconds(int cs);  // "0.05", "12.30"

}  // namespace th::formats
