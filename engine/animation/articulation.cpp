#include "animation/articulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "core/error.h"

namespace th::animation {
namespace {

constexpr int kJaw = 3;
// The inner and outer lips' vertical FAPs, each positive towards the other lip.
constexpr std::array<int, 6> kUpperLip{4, 8, 9, 51, 55, 56};
constexpr std::array<int, 6> kLowerLip{5, 10, 11, 52, 57, 58};
// The mouth's corners, inner and outer, each positive outwards.
constexpr std::array<int, 4> kCorners{6, 7, 53, 54};
bool shapesCorners(int mouthClass) {
  return mouthClass == face::kOh || mouthClass == face::kOu || mouthClass == face::kE || mouthClass == face::kIh;
}

// Each row of faps: its index in the model's visual FAPs, or -1.
std::vector<int> gradientRows(const MouthNetwork& model, const std::vector<int>& fapNumbers) {
  if (model.openingGradient.size() != static_cast<Eigen::Index>(model.visualFaps.size()))
    throw Error(
        "articulation: the mouth network has no opening gradient (train it with `talkinghead train "
        "articulation`)");
  std::vector<int> rows;
  for (const int fap : fapNumbers) {
    const auto found = std::find(model.visualFaps.begin(), model.visualFaps.end(), fap);
    rows.push_back(found == model.visualFaps.end() ? -1 : static_cast<int>(found - model.visualFaps.begin()));
  }
  return rows;
}

// A group of FAPs moved together by one unit each: their rows in faps, and the opening's change per unit.
struct LipGroup {
  std::vector<Eigen::Index> rows;
  double gradient = 0.0;
  bool closes() const { return !rows.empty() && gradient < 0.0; }
};

template <std::size_t N>
LipGroup groupOf(const MouthNetwork& model, const std::array<int, N>& faps, const std::vector<int>& fapNumbers,
                 const std::vector<int>& gradientRow) {
  LipGroup group;
  for (std::size_t i = 0; i < fapNumbers.size(); ++i)
    if (std::find(faps.begin(), faps.end(), fapNumbers[i]) != faps.end() && gradientRow[i] >= 0) {
      group.rows.push_back(static_cast<Eigen::Index>(i));
      group.gradient += model.openingGradient[gradientRow[i]];
    }
  return group;
}

void move(const LipGroup& group, double opening, Eigen::MatrixXd& faps, Eigen::Index frame) {
  const double step = -opening / group.gradient;  // the units that close `opening`
  for (const Eigen::Index row : group.rows) faps(row, frame) += step;
}

}  // namespace

void ArticulationOptions::check() const {
  if (!(evidenceScale > 0.0 && evidenceScale <= 1.0)) throw Error("articulation: the evidence scale must be in (0, 1]");
  if (minHoldFrames < 1 || minHoldFrames > 15) throw Error("articulation: the minimum hold must be 1..15 frames");
  for (const double share : {jawShare, lowerLipShare, ffShare, shapeShare, phoneJawShare, phoneLipShare})
    if (!(share >= 0.0 && share <= 1.0)) throw Error("articulation: shares must be in [0, 1]");
}

face::VisemeTrack networkVisemes(const MouthNetwork& model, const Eigen::MatrixXd& classes,
                                 const ArticulationOptions& options) {
  options.check();
  if (classes.rows() != face::kNumMouthClasses) throw Error("articulation: the class posteriors must have 17 rows");
  const Eigen::MatrixXd evidence =
      options.evidenceScale *
      (classes.array().max(1e-12).log().colwise() - model.classPriors.array().max(1e-12).log()).matrix();
  return decodeClassEvidence(classHmm(model.sequence, options.minHoldFrames), options.minHoldFrames, evidence);
}

void blendPhoneMouth(const MouthNetwork& model, const Eigen::MatrixXd& probabilities,
                     const std::vector<int>& fapNumbers, Eigen::MatrixXd& faps, const ArticulationOptions& options) {
  options.check();
  if (options.phoneJawShare == 0.0 && options.phoneLipShare == 0.0) return;
  if (probabilities.rows() != face::kNumMouthClasses)
    throw Error("articulation: the class probabilities must have 17 rows");
  if (model.classShapes.cols() != face::kNumMouthClasses ||
      model.classShapes.rows() != static_cast<Eigen::Index>(model.visualFaps.size()) ||
      model.basis.mean().size() != model.classShapes.rows())
    throw Error("articulation: the model has no class shapes to make the phones' mouth from");
  if (faps.rows() != static_cast<Eigen::Index>(fapNumbers.size()))
    throw Error("articulation: one row of FAPs per FAP number");
  const Eigen::Index frames = std::min(faps.cols(), probabilities.cols());
  const Eigen::MatrixXd shapes = (model.classShapes * probabilities.leftCols(frames)).colwise() + model.basis.mean();
  for (std::size_t i = 0; i < fapNumbers.size(); ++i) {
    const auto found = std::find(model.visualFaps.begin(), model.visualFaps.end(), fapNumbers[i]);
    if (found == model.visualFaps.end()) continue;
    const Eigen::Index row = static_cast<Eigen::Index>(i);
    const Eigen::Index shapeRow = found - model.visualFaps.begin();
    const double share = fapNumbers[i] == kJaw ? options.phoneJawShare : options.phoneLipShare;
    faps.row(row).head(frames) = (1.0 - share) * faps.row(row).head(frames) + share * shapes.row(shapeRow);
    if (fapNumbers[i] == kJaw) faps.row(row).head(frames) = faps.row(row).head(frames).cwiseMax(0.0);
  }
}

Eigen::RowVectorXd lipOpeningOf(const MouthNetwork& model, const std::vector<int>& fapNumbers,
                                const Eigen::MatrixXd& faps) {
  if (faps.rows() != static_cast<Eigen::Index>(fapNumbers.size()))
    throw Error("articulation: one row of FAPs per FAP number");
  const std::vector<int> rows = gradientRows(model, fapNumbers);
  Eigen::RowVectorXd opening = Eigen::RowVectorXd::Zero(faps.cols());
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i] >= 0) opening += model.openingGradient[rows[i]] * faps.row(static_cast<Eigen::Index>(i));
  return opening;
}

