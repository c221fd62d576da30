#include "eval/mouth_scores.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "eval/mouth_evaluation.h"
#include "features/speech_normaliser.h"
#include "tracking/track.h"

namespace th::eval {

MouthShapes::MouthShapes(const face::FaceModel& face) : fitter_(face) {}

Eigen::MatrixXd MouthShapes::of(const Eigen::MatrixXd& faps, const std::vector<int>& fapNumbers) const {
  if (faps.rows() != static_cast<Eigen::Index>(fapNumbers.size())) throw Error("mouth shapes: one row per FAP number");
  Eigen::MatrixXd shapes(2, faps.cols());
  tracking::FaceFit fit;  // the head at rest, unscaled: the ratios below do not depend on the scale
  for (Eigen::Index t = 0; t < faps.cols(); ++t) {
    fit.faps.fill(0.0);
    for (std::size_t k = 0; k < fapNumbers.size(); ++k)
      fit.faps[static_cast<std::size_t>(fapNumbers[k])] = faps(static_cast<Eigen::Index>(k), t);
    const tracking::Landmarks points = fitter_.project(fit);
    shapes(0, t) = tracking::mouthOpening(points);
    shapes(1, t) = tracking::mouthWidth(points);
  }
  return shapes;
}

Eigen::VectorXd openingGradient(const MouthShapes& shapes, const std::vector<int>& fapNumbers,
                                const Eigen::VectorXd& at, double step) {
  if (at.size() != static_cast<Eigen::Index>(fapNumbers.size()) || !(step > 0.0))
    throw Error("opening gradient: one value per FAP number and a positive step");
  const auto k = static_cast<Eigen::Index>(fapNumbers.size());
  Eigen::MatrixXd probes = at.replicate(1, 2 * k);
  for (Eigen::Index i = 0; i < k; ++i) {
    probes(i, 2 * i) += step;
    probes(i, 2 * i + 1) -= step;
  }
  const Eigen::MatrixXd opened = shapes.of(probes, fapNumbers);
  Eigen::VectorXd gradient(k);
  for (Eigen::Index i = 0; i < k; ++i) gradient[i] = (opened(0, 2 * i) - opened(0, 2 * i + 1)) / (2.0 * step);
  return gradient;
}

CurveScore scoreCurve(const Eigen::RowVectorXd& estimate, const Eigen::RowVectorXd& truth) {
  const Eigen::RowVectorXd e = estimate.array() - estimate.mean();
  const Eigen::RowVectorXd t = truth.array() - truth.mean();
  CurveScore score;
  const double truthNorm = t.squaredNorm();
  score.rho = e.squaredNorm() > 0.0 && truthNorm > 0.0 ? e.dot(t) / std::sqrt(e.squaredNorm() * truthNorm) : 0.0;
  score.spread = truthNorm > 0.0 ? std::sqrt(e.squaredNorm() / truthNorm) : 0.0;
  score.epsilon = truthNorm > 0.0 ? (estimate - truth).squaredNorm() / truthNorm : 0.0;
  return score;
}

MouthScores scoreMouth(const std::vector<Eigen::MatrixXd>& estimates, const std::vector<int>& estimateFaps,
                       const MouthShapes& shapes, const std::vector<const TalkingClip*>& clips,
                       const std::vector<int>& truthFaps) {
  if (estimates.size() != clips.size()) throw Error("mouth scores: one estimate per clip");
  Eigen::Index jawRow = -1;
  const std::vector<std::pair<Eigen::Index, Eigen::Index>> rows = commonFapRows(estimateFaps, truthFaps, jawRow);
  if (jawRow < 0) throw Error("mouth scores: the estimate and the truth need the jaw (FAP 3)");
  Eigen::Index frames = 0;
  for (std::size_t i = 0; i < clips.size(); ++i)
    frames += std::min(estimates[i].cols(), clips[i]->clip.recording.visual.cols());
  const auto n = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd estimate(n, frames), truth(n, frames), estimateShape(2, frames), truthShape(2, frames);
  Eigen::Index column = 0;
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const Eigen::Index count = std::min(estimates[i].cols(), clips[i]->clip.recording.visual.cols());
    for (Eigen::Index r = 0; r < n; ++r) {
      estimate.row(r).segment(column, count) = estimates[i].row(rows[static_cast<std::size_t>(r)].first).head(count);
      truth.row(r).segment(column, count) =
          clips[i]->clip.recording.visual.row(rows[static_cast<std::size_t>(r)].second).head(count);
    }
    estimateShape.middleCols(column, count) = shapes.of(estimates[i].leftCols(count), estimateFaps);
    truthShape.middleCols(column, count) = clips[i]->clip.lipShape.leftCols(count);
    column += count;
  }
  MouthScores scores;
  scores.frames = static_cast<int>(frames);
  scores.jaw = scoreCurve(estimate.row(jawRow), truth.row(jawRow));
  scores.opening = scoreCurve(estimateShape.row(0), truthShape.row(0));
  scores.width = scoreCurve(estimateShape.row(1), truthShape.row(1));
  scores.fapsEpsilon = averageMse(estimate, truth);
  scores.fapsRho = averageCorrelation(estimate, truth);
  return scores;
}

