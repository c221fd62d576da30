// A recording's speech features written out (`talkinghead features IN -o OUT.csv|json`): one row per animation
// frame, time first, as CSV or JSON (with the look-ahead of each feature), or without a file a summary to read
// (source, frames, voicing, F0 range and a coarse F0 contour).
//
//   th::pipeline::writeRecordingFeatures({.input = "speech.wav", .output = "speech.csv"}, std::cout, std::cerr);
//
// Thread contract: pure functions of their arguments and the files they name.
#pragma once

#include <ostream>
#include <string>

#include "audio/audio_file.h"
#include "features/online_features.h"

namespace th::pipeline {

struct FeatureOutput {
  std::string input;            // a recording (audio/media_audio.h: any sound file, a video's or an MP3's sound)
  std::string output;           // CSV or JSON to write (atomically); empty: the summary
  std::string format = "auto";  // csv, json, or auto (from the output's extension)
  features::FeatureOptions options = features::batchFeatureOptions();
};

// The output is opened first, so that an unwritable path fails before any work; "wrote N frames" on `log`, or
// the summary on `summary`.
void writeRecordingFeatures(const FeatureOutput& request, std::ostream& summary, std::ostream& log);

// time_s, then the layout's column names; a row per frame.
void writeFeaturesCsv(std::ostream& out, const features::FeatureMatrix& matrix);
// {frames_per_second, num_frames, columns, lookahead_ms, frames: [[time, values...], ...]} on one line.
void writeFeaturesJson(std::ostream& out, const features::FeatureMatrix& matrix,
                       const features::FeatureLookahead& lookahead);
void writeFeatureSummary(std::ostream& out, const std::string& input, const audio::AudioClip& clip,
                         const features::FeatureMatrix& matrix, const features::FeatureLookahead& lookahead);

}  // namespace th::pipeline
