#include "animation/mouth_model.h"

#include "core/error.h"
#include "hmm/training.h"

namespace th::animation {

MouthModel trainMouthModel(const std::vector<MouthRecording>& parts, const MouthModelOptions& options) {
  if (parts.empty()) throw Error("mouth model: no training data");
  Eigen::Index total = 0;
  for (const auto& part : parts) total += part.numFrames();
  Eigen::MatrixXd allVisual(parts.front().visual.rows(), total);
  Eigen::Index column = 0;
  for (const auto& part : parts) {
    allVisual.middleCols(column, part.numFrames()) = part.visual;
    column += part.numFrames();
  }
  MouthModel model;
  model.contextFrames = options.contextFrames;
  model.basis = VisualBasis::fit(allVisual, {.components = options.visualComponents});

  std::vector<Eigen::MatrixXd> sequences;
  for (const auto& part : parts) {
    const Eigen::MatrixXd audio = stackContext(part.mfcc, options.contextFrames);
    Eigen::MatrixXd joint(audio.rows() + options.visualComponents, part.numFrames());
    joint.topRows(audio.rows()) = audio;
    joint.bottomRows(options.visualComponents) = model.basis.transform(part.visual);
    sequences.push_back(std::move(joint));
  }
  hmm::TrainingOptions training;
  training.numStates = options.states;
  training.numMixtures = options.mixtures;
  training.covariance = options.covariance;
  training.maxIterations = options.maxIterations;
  training.seed = options.seed;
  hmm::TrainingResult result = hmm::trainHmm(sequences, training);
  model.hmm = std::move(result.model);
  model.iterations = static_cast<int>(result.history.size()) - 1;
  const int audioSize = static_cast<int>(sequences.front().rows()) - options.visualComponents;
  model.hmm.blocks = {{"audio", 0, audioSize}, {"visual", audioSize, options.visualComponents}};
  for (int k = 0; k < audioSize; ++k) {
    model.hmm.columnNames.push_back("ctx" + std::to_string(k / parts.front().mfcc.rows() - options.contextFrames) +
                                    "_mfcc" + std::to_string(k % parts.front().mfcc.rows() + 1));
  }
  for (int k = 0; k < options.visualComponents; ++k) model.hmm.columnNames.push_back("visual" + std::to_string(k + 1));
  model.hmm.check();
  return model;
}

Eigen::MatrixXd synthesiseMouth(const MouthModel& model, const Eigen::MatrixXd& mfcc,
                                const MouthSynthesisOptions& options, int* iterations) {
  const Eigen::MatrixXd audio = stackContext(mfcc, model.contextFrames);
  const hmm::HmmInverter inverter(model.hmm, {.maxIterations = options.maxIterations,
                                              .start = options.start,
                                              .seed = options.seed,
                                              .windowFrames = options.windowFrames});
  if (audio.rows() != inverter.audioDimension()) throw Error("mouth synthesis: the audio does not match the model");
  if (options.method == MouthMethod::kMmse) {
    if (iterations != nullptr) *iterations = 0;
    return inverter.mmse(audio);
  }
  hmm::InversionResult result = inverter.invert(audio);
  if (iterations != nullptr) *iterations = result.iterations;
  return result.visual;
}

}  // namespace th::animation
