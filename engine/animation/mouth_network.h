// The articulatory mouth: a small network (nn/network.h) that hears ~0.3 s of speech around a frame and says,
// at once, which mouth class the frame shows (the 17 of face/visemes.h), how the jaw and lips are placed (K
// components of the jaw and lip FAPs) and whether the lips are shut. One network answers all three, so the
// visemes, the face's lips and its closures come from one judgement; it is trained on every speaker's tracked
// lips and on every phone-labelled recording together, each frame training the answers it has a truth for.
//
//   th::animation::MouthNetwork model = th::animation::trainMouthNetwork(recordings, {});
//   th::animation::MouthNetworkOutput out = th::animation::runMouthNetwork(model, subframes);
//   Eigen::MatrixXd faps = th::animation::mouthNetworkFaps(model, out);          // jaw and lip FAPs, FAPU counts
//   (animation/articulation.h turns the output into the visemes and the lips' closures and shape)
//
// What it hears: 13 MFCCs (c1..c13) and the level at three times the animation's rate (90 a second, 25 ms
// windows: a /p/'s closure and burst are 20-80 ms, which 30 fps frames 33 ms apart with 25 ms windows can
// miss), normalised as the mouth model's speech is (features/speech_normaliser.h: cepstral mean and the level
// against its recent peak, causally, so any voice, microphone and level), pastSubframes before a frame's
// centre and futureSubframes after it (the look-ahead: what live use waits for).
// Thread contract: models are values; the functions are pure.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "animation/mouth_data.h"
#include "animation/viseme_model.h"
#include "animation/visual_basis.h"
#include "face/visemes.h"
#include "features/online_features.h"
#include "features/speech_normaliser.h"
#include "nn/network.h"
#include "nn/training.h"

namespace th::animation {

// Speech frames for the network: kSubframesPerFrame per animation frame; subframe 3i is centred on frame i.
inline constexpr int kSubframesPerFrame = 3;
inline constexpr double kSubframesPerSecond = kMouthFramesPerSecond * kSubframesPerFrame;
inline constexpr int kNetworkMfcc = 13;

// c1..c13 and the level at 90 frames a second (features/online_features.h, no pitch): 13 x 3T. frequencyWarp:
// the filterbank's vocal tract length perturbation (features/mfcc.h), for training on more voices.
SpeechFrames speechSubframesOf(std::span<const float> samples16k, double frequencyWarp = 1.0);
// The extractor's settings behind speechSubframesOf, for a stream (MouthNetworkStream's input).
features::FeatureOptions subframeFeatureOptions(double frequencyWarp = 1.0);

struct MouthNetworkOptions {
  int pastSubframes = 24;   // 267 ms before the frame's centre
  int futureSubframes = 9;  // 100 ms after it: the look-ahead
  std::vector<int> hidden{256, 256};
  int visualComponents = 6;  // K components of the jaw and lip FAPs (PCA + ICA, visual_basis.h)
  // The weight of each answer in the loss: mouth classes (cross-entropy), the FAP components and the lips'
  // opening and width (squared error in units of their deviation), the lips shut (binary cross-entropy).
  double classWeight = 1.0;
  double visualWeight = 1.0;
  double shapeWeight = 1.0;
  double closureWeight = 1.0;
  // The lips count as shut where their inner opening (track.h mouthOpening, eye-corner distances) is below this.
  double closedOpening = 0.04;
  features::SpeechNormalisationOptions normalisation{};
  nn::TrainingOptions training{.epochs = 30,
                               .batchFrames = 256,
                               .learningRate = 1e-3,
                               .finalLearningRate = 1e-5,
                               .weightDecay = 1e-4,
                               .dropout = 0.2,
                               .inputNoise = 0.1,
                               .seed = 1};
  void check() const;  // throws th::Error naming the bad option
};

// One training recording at 30 fps: its speech subframes and whatever truths it has for its T frames.
struct NetworkRecording {
  std::string name;
  std::string speaker;
  SpeechFrames subframes;    // kNetworkMfcc x 3T (or more: the rest is context)
  std::vector<int> classes;  // T mouth classes (-1: none), or empty
  Eigen::MatrixXd faps;      // visual FAPs x T (rows: the corpus's FAPs), or empty
  Eigen::MatrixXd lipShape;  // 2 x T: inner-lip opening and mouth width (track.h), or empty
  double weight = 1.0;       // how much each of its frames counts in training (to balance speakers)
  // Where its running cepstral mean starts (c1..c13; empty: the model's prior): a short clip of a speaker heard
  // as a stream that has already adapted to them.
  Eigen::VectorXd startMean;
  int numFrames() const;  // T: the longest of the truths
};

struct MouthNetwork {
  int pastSubframes = 24;
  int futureSubframes = 9;
  features::SpeechNormalisationOptions normalisation;
  Eigen::VectorXd priorMean;  // the training speech's mean c1..c13
  nn::Network network;
  // Output layout: classes [0, 17), components [17, 17 + K), opening and width (standardised), shut.
  std::vector<nn::Head> heads;
  VisualBasis basis;                                              // of the FAPs
  std::vector<int> visualFaps;                                    // the basis's rows, ascending
  Eigen::Vector2d shapeMean{0.0, 0.0}, shapeDeviation{1.0, 1.0};  // of the lips' opening and width
  Eigen::VectorXd classPriors;                                    // the training frames' class shares (17)
  ClassSequence sequence;  // how the training frames' classes follow one another (the visemes' HMM)
  // visualFaps x 17: each class's mean FAPs over the training frames that have both, less their mean (the
  // lips' typical shape for the class: rounded for oh and ou, spread for E and ih; zero for a class never seen).
  Eigen::MatrixXd classShapes;
  // d(inner-lip opening) / d(FAP) for each visual FAP, measured on the face the FAPs drive (eye-corner
  // distances per FAPU count; the trainer sets it, eval/mouth_scores.h openingGradient): how far the lips are
  // from meeting, for closing them. Empty: not known, and the lips cannot be closed by the articulation.
  Eigen::VectorXd openingGradient;

