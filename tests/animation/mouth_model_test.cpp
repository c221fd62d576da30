// The mouth path: the paper's ε and ρ at their reference points, and an AV-HMM that
// learns a known audio-visual link and recovers the visual part from audio by inversion and MMSE.
#include "animation/mouth_model.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "animation/mouth_data.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "eval/mouth_corpus.h"
#include "eval/mouth_evaluation.h"
#include "hmm/model_file.h"
#include "hmm/sampling.h"

namespace th::animation {
namespace {

TEST(MouthEvaluation, ThePapersMeasuresAtTheirReferencePoints) {
  std::mt19937 random(2);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::MatrixXd truth = Eigen::MatrixXd::NullaryExpr(2, 5000, [&] { return 3.0 + 2.0 * normal(random); });
  EXPECT_NEAR(th::eval::averageMse(truth, truth), 0.0, 1e-15);
  EXPECT_NEAR(th::eval::averageCorrelation(truth, truth), 1.0, 1e-12);
  const Eigen::MatrixXd mean = truth.rowwise().mean().replicate(1, truth.cols());
  EXPECT_NEAR(th::eval::averageMse(mean, truth), 1.0, 1e-12) << "the mean prediction scores exactly 1";
  EXPECT_NEAR(th::eval::averageCorrelation(mean, truth), 0.0, 1e-9);
  EXPECT_NEAR(th::eval::averageCorrelation(-truth, truth), -1.0, 1e-12);
  // Correlation ignores scale and offset; ε does not.
  EXPECT_NEAR(th::eval::averageCorrelation(5.0 * truth.array() + 1.0, truth), 1.0, 1e-12);
  EXPECT_GT(th::eval::averageMse(5.0 * truth.array() + 1.0, truth), 10.0);
  EXPECT_THROW(th::eval::averageMse(truth.leftCols(10), truth), Error);
}

// Recordings where the audio (3 "MFCC" dimensions) and the visual parameters (4, driven by 2 sources) share a
// hidden 3-state process.
MouthRecording synthetic(int frames, unsigned seed) {
  hmm::HmmModel joint;
  joint.initial = Eigen::Vector3d::Constant(1.0 / 3.0);
  joint.transition = Eigen::Matrix3d::Constant(0.05);
  joint.transition.diagonal().setConstant(0.9);
  for (int j = 0; j < 3; ++j) {
    Eigen::VectorXd mean(5);
    mean << 2.0 * (j - 1), 1.0 * (j == 1), -1.0 * (j == 2), 1.5 * (j - 1), 1.0 * (j == 0);
    // The visual sources vary little within a state, so the audio (through the state) can explain them.
    const Eigen::VectorXd variances = (Eigen::VectorXd(5) << 0.1, 0.1, 0.1, 0.01, 0.01).finished();
    joint.states.emplace_back(Eigen::VectorXd::Ones(1), std::vector<hmm::Gaussian>{hmm::Gaussian(
                                                            mean, variances.asDiagonal(), hmm::CovarianceType::kFull)});
  }
  std::mt19937 random(seed);
  const hmm::Sample sample = hmm::sampleHmm(joint, frames, random);
  MouthRecording recording;
  recording.speech.mfcc = sample.frames.topRows(3);
  const Eigen::MatrixXd sources = sample.frames.bottomRows(2);
  Eigen::MatrixXd mixing(4, 2);
  mixing << 1.0, 0.2, 0.5, 1.0, -0.3, 0.8, 0.9, -0.4;
  recording.visual = mixing * sources;
  return recording;
}

TEST(MouthModel, RecoversTheVisualPartFromAudioOnHeldOutData) {
  const MouthRecording train = synthetic(3000, 1);
  const MouthRecording test = synthetic(1000, 2);
  for (hmm::CovarianceType covariance : {hmm::CovarianceType::kFull, hmm::CovarianceType::kDiagonal}) {
    const MouthModel model =
        trainMouthModel({train}, {.states = 3, .mixtures = 1, .covariance = covariance, .contextFrames = 1});
    EXPECT_EQ(model.hmm.block("audio").size, 9);
    EXPECT_EQ(model.hmm.block("visual").size, 2);
    const Eigen::MatrixXd truth = model.basis.transform(test.visual);
    for (MouthMethod method : {MouthMethod::kInversion, MouthMethod::kMmse}) {
      const Eigen::MatrixXd estimate = synthesiseMouth(model, test.speech, {.method = method});
      const double rho = th::eval::averageCorrelation(estimate, truth);
      const double epsilon = th::eval::averageMse(estimate, truth);
      std::printf("[ INFO     ] %s, %s: held-out epsilon %.3f, rho %.3f\n",
                  covariance == hmm::CovarianceType::kFull ? "full" : "diagonal",
                  method == MouthMethod::kMmse ? "MMSE" : "inversion", epsilon, rho);
      EXPECT_GT(rho, 0.9);
      EXPECT_LT(epsilon, 0.2);
    }
    // Audio from elsewhere: the estimate no longer follows the truth.
    th::animation::SpeechFrames shuffled{Eigen::MatrixXd(test.speech.mfcc.rows(), test.speech.mfcc.cols()), {}};
    shuffled.mfcc << test.speech.mfcc.rightCols(500), test.speech.mfcc.leftCols(500);
    EXPECT_LT(std::abs(th::eval::averageCorrelation(synthesiseMouth(model, shuffled), truth)), 0.2);
    // Reconstruction gives back the visual parameters' units.
    const Eigen::MatrixXd visual = model.basis.reconstruct(synthesiseMouth(model, test.speech));
    EXPECT_EQ(visual.rows(), 4);
    EXPECT_LT((visual - test.visual).cwiseAbs().mean(), 0.3);
  }
  const MouthModel model = trainMouthModel({train}, {.states = 3, .mixtures = 1, .contextFrames = 1});
  EXPECT_THROW(synthesiseMouth(model, {Eigen::MatrixXd::Zero(5, 10), {}}), Error) << "audio of the wrong dimension";
}

TEST(MouthSynthesiser, StreamsTheWindowedSynthesisFrameByFrame) {
  const MouthRecording train = synthetic(2000, 3);
  const MouthRecording test = synthetic(250, 4);
  const MouthModel model = trainMouthModel({train}, {.states = 3, .mixtures = 2, .contextFrames = 2});
  for (const MouthMethod method : {MouthMethod::kInversion, MouthMethod::kMmse}) {
    for (const int window : {1, 4, 30}) {
      const MouthSynthesisOptions options{.method = method, .windowFrames = window, .maxIterations = 20};
      const Eigen::MatrixXd batch = synthesiseMouth(model, test.speech, options);
      MouthSynthesiser stream(model, options);
      EXPECT_EQ(stream.lookaheadFrames(), 2 + window - 1);
      Eigen::MatrixXd streamed(batch.rows(), batch.cols());
      Eigen::Index out = 0;
      Eigen::VectorXd frame;
      for (Eigen::Index t = 0; t < test.speech.numFrames(); ++t) {
        stream.acceptFrame(0.0, test.speech.mfcc.col(t));
        while (stream.next(frame)) streamed.col(out++) = frame;
        EXPECT_GE(out, t + 1 - stream.lookaheadFrames()) << "frame " << t;
      }
      stream.finish();
      while (stream.next(frame)) streamed.col(out++) = frame;
      ASSERT_EQ(out, batch.cols());
      EXPECT_LT((streamed - batch).cwiseAbs().maxCoeff(), 1e-12)
          << (method == MouthMethod::kMmse ? "MMSE" : "inversion") << ", window " << window;
    }
  }
  EXPECT_THROW(MouthSynthesiser(model, {.windowFrames = 0}), Error) << "batch is not a stream";
  MouthSynthesiser stream(model, {.windowFrames = 3});
  EXPECT_THROW(stream.acceptFrame(0.0, Eigen::VectorXd::Zero(5)), Error) << "MFCCs of the wrong size";
}

TEST(MouthSynthesiser, AModelThatHearsNoLaterFrameStreamsWithoutLookAhead) {
  const MouthRecording train = synthetic(2000, 3);
  const MouthRecording test = synthetic(200, 4);
  const MouthModelOptions options{.states = 3, .mixtures = 1, .contextFrames = 2, .futureContextFrames = 0};
  const MouthModel model = trainMouthModel({train}, options);
  EXPECT_EQ(model.contextWidth(), 3);
  EXPECT_EQ(model.hmm.block("audio").size, 3 * test.speech.mfcc.rows());
  const MouthSynthesisOptions synthesis{.windowFrames = 1, .maxIterations = 20};
  const Eigen::MatrixXd batch = synthesiseMouth(model, test.speech, synthesis);
  MouthSynthesiser stream(model, synthesis);
  EXPECT_EQ(stream.lookaheadFrames(), 0);
  Eigen::VectorXd frame;
  for (Eigen::Index t = 0; t < test.speech.numFrames(); ++t) {
    stream.acceptFrame(0.0, test.speech.mfcc.col(t));
    ASSERT_TRUE(stream.next(frame)) << "frame " << t << " is out as soon as it is in";
    EXPECT_LT((frame - batch.col(t)).cwiseAbs().maxCoeff(), 1e-12) << "frame " << t;
    EXPECT_FALSE(stream.next(frame));
  }
  // Its file keeps the asymmetric context (the shipped files, without the field, read as symmetric).
  const TemporaryFile file(".json");
  saveMouthModel(file.path(), model, options);
  const MouthModel loaded = loadMouthModel(file.path());
  EXPECT_EQ(loaded.contextFrames, 2);
  EXPECT_EQ(loaded.futureContextFrames, 0);
  EXPECT_EQ(synthesiseMouth(loaded, test.speech), synthesiseMouth(model, test.speech));
}

TEST(MouthModel, FileRoundTripAndRefusals) {
  const MouthModelOptions options{.states = 3, .mixtures = 1, .contextFrames = 1};
  const MouthModel model = trainMouthModel({synthetic(1500, 3)}, options);
  const TemporaryFile file(".json");
  saveMouthModel(file.path(), model, options);
  const MouthModel loaded = loadMouthModel(file.path());
  EXPECT_EQ(loaded.contextFrames, 1);
  EXPECT_EQ(loaded.futureContextFrames, 1);
  const MouthRecording test = synthetic(300, 4);
  EXPECT_EQ(synthesiseMouth(loaded, test.speech), synthesiseMouth(model, test.speech));
  EXPECT_EQ(loaded.basis.transform(test.visual), model.basis.transform(test.visual));
  // A plain HMM file is not a mouth model; a mouth model with its basis damaged is refused, naming the file.
  const TemporaryFile plain(".json");
  hmm::saveModel(plain.path(), model.hmm);
  EXPECT_THROW(loadMouthModel(plain.path()), Error);
  std::ostringstream buffer;
  buffer << std::ifstream(file.path()).rdbuf();
  const std::string text = buffer.str();
  const size_t at = text.find("\"explained_variance\"");
  ASSERT_NE(at, std::string::npos);
  const TemporaryFile damaged(".json");
  {
    std::ofstream out(damaged.path());
    out << text.substr(0, at) << "\"explained_variance\":7," << text.substr(text.find(',', at) + 1);
  }
  try {
    loadMouthModel(damaged.path());
    FAIL() << "a basis with explained variance 7 was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(damaged.path().string()), std::string::npos) << error.what();
  }
}

TEST(MouthModel, AModelOfFapsDrivesThemAndItsFileSaysWhich) {
  // The synthetic visual rows taken as FAPs 3, 4, 51, 52 (as a model trained from tracked video has them).
  MouthModelOptions options{.states = 3, .mixtures = 1, .contextFrames = 1};
  options.standardiseVisual = false;
  MouthModel model = trainMouthModel({synthetic(1500, 5)}, options);
  EXPECT_FALSE(th::animation::drivesFaps(model));
  EXPECT_THROW(th::animation::mouthFapNumbers(model), Error);
  model.visualFaps = {3, 4, 51, 52};
  EXPECT_TRUE(th::animation::drivesFaps(model));
  const MouthRecording test = synthetic(300, 6);
  const Eigen::MatrixXd components = synthesiseMouth(model, test.speech);
  const Eigen::MatrixXd faps = th::animation::mouthFapsOf(model, components);
  Eigen::MatrixXd expected = model.basis.reconstruct(components);
  expected.row(0) = expected.row(0).cwiseMax(0.0);  // the jaw does not close past rest
  EXPECT_EQ(faps, expected);
  EXPECT_LT(expected.row(0).minCoeff(), 1e-12);
  EXPECT_THROW(th::animation::jawOpeningOf(model, components), Error);

  const TemporaryFile file(".json");
  saveMouthModel(file.path(), model, options);
  const MouthModel loaded = loadMouthModel(file.path());
  EXPECT_EQ(loaded.visualFaps, model.visualFaps);
  EXPECT_EQ(th::animation::mouthFapsOf(loaded, components), faps);
  // A list that does not match the basis, or is not ascending FAP numbers, is refused naming the file.
  std::ostringstream buffer;
  buffer << std::ifstream(file.path()).rdbuf();
  const std::string text = buffer.str();
  for (const char* broken : {"[3,4,51]", "[3,51,4,52]", "[3,4,51,99]", "\"3\""}) {
    const std::string good = "\"visual_faps\":[3,4,51,52]";
    const size_t at = text.find(good);
    ASSERT_NE(at, std::string::npos);
    const TemporaryFile damaged(".json");
    std::ofstream(damaged.path()) << text.substr(0, at) << "\"visual_faps\":" << broken
                                  << text.substr(at + good.size());
    try {
      loadMouthModel(damaged.path());
      FAIL() << broken << " was accepted";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("visual_faps"), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(damaged.path().string()), std::string::npos) << error.what();
    }
  }
}

// The synthetic recordings with a level per frame (dB, following the first audio dimension), as real speech
// frames have.
MouthRecording withLevel(MouthRecording recording, double gainDb = 0.0) {
  recording.speech.levelDb = (4.0 * recording.speech.mfcc.row(0)).array() - 30.0 + gainDb;
  return recording;
}

std::vector<MouthRecording> syntheticSet(int count, int frames, unsigned seed) {
  std::vector<MouthRecording> set;
  for (int i = 0; i < count; ++i) set.push_back(withLevel(synthetic(frames, seed + static_cast<unsigned>(i))));
  return set;
}

const MouthModelOptions kNormalisedDeltas{.states = 3,
                                          .mixtures = 1,
                                          .contextFrames = 1,
                                          .normaliseSpeech = true,
                                          .visualDeltas = true,
                                          .varianceValidationEvery = 3};

TEST(MouthModel, NormalisedSpeechAndDeltasStreamAsTheirBatchAndSurviveTheirFile) {
  const MouthModel model = trainMouthModel(syntheticSet(6, 400, 30), kNormalisedDeltas);
  ASSERT_TRUE(model.normalisation.has_value());
  EXPECT_EQ(model.speechRowsPerFrame(), 4) << "3 MFCCs and the level";
  EXPECT_EQ(model.hmm.block("audio").size, 12);
  EXPECT_EQ(model.hmm.block("visual").size, 4) << "2 components and their deltas";
  ASSERT_EQ(model.varianceScale.size(), 2);
  EXPECT_TRUE((model.varianceScale.array() >= 1.0).all());
  const MouthRecording test = withLevel(synthetic(250, 40));
  // Streaming, frame by frame: the windowed batch's values (MLPG needs the whole stretch, so windows decode
  // frame estimates).
  for (const MouthMethod method : {MouthMethod::kInversion, MouthMethod::kMmse}) {
    const MouthSynthesisOptions options{.method = method, .windowFrames = 3, .maxIterations = 20};
    const Eigen::MatrixXd batch = synthesiseMouth(model, test.speech, options);
    ASSERT_EQ(batch.rows(), 2);
    MouthSynthesiser stream(model, options);
    Eigen::MatrixXd streamed(batch.rows(), batch.cols());
    Eigen::Index out = 0;
    Eigen::VectorXd frame;
    for (Eigen::Index t = 0; t < test.speech.numFrames(); ++t) {
      stream.acceptFrame(test.speech.levelDb[t], test.speech.mfcc.col(t));
      while (stream.next(frame)) streamed.col(out++) = frame;
    }
    stream.finish();
    while (stream.next(frame)) streamed.col(out++) = frame;
    ASSERT_EQ(out, batch.cols());
    EXPECT_LT((streamed - batch).cwiseAbs().maxCoeff(), 1e-12);
  }
  const TemporaryFile file(".json");
  saveMouthModel(file.path(), model, kNormalisedDeltas);
  const MouthModel loaded = loadMouthModel(file.path());
  EXPECT_TRUE(loaded.visualDeltas);
  EXPECT_EQ(loaded.normalisation->priorMean, model.normalisation->priorMean);
  EXPECT_EQ(loaded.varianceScale, model.varianceScale);
  EXPECT_EQ(synthesiseMouth(loaded, test.speech, {.method = MouthMethod::kMmse}),
            synthesiseMouth(model, test.speech, {.method = MouthMethod::kMmse}));
  // A model that needs levels refuses speech without them; a damaged normalisation or scale is refused naming the
  // file.
  EXPECT_THROW(synthesiseMouth(model, {test.speech.mfcc, {}}), Error);
  std::ostringstream buffer;
  buffer << std::ifstream(file.path()).rdbuf();
  const std::string text = buffer.str();
  for (const auto& [field, broken] :
       std::vector<std::pair<std::string, std::string>>{{"\"level_unit_db\":", "\"level_unit_db\":-1,"},
                                                        {"\"variance_scale\":", "\"variance_scale\":[1.0],"},
                                                        {"\"visual_deltas\":", "\"visual_deltas\":false,"}}) {
    const size_t at = text.find(field);
    ASSERT_NE(at, std::string::npos) << field;
    const size_t end =
        text[text.find_first_not_of(' ', at + field.size())] == '[' ? text.find(']', at) + 2 : text.find(',', at) + 1;
    const TemporaryFile damaged(".json");
    std::ofstream(damaged.path()) << text.substr(0, at) << broken << text.substr(end);
    try {
      loadMouthModel(damaged.path());
      FAIL() << broken << " was accepted";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(damaged.path().string()), std::string::npos) << error.what();
    }
  }
}

