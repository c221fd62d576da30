// A FAP track: MPEG-4 FAP curves over time at a frame rate. What the speech models make, the file formats read
// and write (formats/), the renderer plays and the trackers fit: the one animation type between stages.
//
//   th::face::FapTrack track;
//   track.faps = {3, 48, 49, 50};
//   track.values = Eigen::MatrixXd::Zero(4, numFrames);   // one row per FAP, one column per frame
//   th::face::FapFrame faps = track.at(1.25);              // every FAP at 1.25 s, interpolated
//
// Orientation: like every sequence of frames passed between stages (features, HMM observations, visual
// parameters), a track holds one frame per column (Eigen's column-major storage keeps a frame contiguous).
// Frame i is at i / framesPerSecond seconds. Values are FAP values: counts of the FAP's unit (fap.h), so they
// mean the same on any face.
// Thread contract: a value type.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "face/fap.h"
#include "face/visemes.h"

namespace th::face {

struct FapTrack {
  double framesPerSecond = 30.0;
  std::string name = "talkinghead";  // a file's title (the .fap header's NAME)
  std::vector<int> faps;             // FAP numbers of the rows: ascending, unique, each in 1..68
  Eigen::MatrixXd values;            // faps.size() x numFrames
  // The mouth's visemes on the same frames, where a viseme model made them (the viseme and mouth-cue formats
  // write them); empty otherwise. Not read back from files.
  VisemeTrack visemes;
  std::string source;  // the recording it was made from, absolute, where known (Rhubarb's formats name it)

  int numFrames() const { return static_cast<int>(values.cols()); }
  double durationSeconds() const { return numFrames() / framesPerSecond; }
  // The row of a FAP, or -1 if the track does not carry it.
  int rowOf(int fap) const;
  // Frame `index` as a FapFrame; FAPs the track does not carry are 0.
  FapFrame frame(int index) const;
  // The FAPs at any time, for rendering at another frame rate: linear between the two nearest frames; before
  // the first frame the first, after the last the last. All 0 for an empty track.
  FapFrame at(double seconds) const;
};

}  // namespace th::face
