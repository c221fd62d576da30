// Animation files: FAP curves per frame, as CSV, JSON or an MPEG-4 FAP stream (.fap), chosen by extension.
//
//   th::video::Animation anim;
//   anim.faps = {3, 48, 49, 50};
//   anim.values = Eigen::MatrixXd::Zero(numFrames, 4);           // frames x FAPs, in FAPU counts
//   th::video::writeAnimation("out.fap", anim);                   // atomic: all or nothing
//   th::video::Animation back = th::video::readAnimation("out.csv");
//
// Formats (all three read and write):
//   .csv   header `time_s,fap3,fap48,...` (the FAP columns in ascending order), one row per frame; time_s is
//          frame / fps. Reading takes the frame rate from the time column (frames must be evenly spaced).
//   .json  {"format": "talkinghead-animation", "version": 1, "fps": 30, "name": "...",
//           "faps": [{"number": 3, "name": "open_jaw", "unit": "MNS"}, ...],
//           "time_s": [...], "frames": [[v3, v48, ...], ...]}
//   .fap   the MPEG-4 FAP stream text that Xface and Greta read: a header line `2.1 NAME FPS NFRAMES`, then per
//          frame a mask line of 68 `0`/`1` flags (FAP 1..68) and a line with the frame number and the integer
//          values of the flagged FAPs in FAP order. Writing rounds values to integers and flags every column of
//          the animation in every frame. Reading accepts masks that change between frames: a FAP not sent in
//          a frame holds its last value (0 before it is first sent), and the columns are every FAP sent at
//          least once. Blank lines and lines starting with '#' are skipped.
// Values are FAP values: counts of the FAP's unit (face/fap.h), so they mean the same on any face.
// Errors (th::Error) are one line that names the file and, when reading, the line and what is wrong.
// Thread contract: pure functions of files.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace th::video {

struct Animation {
  double framesPerSecond = 30.0;
  std::string name = "talkinghead";  // the .fap header's NAME (spaces become '_' when written)
  std::vector<int> faps;             // FAP numbers of the columns: ascending, unique, each in 1..68
  Eigen::MatrixXd values;            // numFrames x faps.size()
  int numFrames() const { return static_cast<int>(values.rows()); }
  // The column of a FAP, or -1 if the animation does not carry it.
  int columnOf(int fap) const;
};

enum class AnimationFormat { kCsv, kJson, kFap };

// By the extension (case-insensitive .csv, .json, .fap); throws th::Error naming the file otherwise.
AnimationFormat animationFormatOf(const std::filesystem::path& path);

// Checks the animation (positive finite fps, FAP numbers valid/ascending/unique, values finite and sized to
// the columns); throws th::Error naming the file if it is not, before anything is written.
void writeAnimation(const std::filesystem::path& path, const Animation& animation);

Animation readAnimation(const std::filesystem::path& path);

}  // namespace th::video