void articulateLips(const MouthNetwork& model, const std::vector<int>& shown, const std::vector<int>& fapNumbers,
                    Eigen::MatrixXd& faps, const ArticulationOptions& options) {
  options.check();
  const Eigen::RowVectorXd opening = lipOpeningOf(model, fapNumbers, faps);
  const std::vector<int> rows = gradientRows(model, fapNumbers);
  const LipGroup upper = groupOf(model, kUpperLip, fapNumbers, rows);
  const LipGroup lower = groupOf(model, kLowerLip, fapNumbers, rows);
  Eigen::Index jawRow = -1;
  double jawGradient = 0.0;
  for (std::size_t i = 0; i < fapNumbers.size(); ++i)
    if (fapNumbers[i] == kJaw && rows[i] >= 0) {
      jawRow = static_cast<Eigen::Index>(i);
      jawGradient = model.openingGradient[rows[i]];
    }
  if (!upper.closes() && !lower.closes())
    throw Error("articulation: the FAPs have no lip FAP that closes the mouth (4, 5, 8-11, 51, 52, 55-58)");

  // The corners' rows in faps and in the model's shapes.
  std::vector<std::pair<Eigen::Index, int>> corners;
  if (model.classShapes.cols() == face::kNumMouthClasses)
    for (std::size_t i = 0; i < fapNumbers.size(); ++i)
      if (std::find(kCorners.begin(), kCorners.end(), fapNumbers[i]) != kCorners.end() && rows[i] >= 0)
        corners.emplace_back(static_cast<Eigen::Index>(i), rows[i]);
  const Eigen::VectorXd mean = model.basis.mean();

  const Eigen::Index frames = std::min<Eigen::Index>(faps.cols(), static_cast<Eigen::Index>(shown.size()));
  for (Eigen::Index t = 0; t < frames; ++t) {
    const int mouthClass = shown[static_cast<std::size_t>(t)];
    if (shapesCorners(mouthClass))
      for (const auto& [row, shapeRow] : corners) {
        const double offset = model.classShapes(shapeRow, mouthClass);
        const double target = mean[shapeRow] + offset;
        const double bounded = offset < 0.0 ? std::min(faps(row, t), target) : std::max(faps(row, t), target);
        faps(row, t) += options.shapeShare * (bounded - faps(row, t));
      }
    double gap = opening[t];
    if (gap <= 0.0) continue;
    if (mouthClass == face::kPp) {
      // The jaw's part, never past rest (FAP 3 ≥ 0).
      if (jawRow >= 0 && jawGradient > 0.0) {
        const double lowered = std::min(options.jawShare * gap / jawGradient, std::max(faps(jawRow, t), 0.0));
        faps(jawRow, t) -= lowered;
        gap -= lowered * jawGradient;
      }
      const double lowerShare = !upper.closes() ? 1.0 : !lower.closes() ? 0.0 : options.lowerLipShare;
      if (lowerShare > 0.0) move(lower, lowerShare * gap, faps, t);
      if (lowerShare < 1.0) move(upper, (1.0 - lowerShare) * gap, faps, t);
    } else if (mouthClass == face::kFf && lower.closes()) {
      move(lower, options.ffShare * gap, faps, t);
    }
  }
}

}  // namespace th::animation
