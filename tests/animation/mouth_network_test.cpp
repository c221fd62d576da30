// The mouth network on speech made here, whose truths are known: it learns the classes, the jaw and the closures
// of the sounds it is trained on, keeps its answers through its file, and refuses broken files naming the field.
#include "animation/mouth_network.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "core/error.h"
#include "core/temporary_file.h"
#include "core/text_files.h"

namespace {

using th::animation::NetworkRecording;

constexpr int kRate = 16000;

// Segments of 150-300 ms, the first voiced: silence (lips shut, class sil), a vowel-like harmonic sound (jaw open,
// class aa) or hiss (jaw half open, class SS), with their truths at 30 frames a second.
NetworkRecording synthetic(unsigned seed, double seconds, double pitchHz) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> length(0.15, 0.3);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  std::vector<float> samples;
  std::vector<int> segmentClass;
  std::vector<std::pair<double, int>> segments;
  // It starts with sound: the level is heard against the loudest sound so far (features/speech_normaliser.h),
  // so silence before any sound is not yet quiet.
  int kind = 1;
  double t = 0.0;
  while (t < seconds) {
    const double d = length(random);
    segments.emplace_back(t + d, kind);
    const int n = static_cast<int>(d * kRate);
    for (int i = 0; i < n; ++i) {
      const double time = static_cast<double>(samples.size()) / kRate;
      float value = 0.0f;
      if (kind == 1)
        for (int h = 1; h <= 12; ++h)
          value +=
              static_cast<float>(0.3 / h * std::sin(2.0 * M_PI * pitchHz * h * time) * (h == 3 || h == 4 ? 3.0 : 1.0));
      if (kind == 2) value = 0.1f * noise(random);
      samples.push_back(value + 1e-4f * noise(random));
    }
    t += d;
    kind = (kind + 1 + static_cast<int>(random() % 2)) % 3;
  }
  NetworkRecording r;
  r.name = "synthetic";
  r.subframes = th::animation::speechSubframesOf(samples);
  const int frames = r.subframes.numFrames() / th::animation::kSubframesPerFrame;
  r.faps = Eigen::MatrixXd::Zero(2, frames);
  r.lipShape = Eigen::MatrixXd::Zero(2, frames);
  std::size_t segment = 0;
  for (int f = 0; f < frames; ++f) {
    const double time = f / 30.0;
    while (segment + 1 < segments.size() && segments[segment].first <= time) ++segment;
    const int k = segments[segment].second;
    r.classes.push_back(k == 0 ? th::face::kSilence : k == 1 ? th::face::kAa : th::face::kSs);
    r.faps(0, f) = k == 0 ? 0.0 : k == 1 ? 400.0 : 150.0;  // the jaw (FAP 3)
    r.faps(1, f) = k == 1 ? -60.0 : 10.0;                  // a lip FAP
    r.lipShape(0, f) = k == 0 ? 0.01 : k == 1 ? 0.4 : 0.1;
    r.lipShape(1, f) = k == 2 ? 0.62 : 0.55;
  }
  return r;
}

th::animation::MouthNetworkOptions smallOptions() {
  th::animation::MouthNetworkOptions options;
  options.hidden = {32};
  options.pastSubframes = 6;
  options.futureSubframes = 3;
  options.visualComponents = 2;
  options.training.epochs = 25;
  options.training.batchFrames = 32;
  options.training.learningRate = 3e-3;
  return options;
}

TEST(MouthNetwork, SubframesAreThreeAFrameAndAWarpChangesThem) {
  std::vector<float> samples(kRate);
  std::mt19937 random(2);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  for (float& s : samples) s = noise(random);
  const th::animation::SpeechFrames plain = th::animation::speechSubframesOf(samples);
  EXPECT_NEAR(plain.numFrames(), 90, 1);
  EXPECT_EQ(plain.mfcc.rows(), th::animation::kNetworkMfcc);
  EXPECT_TRUE(th::animation::speechSubframesOf(samples, 1.0).mfcc.isApprox(plain.mfcc));
  const th::animation::SpeechFrames warped = th::animation::speechSubframesOf(samples, 1.1);
  EXPECT_EQ(warped.numFrames(), plain.numFrames());
  EXPECT_GT((warped.mfcc - plain.mfcc).cwiseAbs().maxCoeff(), 0.1);
  EXPECT_EQ(warped.levelDb, plain.levelDb);  // the warp moves the filters, not the level
}

TEST(MouthNetwork, LearnsClassesJawAndClosuresOfSoundsItHasNotHeard) {
  const std::vector<NetworkRecording> training{synthetic(1, 12.0, 120.0), synthetic(2, 12.0, 210.0)};
  const NetworkRecording test = synthetic(3, 6.0, 160.0);  // another voice
  const th::animation::MouthNetworkTraining trained =
      th::animation::trainMouthNetwork(training, {3, 12}, smallOptions());
  EXPECT_LT(trained.report.trainingLoss.back(), trained.report.trainingLoss.front());
  const th::animation::MouthNetworkOutput out = th::animation::runMouthNetwork(trained.model, test.subframes);
  ASSERT_GE(out.numFrames(), test.numFrames());
  const Eigen::MatrixXd faps = th::animation::mouthNetworkFaps(trained.model, out);
  int right = 0, shutRight = 0, frames = 0;
  Eigen::RowVectorXd jaw(test.numFrames()), truth(test.numFrames());
  for (int t = 0; t < test.numFrames(); ++t) {
    Eigen::Index best = 0;
    out.classes.col(t).maxCoeff(&best);
    right += best == test.classes[static_cast<std::size_t>(t)] ? 1 : 0;
    shutRight += (out.shut[t] > 0.5) == (test.lipShape(0, t) < 0.04) ? 1 : 0;
    jaw[t] = faps(0, t);
    truth[t] = test.faps(0, t);
    ++frames;
  }
  // Frames at a segment's edge are ambiguous; the rest are told apart.
  EXPECT_GT(static_cast<double>(right) / frames, 0.85);
  EXPECT_GT(static_cast<double>(shutRight) / frames, 0.85);
  const Eigen::RowVectorXd a = jaw.array() - jaw.mean(), b = truth.array() - truth.mean();
  EXPECT_GT(a.dot(b) / std::sqrt(a.squaredNorm() * b.squaredNorm()), 0.8);
  EXPECT_GE(faps.row(0).minCoeff(), 0.0);  // the jaw never closes past rest
}

