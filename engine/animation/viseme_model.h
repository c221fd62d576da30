// Visemes from speech: which of the mouth classes (face/visemes.h) each 30 fps frame shows, heard from the same
// normalised MFCCs the mouth model inverts, for the viseme and mouth-cue formats and the live outputs.
//
//   th::animation::VisemeModel model = th::animation::trainVisemeModel(labelled, {});
//   th::face::VisemeTrack visemes = th::animation::decodeVisemes(model, heard.speech);   // batch
//
//   th::animation::VisemeStream stream(model);                                          // live, frame by frame
//   stream.accept(levelDb, mfcc);                                                       // each speech frame
//   while (stream.next(frame)) use(frame.probabilities, frame.mouthClass);
//
// The model, in three layers:
// - Each frame's features are the speech normaliser's c1..c11 and level (features/speech_normaliser.h, any
//   voice, microphone and level) with ±tc frames of context (features/context.h): 12 (2 tc + 1) values.
// - Linear discriminant analysis projects them onto the directions that best separate the classes (the
//   generalised eigenvectors of the between-class and within-class scatter), where each class is a Gaussian
//   mixture (trained by EM as a one-state HMM, hmm/training.h).
// - An HMM over the classes decodes the sequence. Each class is a chain of minHoldFrames states that must be
//   passed in turn, so a class once entered is shown for at least that long (no 1-2-frame flicker); the
//   chain's last state loops with the probability that gives the class's mean run length in the training
//   labels, and leaves to the next class by the labels' class bigrams. The emission log-likelihoods are
//   scaled by emissionScale (context frames overlap, so a frame's evidence is counted several times; the
//   scale is measured by cross-validation across speakers, docs/visemes.md).
// Batch decoding gives each frame's class probabilities (forward-backward) and the shown classes (Viterbi).
// The stream gives the same probabilities with a fixed lag (hmm/forward_backward.h FixedLagSmoother) and
// the shown class by online Viterbi with the same maximum lag, held for minHoldFrames where a decision the lag
// forced would cut it short.
// Thread contract: models are values; decodeVisemes is a pure function; a VisemeStream belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "animation/mouth_data.h"
#include "face/visemes.h"
#include "features/context.h"
#include "features/speech_normaliser.h"
#include "hmm/forward_backward.h"
#include "hmm/hmm_model.h"
#include "hmm/viterbi.h"

namespace th::animation {

struct VisemeModelOptions {
  int contextFrames = 2;  // tc: ±67 ms at 30 fps
  int dimensions = 10;    // LDA directions kept (at most the classes less one)
  int mixtures = 2;       // Gaussians per class
  int minHoldFrames = 3;  // 100 ms at 30 fps
  double emissionScale = 0.5;
  features::SpeechNormalisationOptions normalisation{};
  unsigned seed = 1;
  void check() const;  // throws th::Error naming the bad option
};

// A recording's speech frames and each frame's class (face::MouthClass, or -1 where unlabelled).
struct LabelledSpeech {
  SpeechFrames speech;
  std::vector<int> classes;
};

struct VisemeModel {
  int contextFrames = 2;
  int minHoldFrames = 3;
  double emissionScale = 0.5;
  features::SpeechNormalisationOptions normalisation;
  Eigen::VectorXd priorMean;   // the training speech's mean c1..c11
  Eigen::VectorXd inputMean;   // of the stacked features
  Eigen::MatrixXd projection;  // dimensions x 12 (2 tc + 1): the LDA directions
  hmm::HmmModel hmm;           // state s shows class s / minHoldFrames
  int classOfState(int state) const { return state / minHoldFrames; }
};

// Throws th::Error if a class has fewer frames than its mixtures need, or the labels and frames disagree.
VisemeModel trainVisemeModel(const std::vector<LabelledSpeech>& recordings, const VisemeModelOptions& options);

// The projected features the HMM reads (dimensions x T).
Eigen::MatrixXd visemeFeatures(const VisemeModel& model, const SpeechFrames& speech);
face::VisemeTrack decodeVisemes(const VisemeModel& model, const SpeechFrames& speech);

// How the mouth classes follow one another in labelled frames (each recording's classes, -1 unlabelled): each
// class's mean run in frames (0: never seen), and add-½-smoothed counts of the run bigrams and of the first runs.
struct ClassSequence {
  Eigen::VectorXd meanRun;  // kNumMouthClasses
  Eigen::MatrixXd bigrams;  // kNumMouthClasses x kNumMouthClasses: from (row) → to (column)
  Eigen::VectorXd starts;   // kNumMouthClasses
};
ClassSequence classSequenceOf(const std::vector<std::vector<int>>& labels);

// The class HMM: minHoldFrames states per class in a chain, the last looping so that the class's mean run is
// the sequence's, leaving by its bigrams. emissions: one density per class (empty: the states carry none, for
// evidence from elsewhere, decodeClassEvidence).
hmm::HmmModel classHmm(const ClassSequence& sequence, int minHoldFrames,
                       const std::vector<hmm::GaussianMixture>& emissions = {});

// Decoding from any per-class evidence (kNumMouthClasses x T log-likelihoods, e.g. a network's scaled log
// posteriors over its priors): forward-backward class probabilities and the Viterbi path. Throws th::Error if
// the shapes disagree.
face::VisemeTrack decodeClassEvidence(const hmm::HmmModel& classes, int minHoldFrames,
                                      const Eigen::MatrixXd& classLogLikelihoods);

// The per-frame most likely class with no HMM (each frame alone): what the HMM's smoothing is measured against.
std::vector<int> classifyFrames(const VisemeModel& model, const SpeechFrames& speech);

void saveVisemeModel(const std::filesystem::path& path, const VisemeModel& model);
VisemeModel loadVisemeModel(const std::filesystem::path& path);  // errors name the file and the field

// One decoded frame of a stream.
struct VisemeFrame {
  Eigen::VectorXd probabilities;  // kNumMouthClasses
  int mouthClass = 0;
};

// Two sources: the viseme model's own (accept each speech frame), or any per-class evidence (acceptEvidence,
// decodeClassEvidence's) decoded with a class HMM. The stream keeps a reference to the model or the HMM.
class VisemeStream {
 public:
  // lagFrames: how many frames after a frame its class is decided (beyond the context's tc).
  explicit VisemeStream(const VisemeModel& model, int lagFrames = 2);
  VisemeStream(const hmm::HmmModel& classes, int minHoldFrames, int lagFrames);
  void accept(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc);         // the viseme model's stream only
  void acceptEvidence(const Eigen::Ref<const Eigen::VectorXd>& classLogLikelihoods);  // kNumMouthClasses
  void finish();  // the input has ended: the frames still waiting are decided
  bool next(VisemeFrame& frame);
  int latencyFrames() const { return (model_ != nullptr ? model_->contextFrames : 0) + lagFrames_; }

 private:
  void pushStacked(const Eigen::VectorXd& stacked);

  const VisemeModel* model_ = nullptr;
  const hmm::HmmModel& hmm_;
  int minHoldFrames_;
  int lagFrames_;
  std::optional<features::OnlineSpeechNormaliser> normaliser_;
  std::optional<features::ContextStacker> stacker_;
  hmm::FixedLagSmoother smoother_;
  hmm::OnlineViterbi viterbi_;
  Eigen::VectorXd normalised_, stateEvidence_;
  int taken_ = 0;
  int shownClass_ = 0;
  int shownFrames_ = 0;
};

}  // namespace th::animation
