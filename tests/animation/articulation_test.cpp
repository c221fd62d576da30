// The articulation: the network's class posteriors decoded into shown classes, and the lips closed on the
// frames shown as PP (raised on FF) by the face's opening gradient, the rest of the mouth left as it was.
#include "animation/articulation.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/error.h"
#include "face/visemes.h"

namespace th::animation {
namespace {

// The visual FAPs of the shipped mouth, with an opening gradient of the shape the face gives (the jaw opens the
// lips, the lip FAPs close them, the corners barely matter).
const std::vector<int> kFaps{3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60};

MouthNetwork modelWithGradient() {
  MouthNetwork model;
  model.visualFaps = kFaps;
  model.openingGradient.resize(static_cast<Eigen::Index>(kFaps.size()));
  model.openingGradient << 2.4e-4, -1.7e-4, -1.6e-4, 1e-6, 1e-6, -1e-4, -1e-4, -1e-4, -1e-4, -3e-6, -3e-6, -1.3e-4,
      -1.1e-4, 1e-6, 1e-6, -8e-5, -8e-5, -7e-5, -7e-5, -3e-6, -3e-6;
  // Runs of four frames, the classes following one another in turn.
  std::vector<int> labels;
  for (int repeat = 0; repeat < 20; ++repeat)
    for (int c = 0; c < face::kNumMouthClasses; ++c)
      for (int k = 0; k < 4; ++k) labels.push_back(c);
  model.sequence = classSequenceOf({labels});
  model.classPriors = Eigen::VectorXd::Constant(face::kNumMouthClasses, 1.0 / face::kNumMouthClasses);
  return model;
}

Eigen::Index rowOf(int fap) {
  return static_cast<Eigen::Index>(std::find(kFaps.begin(), kFaps.end(), fap) - kFaps.begin());
}

Eigen::MatrixXd openMouth(int frames) {
  Eigen::MatrixXd faps = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(kFaps.size()), frames);
  faps.row(rowOf(3)).setConstant(300.0);  // the jaw open
  faps.row(rowOf(6)).setConstant(-40.0);  // the corners in: a rounded mouth
  return faps;
}

TEST(Articulation, ClosesTheLipsOnPpByJawAndLips) {
  const MouthNetwork model = modelWithGradient();
  Eigen::MatrixXd faps = openMouth(3);
  const Eigen::MatrixXd before = faps;
  const double open = lipOpeningOf(model, kFaps, faps)[1];
  const std::vector<int> shown{face::kAa, face::kPp, face::kAa};
  articulateLips(model, shown, kFaps, faps, {.jawShare = 0.5});
  const Eigen::RowVectorXd opening = lipOpeningOf(model, kFaps, faps);
  EXPECT_GT(opening[0], 0.05);
  EXPECT_NEAR(opening[1], 0.0, 1e-9);  // the lips meet
  EXPECT_TRUE(faps.col(0).isApprox(before.col(0)));
  EXPECT_TRUE(faps.col(2).isApprox(before.col(2)));
  // Half by the jaw, which stays open past rest; the lower lip moves more than the upper.
  EXPECT_LT(faps(rowOf(3), 1), 300.0);
  EXPECT_GT(faps(rowOf(3), 1), 0.0);
  EXPECT_NEAR((300.0 - faps(rowOf(3), 1)) * 2.4e-4, 0.5 * open, 1e-9);
  EXPECT_GT(faps(rowOf(5), 1), faps(rowOf(4), 1));
  EXPECT_GT(faps(rowOf(4), 1), 0.0);
  EXPECT_EQ(faps(rowOf(6), 1), -40.0);  // the mouth's width is not touched
}

TEST(Articulation, ByDefaultTheLipsAloneCloseAndTheJawIsTheMouthModels) {
  const MouthNetwork model = modelWithGradient();
  Eigen::MatrixXd faps = openMouth(1);
  articulateLips(model, {face::kPp}, kFaps, faps, {});
  EXPECT_NEAR(lipOpeningOf(model, kFaps, faps)[0], 0.0, 1e-9);
  EXPECT_EQ(faps(rowOf(3), 0), 300.0);
}

TEST(Articulation, FfRaisesTheLowerLipOnly) {
  const MouthNetwork model = modelWithGradient();
  Eigen::MatrixXd faps = openMouth(1);
  const double open = lipOpeningOf(model, kFaps, faps)[0];
  articulateLips(model, {face::kFf}, kFaps, faps, {.ffShare = 0.7});
  EXPECT_NEAR(lipOpeningOf(model, kFaps, faps)[0], 0.3 * open, 1e-9);
  EXPECT_EQ(faps(rowOf(3), 0), 300.0);
  EXPECT_EQ(faps(rowOf(4), 0), 0.0);
  EXPECT_GT(faps(rowOf(5), 0), 0.0);
}

TEST(Articulation, AJawAtRestLeavesTheClosureToTheLipsAndClosedLipsAlone) {
  const MouthNetwork model = modelWithGradient();
  Eigen::MatrixXd faps = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(kFaps.size()), 2);
  faps(rowOf(4), 0) = -200.0;  // the upper lip raised, the jaw at rest
  faps(rowOf(5), 1) = 100.0;   // the lower lip pressed up: already closed
  const Eigen::MatrixXd before = faps;
  articulateLips(model, {face::kPp, face::kPp}, kFaps, faps, {});
  EXPECT_NEAR(lipOpeningOf(model, kFaps, faps)[0], 0.0, 1e-9);
  EXPECT_EQ(faps(rowOf(3), 0), 0.0);
  EXPECT_TRUE(faps.col(1).isApprox(before.col(1)));
}