  int inputsPerSubframe() const { return kNetworkMfcc + 1; }
  int contextSubframes() const { return pastSubframes + futureSubframes + 1; }
  int lookaheadMs() const;
};

struct MouthNetworkOutput {
  Eigen::MatrixXd classes;     // 17 x T: P(class | speech)
  Eigen::MatrixXd components;  // K x T
  Eigen::MatrixXd lipShape;    // 2 x T: opening and width (eye-corner distances)
  Eigen::RowVectorXd shut;     // T: P(lips shut)
  int numFrames() const { return static_cast<int>(shut.size()); }
};

struct MouthNetworkTraining {
  MouthNetwork model;
  nn::TrainingReport report;
};
// validation: recordings whose loss picks the epoch kept (may be empty: the last epoch is kept).
MouthNetworkTraining trainMouthNetwork(const std::vector<NetworkRecording>& recordings,
                                       const std::vector<int>& visualFaps, const MouthNetworkOptions& options,
                                       const std::vector<NetworkRecording>& validation = {});

// The network's inputs for T = subframes / 3 frames (inputs x T). startMean: where the running cepstral mean
// starts (c1..c13; nullptr or empty: the model's prior, the training speech's mean) — a stream that has heard
// this speaker for a while has their mean.
Eigen::MatrixXf mouthNetworkInputs(const MouthNetwork& model, const SpeechFrames& subframes,
                                   const Eigen::VectorXd* startMean = nullptr);
MouthNetworkOutput runMouthNetwork(const MouthNetwork& model, const SpeechFrames& subframes,
                                   const Eigen::VectorXd* startMean = nullptr);
// The FAPs of the components (rows: visualFaps); the jaw (FAP 3) never below 0.
Eigen::MatrixXd mouthNetworkFaps(const MouthNetwork& model, const MouthNetworkOutput& output);

// The network frame by frame, for live use: each speech subframe in as it comes (c1..c13 and the level), each
// frame's answers out once its look-ahead (futureSubframes) has come, or the input has ended. The same answers as
// runMouthNetwork on the whole input with the model's prior mean, frame for frame. Holds only the context a
// frame needs. The model must outlive the stream.
struct MouthNetworkFrame {
  Eigen::VectorXd classes;  // 17: P(class | speech)
  double shut = 0.0;        // P(lips shut)
};
class MouthNetworkStream {
 public:
  explicit MouthNetworkStream(const MouthNetwork& model);
  void accept(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc);
  void finish();
  bool next(MouthNetworkFrame& frame);
  std::size_t subframesHeld() const { return normalised_.size(); }

 private:
  const MouthNetwork& model_;
  features::OnlineSpeechNormaliser normaliser_;
  nn::Inference inference_;
  std::deque<Eigen::VectorXd> normalised_;  // subframes from base_ on
  Eigen::Index base_ = 0, received_ = 0, nextFrame_ = 0;
  bool finished_ = false;
  Eigen::VectorXf input_;
  Eigen::MatrixXf output_;
};

void saveMouthNetwork(const std::filesystem::path& path, const MouthNetwork& model);
MouthNetwork loadMouthNetwork(const std::filesystem::path& path);  // errors name the file and the field

}  // namespace th::animation
