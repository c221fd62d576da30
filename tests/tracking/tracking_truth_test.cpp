// Truth we control: our own face, rendered off-screen with head rotations and FAPs from real animation curves,
// tracked with dlib and fitted. Two kinds of curves: the shipped models animating BEAT2 speech (the head moves
// a lot, the lips only with the jaw), and a real speaker's jaw and lips (a GRID clip tracked and fitted) with
// the head model's rotations on that clip's sound. The head's rotations come back within 2° per axis (root mean
// square over the frames), with either kind of curves. The jaw and lip FAPs' errors are printed as shares of
// each one's range, not held to 10 %, which dlib's landmarks on our rendered face do not allow
// (docs/tracking.md); from perfect landmarks the fit meets it (the last test).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "audio/audio_file.h"
#include "core/data_path.h"
#include "face/face_model.h"
#include "face/fap_track.h"
#include "pipeline/offline.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "tracking/track.h"
#include "tracking/video_training.h"

namespace {

double degrees(double angleUnits) {
  return angleUnits * th::face::kAngleUnit * 180.0 / std::numbers::pi;
}

const th::face::FaceModel& faceModel() {
  static const th::face::FaceModel face = th::face::FaceModel::buildDefault();
  return face;
}

std::filesystem::path modelFile(const char* name) {
  return std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "models" / name;
}

struct FapError {
  int fap = 0;
  double rms = 0.0;    // FAPU counts, or degrees for 48-50
  double range = 0.0;  // of the truth, likewise
};

// Renders every pose (after a rest frame, the tracker's neutral), tracks and fits the frames, and returns the
// RMS error of each fitted FAP that the poses move.
std::vector<FapError> renderTrackAndFit(const std::vector<th::face::FapFrame>& poses, double framesPerSecond) {
  const th::face::FaceModel& face = faceModel();
  constexpr int kWidth = 640, kHeight = 480;
  th::render::OffscreenContext context;
  th::render::FaceRenderer renderer(context, face.mesh(), {.width = kWidth, .height = kHeight});
  renderer.setMouthOpening(face.innerLipVertices());
  const th::render::OrbitCamera camera = th::render::frameHead(face.mesh().positions, double(kWidth) / kHeight);
  th::tracking::LandmarkDetector detector;
  th::tracking::Track track;
  track.framesPerSecond = framesPerSecond;
  track.width = kWidth;
  track.height = kHeight;
  std::vector<th::face::FapFrame> shown{th::face::FapFrame{}};
  shown.insert(shown.end(), poses.begin(), poses.end());
  for (std::size_t f = 0; f < shown.size(); ++f) {
    renderer.setPositions(face.deform(shown[f]));
    renderer.setPupilScale(face.pupilScale(shown[f]));
    const th::render::Image image = renderer.renderImage(camera);
    cv::Mat bgr;
    cv::cvtColor(cv::Mat(kHeight, kWidth, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data())), bgr,
                 cv::COLOR_RGB2BGR);
    th::tracking::TrackedFrame frame;
    frame.seconds = static_cast<double>(f) / framesPerSecond;
    frame.found = detector.find(bgr, frame.landmarks);
    EXPECT_TRUE(frame.found) << "no face found in rendered frame " << f;
    track.frames.push_back(frame);
  }
  {
    // Smoothed over time as trackVideo does (the rest frame, a still, left out).
    std::vector<th::tracking::Landmarks> points;
    std::vector<bool> found;
    for (std::size_t f = 1; f < track.frames.size(); ++f) {
      points.push_back(track.frames[f].landmarks);
      found.push_back(track.frames[f].found);
    }
    th::tracking::smoothLandmarks(points, found);
    for (std::size_t f = 1; f < track.frames.size(); ++f) track.frames[f].landmarks = points[f - 1];
  }
  // The renderer's camera: its focal length in pixels from its vertical field of view.
  th::tracking::FitOptions fitOptions;
  fitOptions.focalLengthPixels = 0.5 * kHeight / std::tan(0.5 * camera.fovYDegrees * std::numbers::pi / 180.0);
  fitOptions.principalPoint = {0.5 * kWidth, 0.5 * kHeight};
  th::tracking::fitTrack(track, face, fitOptions, 0);
  {
    // How far dlib's points lie from the model's own (projected with the rest frame's calibration), by group.
    th::tracking::FaceFitter calibrated(face, fitOptions);
    const th::tracking::FaceFit rest = calibrated.calibrate(track.frames[0].landmarks);
    const struct {
      const char* name;
      int first, last;
    } groups[] = {{"chin", 8, 8}, {"eyes", 36, 47}, {"nose", 27, 35}, {"outer lips", 48, 59}, {"inner lips", 60, 67}};
    for (const auto& group : groups) {
      double squared = 0.0;
      int count = 0;
      for (std::size_t f = 1; f < shown.size(); ++f) {
        th::tracking::FaceFit truthFit = rest;
        truthFit.faps = shown[f];
        const th::tracking::Landmarks want = calibrated.project(truthFit);
        for (int i = group.first; i <= group.last; ++i, ++count)
          squared += (track.frames[f].landmarks.col(i) - want.col(i)).squaredNorm();
      }
      std::printf("dlib's %s: %.1f px RMS from the model's (eye corners %.0f px apart)\n", group.name,
                  std::sqrt(squared / count),
                  (track.frames[0].landmarks.col(36) - track.frames[0].landmarks.col(45)).norm());
    }
  }