TEST(MouthNetwork, ItsFileKeepsItsAnswersAndBrokenFilesAreRefused) {
  const std::vector<NetworkRecording> training{synthetic(4, 6.0, 140.0)};
  th::animation::MouthNetworkOptions options = smallOptions();
  options.training.epochs = 2;
  th::animation::MouthNetwork model = th::animation::trainMouthNetwork(training, {3, 12}, options).model;
  model.openingGradient = Eigen::Vector2d(2e-4, -1e-6);
  th::TemporaryFile file(".json");
  th::animation::saveMouthNetwork(file.path(), model);
  const th::animation::MouthNetwork back = th::animation::loadMouthNetwork(file.path());
  const th::animation::MouthNetworkOutput a = th::animation::runMouthNetwork(model, training[0].subframes);
  const th::animation::MouthNetworkOutput b = th::animation::runMouthNetwork(back, training[0].subframes);
  EXPECT_TRUE(a.classes.isApprox(b.classes, 1e-12));
  EXPECT_TRUE(a.components.isApprox(b.components, 1e-9));
  EXPECT_TRUE(a.shut.isApprox(b.shut, 1e-12));
  EXPECT_EQ(back.visualFaps, model.visualFaps);
  EXPECT_EQ(back.lookaheadMs(), 33);
  EXPECT_TRUE(back.openingGradient.isApprox(model.openingGradient));
  EXPECT_TRUE(back.classShapes.isApprox(model.classShapes));
  // The classes' shapes are their frames' FAPs about the mean: aa opens the jaw most, silence least; classes the
  // recording never shows have none.
  EXPECT_GT(model.classShapes(0, th::face::kAa), model.classShapes(0, th::face::kSs));
  EXPECT_LT(model.classShapes(0, th::face::kSilence), 0.0);
  EXPECT_EQ(model.classShapes.col(th::face::kPp).norm(), 0.0);
  EXPECT_TRUE(back.sequence.bigrams.isApprox(model.sequence.bigrams));
  EXPECT_TRUE(back.sequence.meanRun.isApprox(model.sequence.meanRun));

  const std::string text = th::readTextFile(file.path(), "model");
  const auto failure = [&](const std::string& from, const std::string& to) {
    th::TemporaryFile broken(".json");
    std::string spoilt = text;
    const std::size_t at = spoilt.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    spoilt.replace(at, from.size(), to);
    std::ofstream(broken.path()) << spoilt;
    try {
      th::animation::loadMouthNetwork(broken.path());
    } catch (const th::Error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(failure("\"past_subframes\": 6", "\"past_subframes\": 7").find("network"), std::string::npos);
  EXPECT_NE(failure("\"kind\": \"mouth_network\"", "\"kind\": \"mouth\"").find(": kind"), std::string::npos);
  EXPECT_NE(failure("\"visual_faps\": [\n  3,\n  12\n ]", "\"visual_faps\": [12, 3]").find("visual_faps"),
            std::string::npos);
  EXPECT_NE(failure("\"format_version\": 2", "\"format_version\": 1").find("format_version"), std::string::npos);
  EXPECT_NE(failure("\"opening_gradient\": [", "\"opening_gradient\": [1,").find("opening_gradient"),
            std::string::npos);
  EXPECT_NE(failure("\"mean_run\": [", "\"mean_run\": [-1,").find("class_sequence"), std::string::npos);
}

TEST(MouthNetwork, TheStreamAnswersAsTheBatchFrameForFrame) {
  const std::vector<NetworkRecording> training{synthetic(4, 6.0, 140.0)};
  th::animation::MouthNetworkOptions options = smallOptions();
  options.training.epochs = 1;
  const th::animation::MouthNetwork model = th::animation::trainMouthNetwork(training, {3, 12}, options).model;
  const th::animation::SpeechFrames& speech = training[0].subframes;
  const th::animation::MouthNetworkOutput batch = th::animation::runMouthNetwork(model, speech);
  th::animation::MouthNetworkStream stream(model);
  th::animation::MouthNetworkFrame frame;
  int frames = 0;
  std::size_t held = 0;
  const auto check = [&] {
    ASSERT_LT(frames, batch.numFrames());
    EXPECT_TRUE(frame.classes.isApprox(batch.classes.col(frames), 1e-5)) << frames;
    EXPECT_NEAR(frame.shut, batch.shut[frames], 1e-5);
    ++frames;
  };
  for (Eigen::Index t = 0; t < speech.numFrames(); ++t) {
    stream.accept(speech.levelDb[t], speech.mfcc.col(t));
    held = std::max(held, stream.subframesHeld());
    while (stream.next(frame)) check();
    // A frame is out as soon as its look-ahead has come.
    EXPECT_EQ(frames,
              t >= model.futureSubframes ? (t - model.futureSubframes) / th::animation::kSubframesPerFrame + 1 : 0);
  }
  stream.finish();
  while (stream.next(frame)) check();
  EXPECT_EQ(frames, batch.numFrames());
  EXPECT_LE(held, static_cast<std::size_t>(model.contextSubframes() + th::animation::kSubframesPerFrame));
}

}  // namespace
