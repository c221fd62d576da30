#include "hmm_test_models.h"

#include <random>

namespace th::test {

hmm::HmmModel stickyModel1d(int numStates, double stay) {
  hmm::HmmModel model;
  model.initial = Eigen::VectorXd::Constant(numStates, 1.0 / numStates);
  model.transition = Eigen::MatrixXd::Constant(numStates, numStates, (1.0 - stay) / (numStates - 1));
  model.transition.diagonal().setConstant(stay);
  for (int j = 0; j < numStates; ++j) {
    model.states.emplace_back(
        Eigen::VectorXd::Ones(1),
        std::vector<hmm::Gaussian>{hmm::Gaussian(Eigen::VectorXd::Constant(1, 3.0 * j), Eigen::MatrixXd::Identity(1, 1),
                                                 hmm::CovarianceType::kFull)});
  }
  return model;
}

hmm::HmmModel randomModel(int numStates, int numMixtures, int dimension, hmm::CovarianceType type, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(0.1, 1.0);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  hmm::HmmModel model;
  model.initial = Eigen::VectorXd::NullaryExpr(numStates, [&] { return uniform(random); });
  model.initial /= model.initial.sum();
  model.transition = Eigen::MatrixXd::NullaryExpr(numStates, numStates, [&] { return uniform(random); });
  for (int i = 0; i < numStates; ++i) model.transition.row(i) /= model.transition.row(i).sum();
  for (int j = 0; j < numStates; ++j) {
    std::vector<hmm::Gaussian> components;
    Eigen::VectorXd weights = Eigen::VectorXd::NullaryExpr(numMixtures, [&] { return uniform(random); });
    weights /= weights.sum();
    for (int m = 0; m < numMixtures; ++m) {
      const Eigen::VectorXd mean = Eigen::VectorXd::NullaryExpr(dimension, [&] { return 3.0 * gaussian(random); });
      const Eigen::MatrixXd a =
          Eigen::MatrixXd::NullaryExpr(dimension, dimension, [&] { return 0.5 * gaussian(random); });
      const Eigen::MatrixXd covariance = a * a.transpose() + 0.3 * Eigen::MatrixXd::Identity(dimension, dimension);
      components.emplace_back(mean, covariance, type);
    }
    model.states.emplace_back(weights, std::move(components));
  }
  return model;
}

}  // namespace th::test
