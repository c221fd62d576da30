// The stages chosen by their options: with a bounded look-ahead, the streaming stage; without, the batch decoder
// in the stage shape, which readies nothing before the end of its input, then every frame, each equal to what the
// batch function gives for the whole input.
#include "animation/recording_stages.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "made_up_speech.h"

namespace {

using namespace th::animation;

std::string modelPath(const char* name) {
  return std::string(TALKINGHEAD_SOURCE_DIR) + "/models/" + name;
}

using th::test::madeUpSpeech;

SpeechFrames matrixOf(const std::vector<SpeechFrame>& frames) {
  SpeechFrames speech;
  speech.mfcc.resize(frames.front().mfcc.size(), static_cast<Eigen::Index>(frames.size()));
  speech.levelDb.resize(static_cast<Eigen::Index>(frames.size()));
  for (std::size_t t = 0; t < frames.size(); ++t) {
    speech.mfcc.col(static_cast<Eigen::Index>(t)) = frames[t].mfcc;
    speech.levelDb[static_cast<Eigen::Index>(t)] = frames[t].levelDb;
  }
  return speech;
}

// The whole-input contract: nothing before the end, all of it after, then read by index until forgotten.
template <typename In, typename Out>
std::vector<Out> runWhole(OnlineStage<In, Out>& stage, const std::vector<In>& inputs) {
  EXPECT_EQ(stage.latencyFrames(), kWholeInput);
  for (const In& frame : inputs) {
    stage.accept(frame);
    EXPECT_EQ(stage.numFramesReady(), 0) << "a batch decoder waits for the whole input";
  }
  EXPECT_GT(stage.framesHeld(), 0U) << "the input, held until its end";
  stage.inputFinished();
  stage.inputFinished();
  const int perFrame = stage.inputFramesPerFrame();
  EXPECT_EQ(stage.numFramesReady(), (static_cast<int>(inputs.size()) + perFrame - 1) / perFrame);
  std::vector<Out> outputs(static_cast<std::size_t>(stage.numFramesReady()));
  for (int t = 0; t < stage.numFramesReady(); ++t) stage.getFrame(t, outputs[static_cast<std::size_t>(t)]);
  Out out;
  EXPECT_THROW(stage.getFrame(stage.numFramesReady(), out), th::Error) << "not ready";
  stage.forgetBefore(2);
  EXPECT_THROW(stage.getFrame(1, out), th::Error) << "forgotten";
  EXPECT_EQ(stage.framesHeld(), outputs.size() - 2) << "the input is freed once decided";
  EXPECT_THROW(stage.accept(inputs.front()), th::Error) << "input after its end";
  return outputs;
}

TEST(RecordingStages, HeadBatchOrStreaming) {
  const HeadModel model = loadHeadModel(modelPath("head.json"));
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<ProsodyFrame> prosody(300);
  Eigen::MatrixXd matrix(4, 300);
  Eigen::RowVectorXd voiced(300);
  for (std::size_t t = 0; t < prosody.size(); ++t) {
    prosody[t] = {.prosody = Eigen::Vector4d::NullaryExpr([&] { return noise(random); }), .voiced = t % 40 < 30};
    matrix.col(static_cast<Eigen::Index>(t)) = prosody[t].prosody;
    voiced[static_cast<Eigen::Index>(t)] = prosody[t].voiced ? 1.0 : 0.0;
  }
  const HeadSynthesisOptions batch{.variant = HeadVariant::kTrajectory, .maxLagFrames = -1};
  const std::vector<HeadFrame> frames = runWhole(*makeHeadStage(model, batch), prosody);
  const Eigen::MatrixXd expected = synthesiseHead(model, matrix, voiced, batch);
  for (std::size_t t = 0; t < frames.size(); ++t)
    ASSERT_EQ(frames[t].rotationDegrees, expected.col(static_cast<Eigen::Index>(t))) << "frame " << t;

  const auto streaming = makeHeadStage(model, {.maxLagFrames = kLiveHeadLagFrames});
  EXPECT_NE(dynamic_cast<HeadStage*>(streaming.get()), nullptr);
}

TEST(RecordingStages, MouthBatchOrStreaming) {
  const MouthModel model = loadMouthModel(modelPath("mouth.json"));
  const std::vector<SpeechFrame> speech = madeUpSpeech(200, 11, 4);
  const MouthSynthesisOptions batch{.method = MouthMethod::kInversion, .maxIterations = 20};
  const std::vector<MouthFrame> frames = runWhole(*makeMouthStage(model, batch), speech);
  const Eigen::MatrixXd expected = synthesiseMouth(model, matrixOf(speech), batch);
  for (std::size_t t = 0; t < frames.size(); ++t)
    ASSERT_EQ(frames[t].components, expected.col(static_cast<Eigen::Index>(t))) << "frame " << t;

  const auto streaming = makeMouthStage(model, {.windowFrames = 1});
  EXPECT_NE(dynamic_cast<MouthStage*>(streaming.get()), nullptr);
}

TEST(RecordingStages, VisemesBatchOrStreaming) {
  const VisemeModel model = loadVisemeModel(modelPath("visemes.json"));
  const std::vector<SpeechFrame> speech = madeUpSpeech(200, static_cast<int>(model.priorMean.size()), 5);
  const std::vector<VisemeFrame> frames = runWhole(*makeVisemeStage(model, -1), speech);
  const th::face::VisemeTrack expected = decodeVisemes(model, matrixOf(speech));
  ASSERT_EQ(frames.size(), expected.classes.size());
  for (std::size_t t = 0; t < frames.size(); ++t) {
    EXPECT_EQ(frames[t].mouthClass, expected.classes[t]);
    ASSERT_EQ(frames[t].probabilities, expected.posteriors.col(static_cast<Eigen::Index>(t)));
  }
  EXPECT_NE(dynamic_cast<VisemeStage*>(makeVisemeStage(model, 2).get()), nullptr);
}

TEST(RecordingStages, ArticulationOnTheWholeRecording) {
  const MouthNetwork model = loadMouthNetwork(modelPath("articulation.json"));
  const std::vector<SpeechFrame> subframes = madeUpSpeech(3 * 100 + 1, kNetworkMfcc, 6);
  // The cepstral mean of the whole recording: the network hears it before its first frame.
  const std::vector<MouthNetworkFrame> heard = runWhole(*makeMouthNetworkStage(model, true), subframes);
  const SpeechFrames matrix = matrixOf(subframes);
  const Eigen::VectorXd mean = matrix.mfcc.rowwise().mean();
  const MouthNetworkOutput expected = runMouthNetwork(model, matrix, &mean);
  ASSERT_EQ(static_cast<int>(heard.size()), expected.numFrames());
  for (std::size_t t = 0; t < heard.size(); ++t) {
    ASSERT_EQ(heard[t].classes, expected.classes.col(static_cast<Eigen::Index>(t)));
    ASSERT_EQ(heard[t].shut, expected.shut[static_cast<Eigen::Index>(t)]);
  }
  EXPECT_NE(dynamic_cast<MouthNetworkStage*>(makeMouthNetworkStage(model, false).get()), nullptr);

  const std::vector<VisemeFrame> classes = runWhole(*makeArticulationVisemeStage(model, {}, -1), heard);
  const th::face::VisemeTrack decided = networkVisemes(model, expected.classes, {});
  ASSERT_EQ(classes.size(), decided.classes.size());
  for (std::size_t t = 0; t < classes.size(); ++t) EXPECT_EQ(classes[t].mouthClass, decided.classes[t]);
  EXPECT_NE(dynamic_cast<ArticulationVisemeStage*>(makeArticulationVisemeStage(model, {}, 0).get()), nullptr);
  ArticulationOptions bad;
  bad.evidenceScale = -1.0;
  EXPECT_THROW(makeArticulationVisemeStage(model, bad, -1), th::Error) << "options checked as the stream's are";
}

}  // namespace