TEST(MouthModel, AGainOnTheSpeechLeavesTheMouthAsItWas) {
  const MouthModel model = trainMouthModel(syntheticSet(6, 400, 50), kNormalisedDeltas);
  const MouthRecording test = withLevel(synthetic(300, 60));
  const MouthRecording quieter = withLevel(synthetic(300, 60), -20.0);
  EXPECT_LT((synthesiseMouth(model, test.speech) - synthesiseMouth(model, quieter.speech)).cwiseAbs().maxCoeff(), 1e-9);
}

// A mouth that moves smoothly (a slow random process) and speech that hears it through noise, frame by frame:
// the frames' own estimates jitter with the noise, as real ones do.
MouthRecording smoothSynthetic(int frames, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  MouthRecording recording;
  recording.speech.mfcc.resize(3, frames);
  recording.visual.resize(4, frames);
  double s = 0.0, velocity = 0.0;
  for (int t = 0; t < frames; ++t) {
    velocity = 0.9 * velocity + 0.1 * normal(random);
    s = 0.98 * s + velocity;
    recording.speech.mfcc.col(t) << s + 0.7 * normal(random), std::abs(s) + 0.7 * normal(random), normal(random);
    recording.visual.col(t) << s, 0.5 * s, -0.3 * s, 0.2 * s;
    recording.visual.col(t) += 0.05 * Eigen::Vector4d(normal(random), normal(random), normal(random), normal(random));
  }
  return withLevel(recording);
}

