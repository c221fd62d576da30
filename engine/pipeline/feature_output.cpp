#include "pipeline/feature_output.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "audio/media_audio.h"
#include "core/atomic_file.h"

namespace th::pipeline {

void writeRecordingFeatures(const FeatureOutput& request, std::ostream& summary, std::ostream& log) {
  std::string format = request.format;
  if (format == "auto") {
    format = request.output.size() >= 5 && request.output.substr(request.output.size() - 5) == ".json" ? "json" : "csv";
  }
  // Open the output first so that an unwritable path fails before any work is done.
  std::unique_ptr<AtomicFile> output;
  if (!request.output.empty()) output = std::make_unique<AtomicFile>(request.output);

  const audio::AudioClip clip = audio::readRecording(request.input);
  const features::FeatureMatrix matrix = features::computeFeatures(clip.samples, request.options);
  const features::OnlineFeatureExtractor probe(request.options);
  if (!output) {
    writeFeatureSummary(summary, request.input, clip, matrix, probe.lookahead());
    return;
  }
  if (format == "json") {
    writeFeaturesJson(output->stream(), matrix, probe.lookahead());
  } else {
    writeFeaturesCsv(output->stream(), matrix);
  }
  output->commit();
  log << "wrote " << matrix.numFrames() << " frames to " << request.output << '\n';
}

void writeFeaturesCsv(std::ostream& out, const features::FeatureMatrix& matrix) {
  out << "time_s";
  for (const auto& name : matrix.layout.columnNames()) out << ',' << name;
  out << '\n';
  out << std::setprecision(7);
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    out << std::fixed << std::setprecision(6) << frame / matrix.framesPerSecond << std::defaultfloat
        << std::setprecision(7);
    for (float value : matrix.row(frame)) out << ',' << value;
    out << '\n';
  }
}

void writeFeaturesJson(std::ostream& out, const features::FeatureMatrix& matrix,
                       const features::FeatureLookahead& lookahead) {
  nlohmann::json document;
  document["frames_per_second"] = matrix.framesPerSecond;
  document["num_frames"] = matrix.numFrames();
  std::vector<std::string> columns = {"time_s"};
  const auto names = matrix.layout.columnNames();
  columns.insert(columns.end(), names.begin(), names.end());
  document["columns"] = columns;
  document["lookahead_ms"] = {{"f0", lookahead.f0Ms},           {"energy", lookahead.energyMs},
                              {"mfcc", lookahead.mfccMs},       {"deltas", lookahead.deltasMs},
                              {"context", lookahead.contextMs}, {"total", lookahead.totalMs}};
  nlohmann::json rows = nlohmann::json::array();
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    nlohmann::json row = nlohmann::json::array();
    row.push_back(frame / matrix.framesPerSecond);
    for (float value : matrix.row(frame)) row.push_back(value);
    rows.push_back(std::move(row));
  }
  document["frames"] = std::move(rows);
  out << document.dump() << '\n';
}

void writeFeatureSummary(std::ostream& out, const std::string& input, const audio::AudioClip& clip,
                         const features::FeatureMatrix& matrix, const features::FeatureLookahead& lookahead) {
  std::vector<float> voiced;
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    const float f0 = matrix.row(frame)[features::FeatureLayout::kF0Hz];
    if (f0 > 0) voiced.push_back(f0);
  }
  std::sort(voiced.begin(), voiced.end());
  const auto quantile = [&](double q) {
    return voiced.empty() ? 0.0f : voiced[static_cast<size_t>(q * static_cast<double>(voiced.size() - 1))];
  };
  out << std::fixed << std::setprecision(1);
  out << input << '\n'
      << "  source: " << clip.sourceRateHz << " Hz, " << clip.sourceChannels << " channel(s), " << std::setprecision(2)
      << clip.durationSeconds() << " s -> 16 kHz mono\n"
      << std::setprecision(1) << "  frames: " << matrix.numFrames() << " at " << matrix.framesPerSecond << " fps, "
      << matrix.layout.size() << " values per frame (f0, energy, 2 deltas, " << matrix.layout.numMfcc << " MFCC, +-"
      << matrix.layout.contextFrames << " frames of MFCC context)\n"
      << "  voiced: " << (matrix.numFrames() ? 100.0 * static_cast<double>(voiced.size()) / matrix.numFrames() : 0.0)
      << " % of frames; F0 median " << quantile(0.5) << " Hz, 5-95 % range " << quantile(0.05) << "-" << quantile(0.95)
      << " Hz\n"
      << "  look-ahead (ms): F0 " << lookahead.f0Ms << ", energy " << lookahead.energyMs << ", MFCC "
      << lookahead.mfccMs << ", deltas " << lookahead.deltasMs << ", context " << lookahead.contextMs
      << "; whole frame " << lookahead.totalMs << " (" << lookahead.totalFrames << " frames)\n";
  // A coarse picture of the F0 contour: one character per 100 ms, height by F0, '.' unvoiced.
  std::string contour;
  const int step = std::max(1, static_cast<int>(std::lround(matrix.framesPerSecond / 10.0)));
  const float low = quantile(0.05);
  const float high = std::max(quantile(0.95), low + 1.0f);
  const std::string levels = "_-=^";
  for (int frame = 0; frame < matrix.numFrames() && contour.size() < 100; frame += step) {
    const float f0 = matrix.row(frame)[features::FeatureLayout::kF0Hz];
    if (f0 <= 0) {
      contour += '.';
    } else {
      const int level = std::clamp(static_cast<int>((f0 - low) / (high - low) * 4.0f), 0, 3);
      contour += levels[static_cast<size_t>(level)];
    }
  }
  out << "  F0 contour (100 ms per character): " << contour << '\n';
}

}  // namespace th::pipeline