  std::vector<int> faps{48, 49, 50};
  faps.insert(faps.end(), track.fittedFaps.begin(), track.fittedFaps.end());
  std::vector<FapError> errors;
  for (int fap : faps) {
    const auto n = static_cast<std::size_t>(fap);
    const auto value = [&](double v) { return fap >= 48 && fap <= 50 ? degrees(v) : v; };
    double squared = 0.0, low = 1e300, high = -1e300;
    for (std::size_t f = 1; f < shown.size(); ++f) {
      const double want = value(shown[f][n]);
      squared += std::pow(value(track.frames[f].fit.faps[n]) - want, 2);
      low = std::min(low, want);
      high = std::max(high, want);
    }
    if (high - low <= 0.0) continue;  // a FAP these curves do not move
    errors.push_back({fap, std::sqrt(squared / static_cast<double>(shown.size() - 1)), high - low});
  }
  for (const FapError& e : errors)
    std::printf("FAP %2d: RMS error %7.2f %s, %5.1f %% of the truth's range %.2f\n", e.fap, e.rms,
                e.fap >= 48 && e.fap <= 50 ? "degrees" : "units", 100.0 * e.rms / e.range, e.range);
  return errors;
}

void expectRotationsWithin(double degreesRms, const std::vector<FapError>& errors) {
  int rotations = 0;
  for (const FapError& e : errors)
    if (e.fap >= 48 && e.fap <= 50) {
      EXPECT_LE(e.rms, degreesRms) << "FAP " << e.fap;
      ++rotations;
    }
  EXPECT_EQ(rotations, 3);
}

