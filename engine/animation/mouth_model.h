// Mouth from audio (the second source paper, Terissi & Gómez): a joint audio-visual HMM over [audio features with
// ±tc frames of context | K visual components (and their deltas)], inverted to recover the visual part from
// audio alone.
//
//   th::animation::MouthModel model = th::animation::trainMouthModel(recordings, {.states = 8, .mixtures = 2});
//   Eigen::MatrixXd components = th::animation::synthesiseMouth(model, speech, {});   // K x T
//   Eigen::MatrixXd faps = th::animation::mouthFapsOf(model, components);             // jaw and lip FAPs
//
// The visual components are ICA after PCA (visual_basis.h) of the visual parameters, fitted on the training
// part: the jaw and lip FAPs themselves for models trained from tracked video (the shipped ones: `talkinghead
// train mouth`, eval/talking_corpus.h; visualFaps names them), or BEAT2's [jaw opening, 100 expression
// coefficients] for the paper's model (turned into FAPs by the FAP map). The audio is c1..c11 as the paper has
// it, or normalised for any voice, microphone and level (features/speech_normaliser.h). The HMM is trained by
// Baum-Welch (maximum likelihood, as the paper) with full or diagonal covariance. Synthesis: HMM inversion
// (hmm/inversion.h, eq. 7/8) from the paper's random start or from the audio-only conditional mean (ours), or
// the non-iterative MMSE estimate; batch or windowed. A model with the components' deltas generates the
// trajectory (MLPG, mlpg.h) from the frames' Gaussians in batch; one with a variance scale restores the spread
// that averaging over states takes away (global variance compensation, measured on held-out sequences).
// Thread contract: models are values; synthesis is a pure function.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <filesystem>
#include <optional>
#include <vector>

#include "animation/fap_mapping.h"
#include "animation/mouth_data.h"
#include "animation/visual_basis.h"
#include "features/context.h"
#include "features/speech_normaliser.h"
#include "hmm/forward_filter.h"
#include "hmm/hmm_model.h"
#include "hmm/inversion.h"

namespace th::animation {

struct MouthModelOptions {
  int states = 4;    // N
  int mixtures = 2;  // M
  hmm::CovarianceType covariance = hmm::CovarianceType::kFull;
  int contextFrames = 3;  // tc: the frames of speech heard before each frame (and after, by default)
  // The frames heard after each frame; -1: tc, the paper's symmetric context. Fewer make a live model wait less
  // (0: for no frame after its own) and hear less of what follows.
  int futureContextFrames = -1;
  int visualComponents = 2;       // K
  bool standardiseVisual = true;  // scale each visual parameter to unit variance before PCA (BEAT2's mix of
                                  // degrees and coefficients); FAPs share one unit and keep their scales
  int maxIterations = 60;
  unsigned seed = 1;
  // The audio front end. false: c1..c11 as they are (the paper). true: c1..c11 less their running mean and the
  // level relative to its recent peak (features/speech_normaliser.h), for any voice, microphone and level.
  bool normaliseSpeech = false;
  features::SpeechNormalisationOptions normalisation{};
  // true: the visual block holds the K components and their deltas, and synthesis generates the smooth
  // trajectory that both make most likely (MLPG, mlpg.h) instead of frame-by-frame estimates.
  bool visualDeltas = false;
  // Global variance compensation (Toda & Tokuda 2007): every N-th training sequence is held out of a first
  // model, that model's estimates (MMSE) on them are compared with the truth, and the final model scales each
  // component by the ratio of the spreads, or less where the estimate correlates too weakly for the full ratio
  // to beat the mean (a factor of at most 2ρ · ratio; never below 1). 0, or fewer than N sequences: none.
  int varianceValidationEvery = 0;
  // Stage 2 (the paper's): with speech-only recordings given to trainMouthModel, the audio side (means and
  // covariances, π, A and weights kept) is re-estimated on them and the training speech together, this many
  // Baum-Welch iterations (hmm/audio_retraining.h), so that it covers more voices.
  int speechOnlyIterations = 5;
};

// The recipe of the shipped mouth models (`talkinghead train mouth`, from tracked talking video): 8 states x 2
// full-covariance Gaussians, ±2 frames of normalised speech, 4 components of the FAPs with their deltas (MLPG),
// global variance compensation measured on every fifth sequence.
MouthModelOptions videoMouthRecipe();

// The speech normalisation a model was trained with: its options and the training speech's mean c1..cN.
struct MouthSpeechNormalisation {
  features::SpeechNormalisationOptions options;
  Eigen::VectorXd priorMean;
};

struct MouthModel {
  hmm::HmmModel hmm;  // blocks "audio" (D·(tc + tf + 1), D = 11 MFCCs, or 12 with the level) and "visual" (K,
                      // or 2K with deltas)
  VisualBasis basis;
  int contextFrames = 3;        // tc: frames heard before each frame
  int futureContextFrames = 3;  // tf: frames heard after it (tc unless trained otherwise)
  int iterations = 0;           // Baum-Welch iterations used
  // From the jaw opening to MPEG-4 FAPs (fap_mapping.h); `train mouth --beat2` measures it on the reference face
  // and stores it with the model, so the model file alone turns audio into FAPs. Absent in sweep models.
  std::optional<MouthFapMap> fapMap;
  // Set for models whose visual parameters are FAPs (trained from tracked video): the FAP numbers of the
  // basis's rows, ascending; the basis reconstructs them in FAPU counts and no FAP map is needed.
  std::vector<int> visualFaps;
  std::optional<MouthSpeechNormalisation> normalisation;  // absent: raw c1..c11
  bool visualDeltas = false;
  // Per component: the factor that restores the truth's spread (global variance compensation); empty: none.
  Eigen::VectorXd varianceScale;

