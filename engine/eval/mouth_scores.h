// How well mouth curves follow a tracked speaker: the jaw, the lips' opening and the mouth's width, as
// correlation, spread and error, over clips of talking video (talking_corpus.h); and the baselines a model must
// beat: the level of the sound alone, the training mean, another clip's sound.
//
//   th::tracking::MouthShapes shapes(face);                        // the face model's lips, for FAP curves
//   th::tracking::MouthScores s = th::tracking::scoreMouth(estimates, fapNumbers, shapes, heldOutClips);
//   // s.jaw.rho, s.opening.spread, ...
//
// Spread is the estimate's standard deviation over the truth's (1: the truth's amplitude; an over-smoothed
// estimate falls below 1). The lips' opening and width of an estimate are measured on the face model deformed
// by its FAPs, with the same landmarks and formula as on the tracked video (track.h: mouthOpening, mouthWidth,
// shares of the eye corners' distance), so the two are in the same units.
// Thread contract: pure functions; a MouthShapes is immutable and may be shared.
#pragma once

#include <Eigen/Core>
#include <map>
#include <utility>
#include <vector>

#include "animation/mouth_data.h"
#include "eval/talking_corpus.h"
#include "face/face_model.h"
#include "tracking/face_fit.h"

namespace th::eval {

class MouthShapes {
 public:
  explicit MouthShapes(const face::FaceModel& face);
  // 2 x T: the inner-lip opening and the mouth width of the face with these FAPs (rows: fapNumbers).
  Eigen::MatrixXd of(const Eigen::MatrixXd& faps, const std::vector<int>& fapNumbers) const;

 private:
  tracking::FaceFitter fitter_;
};

// d(inner-lip opening) / d(FAP) for each of fapNumbers, by central differences of ±step FAP units around `at`
// (a typical open mouth: the opening is a smooth function of the FAPs there, rotation of the jaw included). The
// articulation's closures read it (animation/articulation.h).
Eigen::VectorXd openingGradient(const MouthShapes& shapes, const std::vector<int>& fapNumbers,
                                const Eigen::VectorXd& at, double step = 10.0);

struct CurveScore {
  double rho = 0.0;      // Pearson correlation
  double spread = 0.0;   // std(estimate) / std(truth)
  double epsilon = 0.0;  // the paper's ε: mean squared error / the truth's variance (the mean scores 1)
};

struct MouthScores {
  CurveScore jaw;            // FAP 3
  CurveScore opening;        // inner-lip opening
  CurveScore width;          // mouth width
  double fapsEpsilon = 0.0;  // ε and ρ averaged over the FAPs both hold (the paper's measures)
  double fapsRho = 0.0;
  int frames = 0;
};

// estimates[i]: FAP curves (rows: estimateFaps) for clips[i]; each cut to the shorter of the two.
MouthScores scoreMouth(const std::vector<Eigen::MatrixXd>& estimates, const std::vector<int>& estimateFaps,
                       const MouthShapes& shapes, const std::vector<const TalkingClip*>& clips,
                       const std::vector<int>& truthFaps);

CurveScore scoreCurve(const Eigen::RowVectorXd& estimate, const Eigen::RowVectorXd& truth);

// The energy-envelope baseline: every FAP a linear function (least squares) of the sound's level, relative to
// its recent peak (features/speech_normaliser.h), at frames t − tc .. t + tc. Fitted on training clips.
class LevelBaseline {
 public:
  LevelBaseline(const std::vector<const animation::MouthRecording*>& training, int contextFrames);
  Eigen::MatrixXd predict(const animation::SpeechFrames& speech) const;  // FAPs x T, the training rows

 private:
  Eigen::MatrixXd features(const animation::SpeechFrames& speech) const;
  int contextFrames_;
  Eigen::MatrixXd weights_;  // FAPs x (2 tc + 2): the context's levels and a constant
};

// Mean lip opening and width (MouthShapes' rows) per phone class, over clips with labels: what the truth and each
// estimate do at bilabials, open vowels, rounded and spread vowels.
class PhoneClassShapes {
 public:
  // classes: each frame's (labelClassesAt); shapes: 2 x T. Frames beyond the shorter are left out.
  void add(const std::vector<PhoneClass>& classes, const Eigen::MatrixXd& shapes);
  Eigen::Vector2d mean(PhoneClass phoneClass) const;  // NaN where the class has no frame
  int count(PhoneClass phoneClass) const;

 private:
  std::map<PhoneClass, std::pair<Eigen::Vector2d, int>> sums_;
};

}  // namespace th::eval
