// Training data from talking videos: the clips found in a folder, a track's FAPs at the animation rate beside
// its sound's MFCCs, tracks kept and read back, clips that cannot be used left out with their reason, and a
// mouth model trained on GRID clips that predicts held-out clips' jaw from their sound.
#include "tracking/video_training.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

#include "animation/mouth_model.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "eval/mouth_evaluation.h"
#include "face/face_model.h"
#include "tracking_test_support.h"

namespace {

namespace fs = std::filesystem;
using th::eval::FapScores;

const th::face::FaceModel& faceModel() {
  static const th::face::FaceModel face = th::face::FaceModel::buildDefault();
  return face;
}

th::tracking::VideoCorpusOptions onThreads(unsigned threads, const fs::path& trackFolder = {}) {
  th::tracking::VideoCorpusOptions options;
  options.threads = threads;
  options.trackFolder = trackFolder;
  return options;
}

std::vector<fs::path> gridClips(std::size_t count) {
  std::vector<fs::path> clips = th::tracking::listVideos(th::sharedDataPath("grid/s1"));
  clips.resize(std::min(count, clips.size()));
  return clips;
}

TEST(ListVideos, FindsTheVideosOfAFolderByNameAndRefusesAnEmptyOne) {
  th::TemporaryFolder folder;
  for (const char* name : {"b.MP4", "a.mpg", "c.avi", "notes.txt", "d.wav"}) std::ofstream(folder.path() / name) << "x";
  fs::create_directory(folder.path() / "sub.mp4");  // a folder, not a video
  const std::vector<fs::path> videos = th::tracking::listVideos(folder.path());
  ASSERT_EQ(videos.size(), 3u);
  EXPECT_EQ(videos[0].filename(), "a.mpg");
  EXPECT_EQ(videos[1].filename(), "b.MP4");
  EXPECT_EQ(videos[2].filename(), "c.avi");
  th::TemporaryFolder empty;
  std::ofstream(empty.path() / "notes.txt") << "x";
  try {
    th::tracking::listVideos(empty.path());
    FAIL() << "no error";
  } catch (const th::Error& error) {
    EXPECT_NE(std::string(error.what()).find("holds no videos"), std::string::npos) << error.what();
  }
  EXPECT_THROW(th::tracking::listVideos(folder.path() / "missing"), th::Error);
}

TEST(TrackFileName, ClipsThatDifferOnlyInTheirExtensionKeepTracksOfTheirOwn) {
  EXPECT_NE(th::tracking::trackFileName("talks/a.mp4"), th::tracking::trackFileName("talks/a.avi"));
  EXPECT_EQ(th::tracking::trackFileName("talks/a.mp4"), fs::path("a.mp4.csv"));  // in the track folder, not beside
}

TEST(MouthRecordingOf, ResamplesTheFapsToTheAnimationRateBesideTheSoundsMfccs) {
  // 2 s at 25 fps; FAP 3 a ramp in time, FAP 4 a constant.
  th::tracking::Track track;
  track.video = "synthetic.mp4";
  track.framesPerSecond = 25.0;
  track.fittedFaps = {4, 3};
  for (int f = 0; f < 50; ++f) {
    th::tracking::TrackedFrame frame;
    frame.seconds = f / 25.0;
    frame.found = true;
    frame.fit.faps[3] = 100.0 * frame.seconds;
    frame.fit.faps[4] = -7.0;
    track.frames.push_back(frame);
  }
  std::vector<float> sound(16000 * 3);  // longer than the video: the video sets the length
  for (std::size_t n = 0; n < sound.size(); ++n)
    sound[n] = 0.1f * static_cast<float>(std::sin(0.05 * static_cast<double>(n)));
  const th::animation::MouthRecording recording = th::tracking::mouthRecordingOf(track, sound);
  EXPECT_EQ(recording.visual.rows(), 2);
  // The last video frame is at 49/25 = 1.96 s: animation frames 0 .. 58 (58/30 = 1.933 s).
  ASSERT_EQ(recording.numFrames(), 59);
  EXPECT_EQ(recording.speech.numFrames(), 59);
  EXPECT_EQ(recording.speech.levelDb.size(), 59);
  for (int i = 0; i < recording.numFrames(); ++i) {
    EXPECT_NEAR(recording.visual(0, i), 100.0 * i / 30.0, 1e-9) << i;  // rows ascending: FAP 3 first
    EXPECT_NEAR(recording.visual(1, i), -7.0, 1e-12);
  }
  // A shorter sound cuts it.
  const th::animation::MouthRecording shorter =
      th::tracking::mouthRecordingOf(track, std::span<const float>(sound).first(16000));
  EXPECT_LE(shorter.numFrames(), 30);
  EXPECT_GE(shorter.numFrames(), 28);
  track.fittedFaps.clear();
  EXPECT_THROW(th::tracking::mouthRecordingOf(track, sound), th::Error);
}

TEST(ScoreFaps, IsPerfectForTheTruthAndNeutralForItsMean) {
  th::animation::MouthRecording clip;
  clip.visual.resize(2, 100);
  for (int t = 0; t < 100; ++t) {
    clip.visual(0, t) = 50.0 + 40.0 * std::sin(0.3 * t);
    clip.visual(1, t) = 3.0 * std::cos(0.17 * t);
  }
  const std::vector<int> faps{3, 5};
  const FapScores perfect = th::eval::scoreFaps({clip.visual}, faps, {clip}, faps);
  EXPECT_NEAR(perfect.epsilon, 0.0, 1e-12);
  EXPECT_NEAR(perfect.rho, 1.0, 1e-12);
  EXPECT_NEAR(perfect.jawRho, 1.0, 1e-12);
  EXPECT_EQ(perfect.faps, 2);
  EXPECT_EQ(perfect.frames, 100);
  const Eigen::MatrixXd mean = clip.visual.rowwise().mean().replicate(1, 100);
  const FapScores neutral = th::eval::scoreFaps({mean}, faps, {clip}, faps);
  EXPECT_NEAR(neutral.epsilon, 1.0, 1e-9);
  EXPECT_NEAR(neutral.rho, 0.0, 1e-12);
  // Only the FAPs both hold count; an estimate without the jaw has no jaw scores.
  const FapScores lipsOnly = th::eval::scoreFaps({clip.visual.bottomRows(1)}, {5}, {clip}, faps);
  EXPECT_EQ(lipsOnly.faps, 1);
  EXPECT_TRUE(std::isnan(lipsOnly.jawRho));
  EXPECT_THROW(th::eval::scoreFaps({clip.visual}, {6, 7}, {clip}, faps), th::Error);
}

TEST(VideoCorpus, KeepsTheTracksReusesThemOnlyAsMadeAndLeavesOutAClipWithoutAFace) {
  th::TemporaryFolder folder;
  const fs::path faceless = folder.path() / "faceless.mp4";
  th::test::writeFacelessVideo(faceless);
  std::vector<fs::path> videos = gridClips(2);
  videos.back() = faceless;  // a clip, then one without a face
  const fs::path tracks = folder.path() / "tracks";
  const th::tracking::VideoCorpus first = th::tracking::loadVideoCorpus(videos, faceModel(), onThreads(2, tracks));
  ASSERT_EQ(first.clips.size(), 1u);
  ASSERT_EQ(first.skipped.size(), 1u);
  EXPECT_EQ(first.skipped[0].video, faceless);
  EXPECT_NE(first.skipped[0].reason.find("no face"), std::string::npos) << first.skipped[0].reason;
  EXPECT_EQ(first.faps.size(), 21u);
  for (const th::tracking::VideoClip& clip : first.clips) {
    EXPECT_TRUE(clip.trackedNow);
    EXPECT_EQ(clip.recording.visual.rows(), 21);
    EXPECT_NEAR(clip.recording.numFrames(), 90, 2);  // GRID: 3 s
    EXPECT_LT(clip.meanResidualPixels, 3.0);
    EXPECT_TRUE(fs::exists(tracks / th::tracking::trackFileName(clip.video)));
  }
  // Again: read from the tracks, the same numbers (to the CSV's precision).
  const th::tracking::VideoCorpus second = th::tracking::loadVideoCorpus(videos, faceModel(), onThreads(1, tracks));
  ASSERT_EQ(second.clips.size(), 1u);
  EXPECT_FALSE(second.clips[0].trackedNow);
  EXPECT_LT((second.clips[0].recording.visual - first.clips[0].recording.visual).cwiseAbs().maxCoeff(), 1e-3);
  // Tracks made another way (another tracker version, other options) are made again.
  std::ofstream(tracks / "tracker.txt") << "talkinghead tracker 1\n";
  const th::tracking::VideoCorpus third = th::tracking::loadVideoCorpus(videos, faceModel(), onThreads(2, tracks));
  for (const th::tracking::VideoClip& clip : third.clips) EXPECT_TRUE(clip.trackedNow);
  th::tracking::VideoCorpusOptions otherPriors = onThreads(2, tracks);
  otherPriors.fit.fapPrior = 0.2;
  for (const th::tracking::VideoClip& clip : th::tracking::loadVideoCorpus(videos, faceModel(), otherPriors).clips)
    EXPECT_TRUE(clip.trackedNow);
  // Nothing usable at all is an error that says why.
  try {
    th::tracking::loadVideoCorpus({faceless}, faceModel(), {});
    FAIL() << "no error";
  } catch (const th::Error& error) {
    EXPECT_NE(std::string(error.what()).find("no clip could be used"), std::string::npos) << error.what();
  }
}

TEST(VideoMouthModel, PredictsHeldOutClipsJawFromTheirSoundAndDrivesFapsFromItsFile) {
  const th::tracking::VideoCorpus corpus = th::tracking::loadVideoCorpus(gridClips(15), faceModel(), onThreads(2));
  ASSERT_EQ(corpus.clips.size(), 15u);
  std::vector<th::animation::MouthRecording> train, test;
  for (std::size_t i = 0; i < corpus.clips.size(); ++i)
    (i % 5 == 4 ? test : train).push_back(corpus.clips[i].recording);
  const th::animation::MouthModelOptions options{.states = 4, .mixtures = 1, .contextFrames = 2, .visualComponents = 2};
  const th::animation::MouthModel model = th::tracking::trainVideoMouthModel(train, corpus.faps, options);
  EXPECT_EQ(model.visualFaps, corpus.faps);
  EXPECT_FALSE(model.fapMap.has_value());
  EXPECT_EQ(th::animation::mouthFapNumbers(model), corpus.faps);
  const FapScores scores = th::eval::scoreFaps(th::eval::predictFaps(model, test), corpus.faps, test, corpus.faps);
  const FapScores otherAudio =
      th::eval::scoreFaps(th::eval::predictFaps(model, test, {}, 1), corpus.faps, test, corpus.faps);
  std::cout << "held-out jaw eps " << scores.jawEpsilon << " rho " << scores.jawRho << "; all FAPs eps "
            << scores.epsilon << " rho " << scores.rho << "; another clip's audio: jaw eps " << otherAudio.jawEpsilon
            << " rho " << otherAudio.jawRho << '\n';
  // The sound carries the jaw: well above chance, and better than the wrong clip's sound.
  EXPECT_GT(scores.jawRho, 0.5);
  EXPECT_LT(scores.jawEpsilon, 0.8);  // the mean's is about 1
  EXPECT_GT(scores.jawRho, otherAudio.jawRho);
  // The jaw never closes past rest.
  for (const Eigen::MatrixXd& faps : th::eval::predictFaps(model, test)) EXPECT_GE(faps.row(0).minCoeff(), 0.0);

  // Its file holds the FAPs it drives; read back, it predicts the same.
  th::TemporaryFolder folder;
  const fs::path file = folder.path() / "video_mouth.json";
  th::animation::saveMouthModel(file, model, options);
  const th::animation::MouthModel back = th::animation::loadMouthModel(file);
  EXPECT_EQ(back.visualFaps, corpus.faps);
  EXPECT_TRUE(th::animation::drivesFaps(back));
  const Eigen::MatrixXd before = th::eval::predictFaps(model, {test[0]})[0];
  const Eigen::MatrixXd after = th::eval::predictFaps(back, {test[0]})[0];
  EXPECT_LT((before - after).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_THROW(th::animation::jawOpeningOf(back, Eigen::MatrixXd::Zero(2, 3)), th::Error);
}

}  // namespace
