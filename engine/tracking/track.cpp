#include "tracking/track.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.h"
#include "core/numeric_csv.h"
#include "face/fap.h"
#include "tracking/video_reader.h"

namespace th::tracking {

int Track::framesFound() const {
  int found = 0;
  for (const TrackedFrame& frame : frames) found += frame.found ? 1 : 0;
  return found;
}

Track trackVideo(const std::filesystem::path& video, const TrackOptions& options,
                 const std::function<void(double)>& progress) {
  VideoReader reader(video);
  LandmarkDetector detector(options.landmarks);
  Track track;
  track.video = video;
  track.framesPerSecond = reader.framesPerSecond();
  track.width = reader.width();
  track.height = reader.height();
  if (reader.frameCountHint() > 0) track.frames.reserve(static_cast<std::size_t>(reader.frameCountHint()));
  cv::Mat image;
  double seconds = 0.0;
  while (reader.read(image, seconds)) {
    TrackedFrame frame;
    frame.seconds = seconds;
    frame.found = detector.find(image, frame.landmarks);
    track.frames.push_back(frame);
    if (progress) progress(static_cast<double>(track.frames.size()) / track.framesPerSecond);
  }
  track.fullSearches = detector.fullSearches();
  if (track.framesFound() == 0)
    throw fileError(video, "no face found in any of its " + std::to_string(track.frames.size()) + " frames");

  if (options.smooth) {
    std::vector<Landmarks> points;
    std::vector<bool> found;
    points.reserve(track.frames.size());
    found.reserve(track.frames.size());
    for (const TrackedFrame& frame : track.frames) {
      points.push_back(frame.landmarks);
      found.push_back(frame.found);
    }
    smoothLandmarks(points, found);
    for (std::size_t f = 0; f < points.size(); ++f) track.frames[f].landmarks = points[f];
  }
  // Frames without a face take the nearest frame's landmarks that has one (the earlier one on a tie).
  const std::size_t n = track.frames.size();
  std::vector<long> nearest(n, -1);
  long last = -1;
  for (std::size_t f = 0; f < n; ++f) {
    if (track.frames[f].found) last = static_cast<long>(f);
    nearest[f] = last;
  }
  long next = -1;
  for (std::size_t i = n; i-- > 0;) {
    if (track.frames[i].found) next = static_cast<long>(i);
    const long before = nearest[i];
    const long f = static_cast<long>(i);
    if (before < 0 || (next >= 0 && next - f < f - before)) nearest[i] = next;
  }
  for (std::size_t f = 0; f < n; ++f)
    if (!track.frames[f].found)
      track.frames[f].landmarks = track.frames[static_cast<std::size_t>(nearest[f])].landmarks;
  return track;
}

void fitTrack(Track& track, const face::FaceModel& face, const FitOptions& options, int restFrame) {
  if (track.frames.empty()) throw Error("fitTrack: the track has no frames");
  if (restFrame >= static_cast<int>(track.frames.size()) ||
      (restFrame >= 0 && !track.frames[static_cast<std::size_t>(restFrame)].found))
    throw Error("fitTrack: the rest frame " + std::to_string(restFrame) + " is not a frame with a face");
  FitOptions withCentre = options;
  if (!withCentre.principalPoint.allFinite() && track.width > 0 && track.height > 0)
    withCentre.principalPoint = Eigen::Vector2d(0.5 * track.width, 0.5 * track.height);
  FaceFitter fitter(face, withCentre);
  int neutral = restFrame;
  for (std::size_t f = 0; f < track.frames.size() && restFrame < 0; ++f)
    if (track.frames[f].found &&
        (neutral < 0 || mouthOpening(track.frames[f].landmarks) <
                            mouthOpening(track.frames[static_cast<std::size_t>(neutral)].landmarks)))
      neutral = static_cast<int>(f);
  if (neutral < 0) throw fileError(track.video, "no frame has a face to fit");
  const FaceFit rest = fitter.calibrate(track.frames[static_cast<std::size_t>(neutral)].landmarks);
  const FaceFit* previous = &rest;
  for (TrackedFrame& frame : track.frames) {
    frame.fit = fitter.fit(frame.landmarks, previous);
    previous = &frame.fit;
  }
  track.fittedFaps = fitter.options().faps;
  track.neutralFrame = neutral;
}

namespace {

using face::kDegreesPerAngleUnit;

std::vector<std::string> trackColumns(const std::vector<int>& fittedFaps, bool fitted) {
  std::vector<std::string> columns{"time_s", "face"};
  if (fitted) {
    for (const char* angle : {"pitch_deg", "yaw_deg", "roll_deg"}) columns.emplace_back(angle);
    for (int fap : fittedFaps) columns.push_back("fap" + std::to_string(fap));
    columns.emplace_back("residual_px");
  }
  for (int i = 0; i < kNumLandmarks; ++i) {
    columns.push_back("x" + std::to_string(i));
    columns.push_back("y" + std::to_string(i));
  }
  return columns;
}

}  // namespace

void writeTrackCsv(const std::filesystem::path& path, const Track& track) {
  const bool fitted = !track.fittedFaps.empty();
  std::vector<std::vector<double>> rows;
  rows.reserve(track.frames.size());
  for (const TrackedFrame& frame : track.frames) {
    std::vector<double> row{frame.seconds, frame.found ? 1.0 : 0.0};
    if (fitted) {
      for (int fap : {48, 49, 50}) row.push_back(frame.fit.faps[static_cast<std::size_t>(fap)] * kDegreesPerAngleUnit);
      for (int fap : track.fittedFaps) row.push_back(frame.fit.faps[static_cast<std::size_t>(fap)]);
      row.push_back(frame.fit.residualPixels);
    }
    for (int i = 0; i < kNumLandmarks; ++i) {
      row.push_back(frame.landmarks(0, i));
      row.push_back(frame.landmarks(1, i));
    }
    rows.push_back(std::move(row));
  }
  writeNumericCsv(path, trackColumns(track.fittedFaps, fitted), rows);
}

Track readTrackCsv(const std::filesystem::path& path) {
  const NumericTable table = readNumericCsv(path);
  const auto at = [&](const std::vector<double>& row, int column) { return row[static_cast<std::size_t>(column)]; };
  const int time = table.column("time_s");
  const int face = table.column("face");
  std::vector<int> x(kNumLandmarks), y(kNumLandmarks);
  for (int i = 0; i < kNumLandmarks; ++i) {
    x[static_cast<std::size_t>(i)] = table.column("x" + std::to_string(i));
    y[static_cast<std::size_t>(i)] = table.column("y" + std::to_string(i));
  }
  if (table.rows.size() < 2) throw fileError(path, "a track needs at least two frames");
  Track track;
  track.video = path;
  // Fits, where the file has them: every fapN column.
  const bool fitted = table.findColumn("residual_px") >= 0;
  std::vector<std::pair<int, int>> fapColumns;  // FAP, column
  if (fitted) {
    for (std::size_t c = 0; c < table.columns.size(); ++c)
      if (const std::string& name = table.columns[c];
          name.size() > 3 && name.size() < 6 && name.rfind("fap", 0) == 0 &&
          std::all_of(name.begin() + 3, name.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; })) {
        const int fap = std::stoi(name.substr(3));
        if (fap < 1 || fap > face::kNumFaps) throw fileError(path, "column " + table.columns[c] + " is not a FAP");
        fapColumns.emplace_back(fap, static_cast<int>(c));
        track.fittedFaps.push_back(fap);
      }
  }
  for (const std::vector<double>& row : table.rows) {
    TrackedFrame frame;
    frame.seconds = at(row, time);
    frame.found = at(row, face) != 0.0;
    for (int i = 0; i < kNumLandmarks; ++i) {
      frame.landmarks(0, i) = at(row, x[static_cast<std::size_t>(i)]);
      frame.landmarks(1, i) = at(row, y[static_cast<std::size_t>(i)]);
    }
    if (fitted) {
      frame.fit.faps[48] = at(row, table.column("pitch_deg")) / kDegreesPerAngleUnit;
      frame.fit.faps[49] = at(row, table.column("yaw_deg")) / kDegreesPerAngleUnit;
      frame.fit.faps[50] = at(row, table.column("roll_deg")) / kDegreesPerAngleUnit;
      for (const auto& [fap, column] : fapColumns) frame.fit.faps[static_cast<std::size_t>(fap)] = at(row, column);
      frame.fit.residualPixels = at(row, table.column("residual_px"));
    }
    if (!track.frames.empty() && !(frame.seconds > track.frames.back().seconds))
      throw fileError(path,
                      "times must increase from row to row (row " + std::to_string(track.frames.size() + 1) + ")");
    track.frames.push_back(frame);
  }
  track.framesPerSecond = 1.0 / (track.frames[1].seconds - track.frames[0].seconds);
  return track;
}

double mouthOpening(const Landmarks& landmarks) {
  const auto gap = [&](int a, int b) { return (landmarks.col(a) - landmarks.col(b)).norm(); };
  const double eyes = gap(36, 45);
  if (!(eyes > 0.0)) return 0.0;
  return (gap(61, 67) + gap(62, 66) + gap(63, 65)) / (3.0 * eyes);
}

double mouthWidth(const Landmarks& landmarks) {
  const double eyes = (landmarks.col(36) - landmarks.col(45)).norm();
  return eyes > 0.0 ? (landmarks.col(48) - landmarks.col(54)).norm() / eyes : 0.0;
}

}  // namespace th::tracking
