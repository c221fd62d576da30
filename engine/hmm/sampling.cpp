#include "hmm/sampling.h"

#include <Eigen/Cholesky>

namespace th::hmm {
namespace {

int draw(const Eigen::VectorXd& probabilities, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double u = uniform(random) * probabilities.sum();
  for (Eigen::Index i = 0; i < probabilities.size(); ++i) {
    u -= probabilities[i];
    if (u < 0.0) return static_cast<int>(i);
  }
  Eigen::Index last = probabilities.size() - 1;
  while (last > 0 && probabilities[last] <= 0.0) --last;
  return static_cast<int>(last);
}

}  // namespace

Sample sampleHmm(const HmmModel& model, int numFrames, std::mt19937& random) {
  model.check();
  Sample sample;
  sample.frames.resize(model.dimension(), numFrames);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  // Cholesky factors once per component.
  std::vector<std::vector<Eigen::MatrixXd>> factors(static_cast<size_t>(model.numStates()));
  for (int j = 0; j < model.numStates(); ++j) {
    for (const auto& component : model.states[static_cast<size_t>(j)].components()) {
      factors[static_cast<size_t>(j)].push_back(Eigen::LLT<Eigen::MatrixXd>(component.covariance()).matrixL());
    }
  }
  int state = draw(model.initial, random);
  Eigen::VectorXd noise(model.dimension());
  for (int t = 0; t < numFrames; ++t) {
    if (t > 0) state = draw(model.transition.row(state).transpose(), random);
    const GaussianMixture& mixture = model.states[static_cast<size_t>(state)];
    const int m = draw(mixture.weights(), random);
    for (Eigen::Index k = 0; k < noise.size(); ++k) noise[k] = gaussian(random);
    sample.frames.col(t) = mixture.components()[static_cast<size_t>(m)].mean() +
                           factors[static_cast<size_t>(state)][static_cast<size_t>(m)] * noise;
    sample.states.push_back(state);
    sample.components.push_back(m);
  }
  return sample;
}

}  // namespace th::hmm