TEST(MouthModel, TheTrajectoryIsSmootherAndVarianceCompensationRestoresTheSpread) {
  std::vector<MouthRecording> training;
  for (unsigned i = 0; i < 9; ++i) training.push_back(smoothSynthetic(500, 70 + i));
  MouthModelOptions options = kNormalisedDeltas;
  options.states = 6;
  options.visualComponents = 1;  // the mouth here has one degree of freedom
  const MouthModel model = trainMouthModel(training, options);
  const MouthRecording test = smoothSynthetic(1500, 90);
  const Eigen::MatrixXd truth = model.basis.transform(test.visual);
  const auto roughness = [](const Eigen::MatrixXd& x) {
    return (x.rightCols(x.cols() - 2) - 2.0 * x.middleCols(1, x.cols() - 2) + x.leftCols(x.cols() - 2)).squaredNorm();
  };
  const MouthSynthesisOptions plain{.method = MouthMethod::kMmse, .varianceCompensation = false};
  MouthSynthesisOptions frames = plain;
  frames.trajectory = false;
  const Eigen::MatrixXd trajectory = synthesiseMouth(model, test.speech, plain);
  const Eigen::MatrixXd frameByFrame = synthesiseMouth(model, test.speech, frames);
  std::printf("[ INFO     ] roughness: truth %.1f, trajectory %.1f, frames %.1f; rho %.3f / %.3f\n", roughness(truth),
              roughness(trajectory), roughness(frameByFrame), th::eval::averageCorrelation(trajectory, truth),
              th::eval::averageCorrelation(frameByFrame, truth));
  EXPECT_LT(roughness(trajectory), 0.9 * roughness(frameByFrame));
  EXPECT_GT(th::eval::averageCorrelation(trajectory, truth), th::eval::averageCorrelation(frameByFrame, truth) - 0.02);
  // Compensated, each component's spread comes nearer the truth's (the estimates shrink towards the mean).
  const Eigen::MatrixXd compensated = synthesiseMouth(model, test.speech, {.method = MouthMethod::kMmse});
  // Standard deviations of each component (rows), over the frames.
  const auto spreads = [](const Eigen::MatrixXd& x) {
    const Eigen::MatrixXd centred = x.colwise() - x.rowwise().mean();
    return Eigen::VectorXd((centred.rowwise().squaredNorm() / static_cast<double>(x.cols())).cwiseSqrt());
  };
  const Eigen::VectorXd target = spreads(truth), before = spreads(trajectory), after = spreads(compensated);
  for (Eigen::Index k = 0; k < truth.rows(); ++k) {
    std::printf("[ INFO     ] component %ld: spread %.3f -> %.3f, the truth's %.3f (factor %.2f)\n",
                static_cast<long>(k), before[k], after[k], target[k], model.varianceScale[k]);
    EXPECT_LE(std::abs(after[k] - target[k]), std::abs(before[k] - target[k]) + 1e-12);
  }
}

TEST(MouthData, Beat2TakeIsAligned) {
  const MouthRecording take = th::eval::loadBeat2Mouth();
  EXPECT_EQ(take.numFrames(), 1906);
  EXPECT_EQ(take.visual.rows(), 101);
  EXPECT_EQ(take.speech.mfcc.rows(), 11);
  EXPECT_EQ(take.speech.levelDb.size(), take.numFrames());
  EXPECT_TRUE(take.speech.mfcc.allFinite() && take.speech.levelDb.allFinite());
  EXPECT_TRUE(take.visual.allFinite());
}

}  // namespace
}  // namespace th::animation
