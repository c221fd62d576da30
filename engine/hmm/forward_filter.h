// The forward filter of an HMM: P(state at t | observations up to t), one frame at a time, for a display of a
// model's belief as speech comes in (decoders decide later, after their lag; this does not wait).
//
//   th::hmm::ForwardFilter filter(model);
//   filter.accept(model.emissionLogLikelihoods(frame).col(0));
//   const Eigen::VectorXd& p = filter.posterior();          // N values, sum 1
//
// Thread contract: one thread; the model must outlive it.
#pragma once

#include <Eigen/Core>

#include "hmm/hmm_model.h"

namespace th::hmm {

class ForwardFilter {
 public:
  explicit ForwardFilter(const HmmModel& model)
      : model_(model), posterior_(Eigen::VectorXd::Constant(model.numStates(), 1.0 / model.numStates())) {}

  void accept(const Eigen::Ref<const Eigen::VectorXd>& logEmission) {
    // Scaled by the largest log-likelihood, so that exp() stays in range; the scale cancels in the normalisation.
    const Eigen::VectorXd b = (logEmission.array() - logEmission.maxCoeff()).exp().matrix();
    Eigen::VectorXd next = started_ ? Eigen::VectorXd(model_.transition.transpose() * posterior_) : model_.initial;
    next = next.cwiseProduct(b);
    const double total = next.sum();
    if (total > 0.0) posterior_ = next / total;  // else (every state impossible): the last belief stays
    started_ = true;
  }
  const Eigen::VectorXd& posterior() const { return posterior_; }

 private:
  const HmmModel& model_;
  Eigen::VectorXd posterior_;
  bool started_ = false;
};

}  // namespace th::hmm
