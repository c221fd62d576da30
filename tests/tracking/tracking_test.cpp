// engine/tracking on real GRID clips (speaker s1, 360x288 at 25 fps, 3 s each) and on videos made here.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "audio/media_audio.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "support/files.h"
#include "tracking/mjpeg_writer.h"
#include "tracking/track.h"
#include "tracking/video_reader.h"
#include "tracking_test_support.h"

namespace {

namespace fs = std::filesystem;
using th::tracking::Landmarks;

fs::path gridClip(const std::string& name) {
  return th::sharedDataPath("grid/s1/" + name + ".mpg");
}

// The message of the th::Error that `work` throws ("" if it throws none).
std::string errorOf(const std::function<void()>& work) {
  try {
    work();
  } catch (const th::Error& error) {
    return error.what();
  }
  return "";
}

TEST(VideoReader, ReadsEveryFrameOfAGridClipAtItsOwnRate) {
  th::tracking::VideoReader video(gridClip("bbal7s"));
  EXPECT_DOUBLE_EQ(video.framesPerSecond(), 25.0);
  EXPECT_EQ(video.width(), 360);
  EXPECT_EQ(video.height(), 288);
  cv::Mat frame;
  double seconds = -1.0;
  int frames = 0;
  while (video.read(frame, seconds)) {
    EXPECT_DOUBLE_EQ(seconds, frames / 25.0);
    EXPECT_EQ(frame.type(), CV_8UC3);
    ++frames;
  }
  EXPECT_EQ(frames, 75);
  EXPECT_EQ(video.framesRead(), 75);
}

TEST(VideoReader, BadFilesFailInOneLineNamingThem) {
  th::TemporaryFolder folder;
  th::test::expectFileError(errorOf([&] { th::tracking::VideoReader video(folder.path() / "missing.mpg"); }),
                            folder.path() / "missing.mpg", "no such file");
  const fs::path text = folder.path() / "notes.mp4";
  std::ofstream(text) << "this is not a video";
  th::test::expectFileError(errorOf([&] { th::tracking::VideoReader video(text); }), text, "not a video");
  th::test::expectFileError(errorOf([&] { th::tracking::VideoReader video(folder.path()); }), folder.path(),
                            "not a file");
}

// A take's video as record writes it: every frame comes back, at its rate and size, close to the picture written.
TEST(MjpegWriter, AGridClipsFramesComeBackAtTheirRateAndCloseToTheOriginal) {
  th::TemporaryFolder folder;
  const fs::path copy = folder.path() / "take.avi";
  std::vector<cv::Mat> written;
  {
    th::tracking::VideoReader source(gridClip("bbal7s"));
    th::tracking::MjpegWriter writer(copy, 25.0, source.width(), source.height());
    cv::Mat frame;
    double seconds = 0.0;
    while (source.read(frame, seconds) && written.size() < 20) {
      writer.write(frame);
      written.push_back(frame);
    }
    writer.finish();
  }
  th::tracking::VideoReader back(copy);
  EXPECT_DOUBLE_EQ(back.framesPerSecond(), 25.0);
  EXPECT_EQ(back.width(), 360);
  EXPECT_EQ(back.height(), 288);
  cv::Mat frame;
  double seconds = 0.0;
  std::size_t frames = 0;
  while (back.read(frame, seconds)) {
    ASSERT_LT(frames, written.size());
    // JPEG at quantiser 2 and 4:2:0 colour: a few levels on average, against 255.
    EXPECT_LT(cv::norm(frame, written[frames], cv::NORM_L1) / static_cast<double>(frame.total() * 3), 4.0)
        << "frame " << frames;
    ++frames;
  }
  EXPECT_EQ(frames, written.size());
}

TEST(MjpegWriter, WrongPicturesAndPlacesFailInOneLineNamingTheFile) {
  th::TemporaryFolder folder;
  const fs::path take = folder.path() / "take.avi";
  th::test::expectFileError(errorOf([&] { th::tracking::MjpegWriter writer(take, 25.0, 0, 480); }), take,
                            "picture size");
  const fs::path nowhere = folder.path() / "missing" / "take.avi";
  th::test::expectFileError(errorOf([&] { th::tracking::MjpegWriter writer(nowhere, 25.0, 64, 48); }), nowhere,
                            "cannot be written");
  th::tracking::MjpegWriter writer(take, 25.0, 64, 48);
  th::test::expectFileError(errorOf([&] { writer.write(cv::Mat(48, 32, CV_8UC3, cv::Scalar::all(0))); }), take,
                            "32 x 48");
  writer.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(128)));
  writer.finish();
  th::test::expectFileError(errorOf([&] { writer.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(0))); }), take,
                            "after it was finished");
}

TEST(LandmarkDetector, AMissingShapePredictorIsNamed) {
  th::test::expectFileError(
      errorOf([] { th::tracking::LandmarkDetector detector({.shapePredictor = "/nonexistent/sp.dat"}); }),
      "/nonexistent/sp.dat", "no such file");
  th::TemporaryFolder folder;
  const fs::path junk = folder.path() / "junk.dat";
  std::ofstream(junk) << "not a model";
  th::test::expectFileError(errorOf([&] { th::tracking::LandmarkDetector detector({.shapePredictor = junk}); }), junk,
                            "not a dlib shape predictor");
}