TEST(TrackingTruth, TheShippedModelsCurvesRotationsComeBackWithinTwoDegrees) {
  const th::animation::HeadModel head = th::animation::loadHeadModel(modelFile("head.json"));
  const th::animation::MouthModel mouth = th::animation::loadMouthModel(modelFile("mouth.json"));
  th::audio::AudioClip speech = th::audio::readAudioFile(th::sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav"));
  speech.samples.resize(std::min<std::size_t>(speech.samples.size(), 16000 * 5));  // 5 s: 150 frames
  const th::face::FapTrack truth =
      th::pipeline::animate(speech.samples, &head, &mouth, {.idle = false});  // no blinks: the fit has no lids
  std::vector<th::face::FapFrame> poses;
  for (int f = 0; f < truth.numFrames(); ++f) poses.push_back(truth.at(f / truth.framesPerSecond));
  expectRotationsWithin(2.0, renderTrackAndFit(poses, truth.framesPerSecond));
}

// A GRID clip's jaw and lips, as the tracker fitted them, at its 25 fps, with the head model's rotations on
// its sound (no blinks: the fit has no lids).
std::vector<th::face::FapFrame> realSpeakersPoses(const th::tracking::FitOptions& options, double& framesPerSecond) {
  const std::filesystem::path clip = th::sharedDataPath("grid/s1/bbaz7a.mpg");
  th::tracking::Track real = th::tracking::trackVideo(clip);
  th::tracking::fitTrack(real, faceModel(), options);
  framesPerSecond = real.framesPerSecond;
  const th::audio::AudioClip sound = th::tracking::readClipSound(clip);
  const th::animation::HeadModel head = th::animation::loadHeadModel(modelFile("head.json"));
  const th::face::FapTrack rotations = th::pipeline::animate(sound.samples, &head, nullptr, {.idle = false});
  std::vector<th::face::FapFrame> poses;
  for (const th::tracking::TrackedFrame& frame : real.frames) {
    th::face::FapFrame faps = rotations.at(frame.seconds);
    for (int fap : real.fittedFaps) faps[static_cast<std::size_t>(fap)] = frame.fit.faps[static_cast<std::size_t>(fap)];
    poses.push_back(faps);
  }
  return poses;
}

TEST(TrackingTruth, ARealSpeakersLipsWithModelledHeadRotationsComeBackWithinTwoDegrees) {
  double fps = 0.0;
  const std::vector<th::face::FapFrame> poses = realSpeakersPoses({}, fps);
  expectRotationsWithin(2.0, renderTrackAndFit(poses, fps));
}

// Where the FAPs' errors above come from: given perfect landmarks (the model's own, projected as the renderer's
// camera would, the face 170 px between the eye corners as in the renders) and a pull to 0 too light to bias
// them, the fit gives every FAP back within 3.5 % of its range (the outer lip corners, with the largest ranges,
// 2.6–3.0 %, a few tenths more or less as the head turns more or less) and the rotations within 0.1°. So the fit can
// tell the 21 FAPs and the head apart from 68 points; what it lacks is dlib's accuracy on our rendered face, whose lip
// points lie 2-6 px from the mesh's (tracking_truth_test prints the FAPs' errors).
TEST(TrackingTruth, FromPerfectLandmarksEveryFapComesBackWithinThreeAndAHalfPercentOfItsRange) {
  th::tracking::FitOptions options;
  options.jawPrior = options.fapPrior = 0.001;
  double fps = 0.0;
  const std::vector<th::face::FapFrame> poses = realSpeakersPoses(options, fps);
  options.focalLengthPixels =
      0.5 * 480 / std::tan(0.5 * th::render::OrbitCamera{}.fovYDegrees * std::numbers::pi / 180.0);
  const th::tracking::FaceFitter projector(faceModel(), options);
  th::tracking::FaceFit place;
  const th::tracking::Landmarks unit = projector.project(place);
  place.scale = 170.0 / (unit.col(36) - unit.col(45)).norm();
  place.offset = {320.0, 240.0};
  th::tracking::Track track;
  track.framesPerSecond = fps;
  std::vector<th::face::FapFrame> shown{th::face::FapFrame{}};
  shown.insert(shown.end(), poses.begin(), poses.end());
  for (std::size_t f = 0; f < shown.size(); ++f) {
    th::tracking::FaceFit pose = place;
    pose.faps = shown[f];
    track.frames.push_back(
        {.seconds = static_cast<double>(f) / fps, .found = true, .landmarks = projector.project(pose), .fit = {}});
  }
  th::tracking::fitTrack(track, faceModel(), options, 0);
  for (int fap : {48, 49, 50}) {
    double squared = 0.0;
    for (std::size_t f = 1; f < shown.size(); ++f)
      squared += std::pow(
          degrees(track.frames[f].fit.faps[static_cast<std::size_t>(fap)] - shown[f][static_cast<std::size_t>(fap)]),
          2);
    EXPECT_LE(std::sqrt(squared / static_cast<double>(shown.size() - 1)), 0.1) << "FAP " << fap;
  }
  for (int fap : track.fittedFaps) {
    const auto n = static_cast<std::size_t>(fap);
    double squared = 0.0, low = 1e300, high = -1e300;
    for (std::size_t f = 1; f < shown.size(); ++f) {
      squared += std::pow(track.frames[f].fit.faps[n] - shown[f][n], 2);
      low = std::min(low, shown[f][n]);
      high = std::max(high, shown[f][n]);
    }
    ASSERT_GT(high - low, 10.0) << "FAP " << fap << " hardly moves in these curves";
    const double share = std::sqrt(squared / static_cast<double>(shown.size() - 1)) / (high - low);
    std::printf("perfect landmarks: FAP %2d within %.1f %% of its range %.0f\n", fap, 100.0 * share, high - low);
    EXPECT_LE(share, 0.035) << "FAP " << fap;
  }
}

}  // namespace
