// Truth we control: our own face, rendered off-screen with head rotations and FAPs from real animation curves
// (the shipped models animating BEAT2 speech), tracked with dlib and fitted. The head's rotations come back
// within 2° per axis (root mean square over the frames). The jaw and lip FAPs' errors are printed, not held to
// the 10 % of each one's range: they are not there yet (README, "Tracking").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "animation/animate.h"
#include "audio/audio_file.h"
#include "core/data_path.h"
#include "face/face_model.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "tracking/track.h"

namespace {

double degrees(double angleUnits) { return angleUnits * th::face::kAngleUnit * 180.0 / std::numbers::pi; }

TEST(TrackingTruth, OurRenderedFacesRotationsComeBackWithinTwoDegrees) {
  const th::face::FaceModel face = th::face::FaceModel::build(th::face::loadIctFace(th::face::ictFaceDirectory()));
  const std::filesystem::path models = std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "models";
  const th::animation::HeadModel head = th::animation::loadHeadModel(models / "head.json");
  const th::animation::MouthModel mouth = th::animation::loadMouthModel(models / "mouth.json");
  th::audio::AudioClip speech = th::audio::readAudioFile(th::sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav"));
  speech.samples.resize(std::min<std::size_t>(speech.samples.size(), 16000 * 5));  // 5 s: 150 frames
  const th::video::Animation truth = th::animation::animate(speech.samples, &head, &mouth, {});

  constexpr int kWidth = 640, kHeight = 480;
  th::render::OffscreenContext context;
  th::render::FaceRenderer renderer(context, face.mesh(), {.width = kWidth, .height = kHeight});
  renderer.setMouthOpening(face.innerLipVertices());
  const th::render::OrbitCamera camera = th::render::frameHead(face.mesh().positions, double(kWidth) / kHeight);
  th::tracking::LandmarkDetector detector;
  th::tracking::Track track;
  track.framesPerSecond = truth.framesPerSecond;
  std::vector<th::face::FapValues> poses;
  // Frame 0: the face at rest, the tracker's neutral; then the animation.
  for (int f = -1; f < truth.numFrames(); ++f) {
    th::face::FapValues faps{};
    if (f >= 0)
      for (std::size_t c = 0; c < truth.faps.size(); ++c) faps[static_cast<std::size_t>(truth.faps[c])] = truth.values(f, static_cast<Eigen::Index>(c));
    renderer.setPositions(face.deform(faps));
    renderer.setPupilScale(face.pupilScale(faps));
    const th::render::Image image = renderer.renderImage(camera);
    cv::Mat bgr;
    cv::cvtColor(cv::Mat(kHeight, kWidth, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data())), bgr, cv::COLOR_RGB2BGR);
    th::tracking::TrackedFrame frame;
    frame.seconds = (f + 1) / truth.framesPerSecond;
    frame.found = detector.find(bgr, frame.landmarks);
    ASSERT_TRUE(frame.found) << "no face found in rendered frame " << f + 1;
    track.frames.push_back(frame);
    poses.push_back(faps);
  }
  // The renderer's camera: its focal length in pixels from its vertical field of view.
  th::tracking::FitOptions fitOptions;
  fitOptions.focalLengthPixels = 0.5 * kHeight / std::tan(0.5 * camera.fovYDegrees * std::numbers::pi / 180.0);
  th::tracking::fitTrack(track, face, fitOptions, 0);

  const std::size_t n = track.frames.size() - 1;
  for (int fap : {48, 49, 50}) {
    double squared = 0.0, low = 1e300, high = -1e300;
    for (std::size_t f = 1; f <= n; ++f) {
      const double want = degrees(poses[f][static_cast<std::size_t>(fap)]);
      squared += std::pow(degrees(track.frames[f].fit.faps[static_cast<std::size_t>(fap)]) - want, 2);
      low = std::min(low, want);
      high = std::max(high, want);
    }
    const double rms = std::sqrt(squared / static_cast<double>(n));
    std::cout << "FAP " << fap << ": " << rms << " degrees RMS error (the truth spans " << low << " to " << high << ")\n";
    EXPECT_LE(rms, 2.0) << "FAP " << fap;
  }
  for (int fap : track.fittedFaps) {
    if (truth.columnOf(fap) < 0) continue;
    double squared = 0.0, low = 1e300, high = -1e300;
    for (std::size_t f = 1; f <= n; ++f) {
      const double want = poses[f][static_cast<std::size_t>(fap)];
      squared += std::pow(track.frames[f].fit.faps[static_cast<std::size_t>(fap)] - want, 2);
      low = std::min(low, want);
      high = std::max(high, want);
    }
    const double rms = std::sqrt(squared / static_cast<double>(n));
    std::cout << "FAP " << fap << ": RMS error " << rms << " (the truth spans " << low << " to " << high << ")\n";
  }
}

}  // namespace