// Every frame of a frontal talking-head clip has the face, found in the whole frame only at the start, and
// its landmarks are where a face's are: eyes above the nose above the mouth above the chin, symmetric about
// the nose's bridge.
TEST(Tracking, FindsTheFaceInEveryFrameOfAGridClip) {
  const th::tracking::Track track = th::tracking::trackVideo(gridClip("bbal7s"));
  ASSERT_EQ(track.frames.size(), 75u);
  EXPECT_EQ(track.framesFound(), 75);
  EXPECT_LE(track.fullSearches, 2);
  for (const th::tracking::TrackedFrame& frame : track.frames) {
    const Landmarks& p = frame.landmarks;
    EXPECT_GE(p.row(0).minCoeff(), 0.0);
    EXPECT_LE(p.row(0).maxCoeff(), 360.0);
    EXPECT_GE(p.row(1).minCoeff(), 0.0);
    EXPECT_LE(p.row(1).maxCoeff(), 288.0);
    const double eyes = 0.5 * (p.block<2, 12>(0, 36).rowwise().mean().y() + p(1, 27));
    const double mouth = p.block<2, 20>(0, 48).rowwise().mean().y();
    EXPECT_LT(eyes, p(1, 30));
    EXPECT_LT(p(1, 30), mouth);
    EXPECT_LT(mouth, p(1, 8));
    const double eyeDistance = (p.col(36) - p.col(45)).norm();
    EXPECT_GT(eyeDistance, 40.0);
    EXPECT_LT(eyeDistance, 200.0);
    // The outer eye corners are about equally far from the nose's bridge (a frontal face).
    const double left = (p.col(45) - p.col(27)).norm();
    const double right = (p.col(36) - p.col(27)).norm();
    EXPECT_NEAR(left / right, 1.0, 0.25);
  }
}

// The lips part when the speaker is loud: the tracked mouth opening follows the sound's level (dB) frame by
// frame, on several clips.
TEST(Tracking, TheMouthOpensWithTheSoundsLoudness) {
  for (const std::string name : {"bbal7s", "bbaz7a", "bbil3s", "bgahzn"}) {
    const th::tracking::Track track = th::tracking::trackVideo(gridClip(name));
    const std::vector<double> level =
        th::test::levelPerFrame(th::audio::readMediaAudio(gridClip(name)), track.framesPerSecond, track.frames.size());
    std::vector<double> opening;
    for (std::size_t f = 0; f < level.size(); ++f)
      opening.push_back(th::tracking::mouthOpening(track.frames[f].landmarks));
    const double rho = th::test::correlation(opening, level);
    std::cout << name << ": mouth opening against the sound's level, correlation " << rho << " over " << level.size()
              << " frames\n";
    EXPECT_GT(rho, 0.3) << name;
  }
}

TEST(Tracking, AVideoWithoutAFaceIsAnError) {
  th::TemporaryFolder folder;
  const fs::path video = folder.path() / "gradient.mp4";
  th::test::writeFacelessVideo(video);
  th::test::expectFileError(errorOf([&] { th::tracking::trackVideo(video); }), video,
                            "no face found in any of its 50 frames");
}

// Savitzky-Golay keeps any quadratic trajectory exactly, quietens noise, and leaves the frames it cannot
// centre a full window on (run edges, frames without a face) as they were.
TEST(Smoothing, KeepsQuadraticMotionAndQuietensJitter) {
  std::vector<Landmarks> frames(12);
  std::vector<bool> found(12, true);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const double t = static_cast<double>(f);
    frames[f] = Landmarks::Constant(0.5 * t * t - 3.0 * t + 7.0);
  }
  std::vector<Landmarks> smoothed = frames;
  th::tracking::smoothLandmarks(smoothed, found);
  for (std::size_t f = 0; f < frames.size(); ++f)
    EXPECT_NEAR((smoothed[f] - frames[f]).cwiseAbs().maxCoeff(), 0.0, 1e-9);

  // Alternating jitter of ±1 round a constant: at that rate (the highest there is) the filter passes 13/35.
  for (std::size_t f = 0; f < frames.size(); ++f) frames[f] = Landmarks::Constant(f % 2 == 0 ? 1.0 : -1.0);
  found[6] = false;
  smoothed = frames;
  th::tracking::smoothLandmarks(smoothed, found);
  EXPECT_NEAR(std::abs(smoothed[2](0, 0)), 13.0 / 35.0, 1e-12);  // a full window of found frames
  EXPECT_EQ(smoothed[0](0, 0), 1.0);                             // run edges and windows touching frame 6: unchanged
  EXPECT_EQ(smoothed[5](0, 0), -1.0);
  EXPECT_EQ(smoothed[6](0, 0), 1.0);
  EXPECT_EQ(smoothed[8](0, 0), 1.0);
  EXPECT_NEAR(std::abs(smoothed[9](0, 0)), 13.0 / 35.0, 1e-12);
}

TEST(TrackCsv, ReadsBackWhatItWrote) {
  th::tracking::Track track;
  track.framesPerSecond = 25.0;
  for (int f = 0; f < 4; ++f) {
    th::tracking::TrackedFrame frame;
    frame.seconds = f / 25.0;
    frame.found = f != 2;
    frame.landmarks = Landmarks::Random() * 100.0 + Landmarks::Constant(150.0);
    track.frames.push_back(frame);
  }
  th::TemporaryFolder folder;
  const fs::path path = folder.path() / "track.csv";
  th::tracking::writeTrackCsv(path, track);
  const th::tracking::Track back = th::tracking::readTrackCsv(path);
  ASSERT_EQ(back.frames.size(), 4u);
  EXPECT_NEAR(back.framesPerSecond, 25.0, 1e-6);
  for (std::size_t f = 0; f < 4; ++f) {
    EXPECT_NEAR(back.frames[f].seconds, track.frames[f].seconds, 1e-6);
    EXPECT_EQ(back.frames[f].found, track.frames[f].found);
    EXPECT_LT((back.frames[f].landmarks - track.frames[f].landmarks).cwiseAbs().maxCoeff(), 1e-3);
  }
}

}  // namespace