TEST(Articulation, RoundsOhAndOuAndSpreadsEAndIhToTheirTypicalShape) {
  MouthNetwork model = modelWithGradient();
  Eigen::MatrixXd tracked = Eigen::MatrixXd::Random(static_cast<Eigen::Index>(kFaps.size()), 40) * 50.0;
  model.basis = VisualBasis::fit(tracked, {.components = 2, .standardise = false});
  const Eigen::VectorXd mean = model.basis.mean();
  model.classShapes = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(kFaps.size()), face::kNumMouthClasses);
  for (int fap : {6, 7, 53, 54}) {
    model.classShapes(rowOf(fap), face::kOu) = -30.0;  // rounded: the corners in
    model.classShapes(rowOf(fap), face::kE) = 20.0;    // spread: the corners out
    model.classShapes(rowOf(fap), face::kAa) = -40.0;  // not a rounded class: left alone
  }
  Eigen::MatrixXd faps = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(kFaps.size()), 4);
  for (int fap : {6, 7, 53, 54}) faps.row(rowOf(fap)) = mean[rowOf(fap)] * Eigen::RowVectorXd::Ones(4);
  faps(rowOf(6), 1) = mean[rowOf(6)] - 50.0;  // already more rounded than the class's shape
  const Eigen::MatrixXd before = faps;
  articulateLips(model, {face::kOu, face::kOu, face::kE, face::kAa}, kFaps, faps, {});
  EXPECT_NEAR(faps(rowOf(53), 0), mean[rowOf(53)] - 30.0, 1e-9);
  EXPECT_EQ(faps(rowOf(6), 1), mean[rowOf(6)] - 50.0);
  EXPECT_NEAR(faps(rowOf(7), 2), mean[rowOf(7)] + 20.0, 1e-9);
  EXPECT_TRUE(faps.col(3).isApprox(before.col(3)));
  EXPECT_EQ(faps(rowOf(3), 0), before(rowOf(3), 0));  // only the corners
}

TEST(Articulation, ThePhonesMouthMixesEachClasssShapeByItsProbability) {
  MouthNetwork model = modelWithGradient();
  Eigen::MatrixXd tracked = Eigen::MatrixXd::Random(static_cast<Eigen::Index>(kFaps.size()), 40) * 50.0;
  tracked.row(rowOf(3)).array() += 200.0;
  model.basis = VisualBasis::fit(tracked, {.components = 2, .standardise = false});
  const Eigen::VectorXd mean = model.basis.mean();
  model.classShapes = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(kFaps.size()), face::kNumMouthClasses);
  model.classShapes(rowOf(3), face::kAa) = 150.0;  // open vowels: the jaw down
  model.classShapes(rowOf(3), face::kPp) = -1e4;   // far past rest: clamped at 0
  model.classShapes(rowOf(6), face::kOu) = -30.0;
  Eigen::MatrixXd probabilities = Eigen::MatrixXd::Zero(face::kNumMouthClasses, 3);
  probabilities(face::kAa, 0) = 1.0;
  probabilities(face::kAa, 1) = 0.5, probabilities(face::kOu, 1) = 0.5;
  probabilities(face::kPp, 2) = 1.0;
  const Eigen::MatrixXd inversion = openMouth(4);  // one frame more than the probabilities: left as it is

  Eigen::MatrixXd faps = inversion;
  blendPhoneMouth(model, probabilities, kFaps, faps, {});  // share 0 by default: the mouth model's alone
  EXPECT_TRUE(faps.isApprox(inversion));

  faps = inversion;
  blendPhoneMouth(model, probabilities, kFaps, faps, {.phoneJawShare = 1.0, .phoneLipShare = 1.0});
  EXPECT_NEAR(faps(rowOf(3), 0), mean[rowOf(3)] + 150.0, 1e-9);
  EXPECT_NEAR(faps(rowOf(3), 1), mean[rowOf(3)] + 75.0, 1e-9);
  EXPECT_NEAR(faps(rowOf(6), 1), mean[rowOf(6)] - 15.0, 1e-9);
  EXPECT_EQ(faps(rowOf(3), 2), 0.0);
  EXPECT_TRUE(faps.col(3).isApprox(inversion.col(3)));

  faps = inversion;
  blendPhoneMouth(model, probabilities, kFaps, faps, {.phoneJawShare = 0.25});  // the jaw alone
  EXPECT_NEAR(faps(rowOf(3), 0), 0.75 * 300.0 + 0.25 * (mean[rowOf(3)] + 150.0), 1e-9);
  EXPECT_EQ(faps(rowOf(6), 1), inversion(rowOf(6), 1));

  // FAPs the model has no shape for stay; a model without shapes cannot make the mouth.
  Eigen::MatrixXd withOther = Eigen::MatrixXd::Constant(2, 3, 7.0);
  blendPhoneMouth(model, probabilities, {3, 19}, withOther, {.phoneJawShare = 1.0, .phoneLipShare = 1.0});
  EXPECT_EQ(withOther(1, 0), 7.0);
  model.classShapes.resize(0, 0);
  faps = inversion;
  EXPECT_THROW(blendPhoneMouth(model, probabilities, kFaps, faps, {.phoneJawShare = 0.5}), Error);
  EXPECT_THROW(ArticulationOptions{.phoneLipShare = -0.1}.check(), Error);
}