LevelBaseline::LevelBaseline(const std::vector<const animation::MouthRecording*>& training, int contextFrames)
    : contextFrames_(contextFrames) {
  if (training.empty()) throw Error("level baseline: no training clips");
  Eigen::Index frames = 0;
  for (const auto* recording : training) frames += recording->numFrames();
  const Eigen::Index width = 2 * contextFrames + 2;
  Eigen::MatrixXd x(width, frames), y(training.front()->visual.rows(), frames);
  Eigen::Index column = 0;
  for (const auto* recording : training) {
    x.middleCols(column, recording->numFrames()) = features(recording->speech);
    y.middleCols(column, recording->numFrames()) = recording->visual;
    column += recording->numFrames();
  }
  // Least squares, with a whisper of ridge so that a constant level cannot make the system singular.
  const Eigen::MatrixXd gram =
      x * x.transpose() + 1e-6 * static_cast<double>(frames) * Eigen::MatrixXd::Identity(width, width);
  weights_ = gram.llt().solve(x * y.transpose()).transpose();
}

Eigen::MatrixXd LevelBaseline::features(const animation::SpeechFrames& speech) const {
  const Eigen::MatrixXd normalised = features::normaliseSpeech(
      {}, animation::kMouthFramesPerSecond, Eigen::VectorXd::Zero(speech.mfcc.rows()), speech.levelDb, speech.mfcc);
  const Eigen::RowVectorXd level = normalised.bottomRows(1);
  const Eigen::Index frames = level.size();
  Eigen::MatrixXd x(2 * contextFrames_ + 2, frames);
  for (Eigen::Index t = 0; t < frames; ++t) {
    for (int offset = -contextFrames_; offset <= contextFrames_; ++offset)
      x(offset + contextFrames_, t) = level[std::clamp<Eigen::Index>(t + offset, 0, frames - 1)];
    x(2 * contextFrames_ + 1, t) = 1.0;
  }
  return x;
}

Eigen::MatrixXd LevelBaseline::predict(const animation::SpeechFrames& speech) const {
  return weights_ * features(speech);
}

void PhoneClassShapes::add(const std::vector<PhoneClass>& classes, const Eigen::MatrixXd& shapes) {
  const Eigen::Index frames = std::min<Eigen::Index>(shapes.cols(), static_cast<Eigen::Index>(classes.size()));
  for (Eigen::Index t = 0; t < frames; ++t) {
    auto& [sum, count] = sums_[classes[static_cast<std::size_t>(t)]];
    if (count == 0) sum.setZero();
    sum += shapes.col(t);
    ++count;
  }
}

Eigen::Vector2d PhoneClassShapes::mean(PhoneClass phoneClass) const {
  const auto it = sums_.find(phoneClass);
  return it == sums_.end() || it->second.second == 0 ? Eigen::Vector2d::Constant(std::nan(""))
                                                     : Eigen::Vector2d(it->second.first / it->second.second);
}

int PhoneClassShapes::count(PhoneClass phoneClass) const {
  const auto it = sums_.find(phoneClass);
  return it == sums_.end() ? 0 : it->second.second;
}

}  // namespace th::eval