  int speechRowsPerFrame() const;  // D: 11, or 12 with the level
  int contextWidth() const { return contextFrames + futureContextFrames + 1; }
};

MouthModel trainMouthModel(const std::vector<MouthRecording>& parts, const MouthModelOptions& options,
                           const std::vector<SpeechFrames>& speechOnly = {});

// The ordinary HMM model file; its "training" object holds the visual basis (mean, scale, unmixing, mixing),
// tc and the FAP map if there is one, so the file alone turns audio into jaw and expression parameters (and
// FAPs). Errors name the file.
void saveMouthModel(const std::filesystem::path& path, const MouthModel& model, const MouthModelOptions& options);
MouthModel loadMouthModel(const std::filesystem::path& path);

enum class MouthMethod { kInversion, kMmse };

struct MouthSynthesisOptions {
  MouthMethod method = MouthMethod::kInversion;
  hmm::InversionStart start = hmm::InversionStart::kConditionalMean;
  int windowFrames = 0;  // 0: batch
  int maxIterations = 100;
  unsigned seed = 1;
  // For models with visual deltas: the MMSE estimate's Gaussians (means and posterior spread, per frame) turned
  // into a trajectory by MLPG; batch only (a window decodes frame by frame). false: the frames' own estimates.
  bool trajectory = true;
  bool varianceCompensation = true;  // apply the model's varianceScale, if it has one
};

// The model's audio frames (D x T, before context stacking): c1..c11, or normalised as the model was trained.
Eigen::MatrixXd mouthAudioFrames(const MouthModel& model, const SpeechFrames& speech);

// K x T visual components for T speech frames. `iterations`, if given, receives the inversion's EM count.
Eigen::MatrixXd synthesiseMouth(const MouthModel& model, const SpeechFrames& speech,
                                const MouthSynthesisOptions& options = {}, int* iterations = nullptr);

// synthesiseMouth with a window (windowFrames > 0) as a stream, for the live pipeline: speech frames in one at a
// time, visual components out in order, the same values as the batch call on the whole input. Frame t waits
// for frame t + tc (its context) and then for the rest of its inversion window. Ready frames are kept only
// until taken. Thread contract: one thread per instance; the model must outlive it.
class MouthSynthesiser {
 public:
  MouthSynthesiser(const MouthModel& model, const MouthSynthesisOptions& options);  // windowFrames >= 1
  MouthSynthesiser(const MouthSynthesiser&) = delete;
  MouthSynthesiser& operator=(const MouthSynthesiser&) = delete;

  // The next frame's level (dB re full scale) and c1..c11.
  void acceptFrame(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc);
  void finish();                           // the last tc frames, the last window
  bool next(Eigen::VectorXd& components);  // K values, if a frame is ready
  int lookaheadFrames() const;             // the most frames a frame waits past its own: tc + window - 1
  int lastIterations() const { return stream_.lastIterations(); }
  // P(state | audio up to the frame) under the model's audio marginal (its forward filter) for the frame the
  // last next() gave: for a display of the model's belief.
  const Eigen::VectorXd& posterior() const { return lastPosterior_; }
  int numStates() const;

 private:
  void invertFrame();  // the context-stacked frame in stacked_ into the inverter

  const MouthModel& model_;
  MouthSynthesisOptions options_;
  std::optional<features::OnlineSpeechNormaliser> normaliser_;
  Eigen::VectorXd normalised_;
  hmm::HmmInverter inverter_;
  hmm::StreamingInverter stream_;
  hmm::ForwardFilter filter_;               // over inverter_.audioModel()
  std::deque<Eigen::VectorXd> posteriors_;  // of frames stacked, not yet given by next()
  Eigen::VectorXd lastPosterior_;
  std::optional<features::ContextStacker> stacker_;
  Eigen::VectorXd stacked_;
  bool finished_ = false;
};

// The jaw opening (degrees, row 0 of the visual parameters) that K x T components reconstruct: BEAT2 models
// only (throws th::Error for a model whose visual parameters are FAPs).
Eigen::RowVectorXd jawOpeningOf(const MouthModel& model, const Eigen::MatrixXd& components);

// Whether the model turns audio into FAPs: it has a FAP map or its visual parameters are FAPs. Sweep models
// have neither.
bool drivesFaps(const MouthModel& model);
// The FAPs the model drives, ascending (FAP 3 first), and their values (FAPU counts, rows in that order) for
// K x T components. The jaw (FAP 3) is never below 0: the face's jaw does not close past rest.
std::vector<int> mouthFapNumbers(const MouthModel& model);
Eigen::MatrixXd mouthFapsOf(const MouthModel& model, const Eigen::MatrixXd& components);

}  // namespace th::animation