TEST(Articulation, NeedsTheOpeningGradientAndLipFaps) {
  MouthNetwork model = modelWithGradient();
  Eigen::MatrixXd jawOnly = Eigen::MatrixXd::Constant(1, 2, 100.0);
  EXPECT_THROW(articulateLips(model, {face::kPp, face::kPp}, {3}, jawOnly, {}), Error);
  model.openingGradient.resize(0);
  Eigen::MatrixXd faps = openMouth(1);
  EXPECT_THROW(articulateLips(model, {face::kPp}, kFaps, faps, {}), Error);
  EXPECT_THROW(ArticulationOptions{.evidenceScale = 0.0}.check(), Error);
  EXPECT_THROW(ArticulationOptions{.jawShare = 1.5}.check(), Error);
}

// Posteriors that favour one class per stretch of frames, with some doubt.
Eigen::MatrixXd posteriorsOf(const std::vector<int>& classes, double confidence) {
  Eigen::MatrixXd p = Eigen::MatrixXd::Constant(face::kNumMouthClasses, static_cast<Eigen::Index>(classes.size()),
                                                (1.0 - confidence) / (face::kNumMouthClasses - 1));
  for (std::size_t t = 0; t < classes.size(); ++t) p(classes[t], static_cast<Eigen::Index>(t)) = confidence;
  return p;
}

TEST(Articulation, VisemesFollowTheEvidenceAndHoldAtLeastTheMinimum) {
  const MouthNetwork model = modelWithGradient();
  std::vector<int> truth;
  for (int c : {face::kSilence, face::kPp, face::kAa, face::kOu, face::kSilence})
    for (int k = 0; k < 5; ++k) truth.push_back(c);
  const face::VisemeTrack track = networkVisemes(model, posteriorsOf(truth, 0.8), {});
  ASSERT_EQ(track.numFrames(), static_cast<int>(truth.size()));
  EXPECT_EQ(track.classes, truth);
  EXPECT_TRUE(track.posteriors.colwise().sum().isApprox(Eigen::RowVectorXd::Ones(track.numFrames()), 1e-9));
  // A one-frame blip is not shown for one frame: with a hold of 3 it is shown for 3 or not at all.
  std::vector<int> blip(12, face::kAa);
  blip[6] = face::kPp;
  const face::VisemeTrack held = networkVisemes(model, posteriorsOf(blip, 0.6), {.minHoldFrames = 3});
  for (const face::Run& run : face::runsOf(held.classes)) {
    if (run.first > 0 && run.first + run.length < 12) {
      EXPECT_GE(run.length, 3);
    }
  }
}

TEST(Articulation, TheStreamDecodesAsTheBatchWithALongLag) {
  const MouthNetwork model = modelWithGradient();
  std::vector<int> truth;
  for (int c : {face::kSilence, face::kPp, face::kE, face::kPp, face::kOh, face::kSilence})
    for (int k = 0; k < 4; ++k) truth.push_back(c);
  const Eigen::MatrixXd posteriors = posteriorsOf(truth, 0.5);
  const ArticulationOptions options;
  const face::VisemeTrack batch = networkVisemes(model, posteriors, options);
  const hmm::HmmModel classes = classHmm(model.sequence, options.minHoldFrames);
  VisemeStream stream(classes, options.minHoldFrames, 30);
  const Eigen::MatrixXd evidence =
      options.evidenceScale * (posteriors.array().log().colwise() - model.classPriors.array().log()).matrix();
  std::vector<int> streamed;
  VisemeFrame frame;
  for (Eigen::Index t = 0; t < evidence.cols(); ++t) {
    stream.acceptEvidence(evidence.col(t));
    while (stream.next(frame)) streamed.push_back(frame.mouthClass);
  }
  stream.finish();
  while (stream.next(frame)) streamed.push_back(frame.mouthClass);
  EXPECT_EQ(streamed, batch.classes);
}

}  // namespace
}  // namespace th::animation
