#include "nn/training.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>

#include "core/error.h"

namespace th::nn {

void TrainingOptions::check() const {
  if (epochs < 1) throw Error("network training: epochs " + std::to_string(epochs) + " (at least 1)");
  if (batchFrames < 1) throw Error("network training: batch of " + std::to_string(batchFrames) + " frames");
  if (!(learningRate > 0.0) || !(finalLearningRate >= 0.0) || finalLearningRate > learningRate)
    throw Error("network training: learning rates must satisfy 0 <= final <= start, start > 0");
  if (!(weightDecay >= 0.0)) throw Error("network training: weight decay must be >= 0");
  if (!(dropout >= 0.0 && dropout < 1.0)) throw Error("network training: dropout must be in [0, 1)");
  if (!(inputNoise >= 0.0)) throw Error("network training: input noise must be >= 0");
}

void checkHeads(const Network& network, const std::vector<Head>& heads, const Frames& frames) {
  if (heads.empty()) throw Error("network training: no heads");
  std::vector<int> owner(static_cast<std::size_t>(network.outputs()), -1);
  for (std::size_t h = 0; h < heads.size(); ++h) {
    const Head& head = heads[h];
    if (head.size < 1 || head.firstOutput < 0 || head.firstOutput + head.size > network.outputs())
      throw Error("network training: head \"" + head.name + "\" lies outside the network's " +
                  std::to_string(network.outputs()) + " outputs");
    if (head.kind == HeadKind::kSoftmax && head.size < 2)
      throw Error("network training: softmax head \"" + head.name + "\" needs at least 2 outputs");
    for (int o = head.firstOutput; o < head.firstOutput + head.size; ++o) {
      if (owner[static_cast<std::size_t>(o)] >= 0)
        throw Error("network training: heads \"" +
                    heads[static_cast<std::size_t>(owner[static_cast<std::size_t>(o)])].name + "\" and \"" + head.name +
                    "\" overlap");
      owner[static_cast<std::size_t>(o)] = static_cast<int>(h);
    }
  }
  if (frames.inputs.rows() != network.inputs() || frames.targets.rows() != network.outputs() ||
      frames.mask.rows() != static_cast<Eigen::Index>(heads.size()) || frames.targets.cols() != frames.size() ||
      frames.mask.cols() != frames.size())
    throw Error("network training: frames of " + std::to_string(frames.inputs.rows()) + " inputs, " +
                std::to_string(frames.targets.rows()) + " targets and " + std::to_string(frames.mask.rows()) +
                " mask rows for a network of " + std::to_string(network.inputs()) + " inputs, " +
                std::to_string(network.outputs()) + " outputs and " + std::to_string(heads.size()) + " heads");
  if (!frames.inputs.allFinite() || !frames.targets.allFinite() || !frames.mask.allFinite())
    throw Error("network training: the frames hold a value that is not finite");
}

namespace {

// Per head: the loss summed over the batch's frames (weighted by mask and head weight), and the gradient of
// that sum with respect to the outputs written into `gradient` (outputs x B).
double headLosses(const std::vector<Head>& heads, const Eigen::MatrixXf& outputs,
                  const Eigen::Ref<const Eigen::MatrixXf>& targets, const Eigen::Ref<const Eigen::MatrixXf>& mask,
                  Eigen::MatrixXf* gradient) {
  double total = 0.0;
  if (gradient != nullptr) gradient->setZero(outputs.rows(), outputs.cols());
  for (std::size_t h = 0; h < heads.size(); ++h) {
    const Head& head = heads[h];
    const auto z = outputs.middleRows(head.firstOutput, head.size);
    const auto y = targets.middleRows(head.firstOutput, head.size);
    for (Eigen::Index t = 0; t < outputs.cols(); ++t) {
      const float m = mask(static_cast<Eigen::Index>(h), t) * static_cast<float>(head.weight);
      if (m == 0.0f) continue;
      switch (head.kind) {
        case HeadKind::kSoftmax: {
          const float top = z.col(t).maxCoeff();
          const Eigen::ArrayXf e = (z.col(t).array() - top).exp();
          const float sum = e.sum();
          const float logSum = std::log(sum) + top;
          total += m * (y.col(t).sum() * logSum - y.col(t).dot(z.col(t)));
          if (gradient != nullptr)
            gradient->col(t).segment(head.firstOutput, head.size) = m * (e.matrix() / sum * y.col(t).sum() - y.col(t));
          break;
        }
        case HeadKind::kRegression: {
          const Eigen::VectorXf error = z.col(t) - y.col(t);
          total += 0.5 * m * error.squaredNorm();
          if (gradient != nullptr) gradient->col(t).segment(head.firstOutput, head.size) = m * error;
          break;
        }
        case HeadKind::kSigmoid: {
          for (Eigen::Index k = 0; k < head.size; ++k) {
            const float logit = z(k, t), target = y(k, t);
            // log(1 + e^x) computed without overflow.
            const float softplus = std::max(logit, 0.0f) + std::log1p(std::exp(-std::abs(logit)));
            total += m * (softplus - target * logit);
            if (gradient != nullptr)
              (*gradient)(head.firstOutput + k, t) = m * (1.0f / (1.0f + std::exp(-logit)) - target);
          }
          break;
        }
      }
    }
  }
  return total;
}

struct AdamState {
  std::vector<Eigen::MatrixXf> weightMoment1, weightMoment2;
  std::vector<Eigen::VectorXf> biasMoment1, biasMoment2;
  explicit AdamState(const Network& network) {
    for (const DenseLayer& layer : network.layers()) {
      weightMoment1.push_back(Eigen::MatrixXf::Zero(layer.weights.rows(), layer.weights.cols()));
      weightMoment2.push_back(Eigen::MatrixXf::Zero(layer.weights.rows(), layer.weights.cols()));
      biasMoment1.push_back(Eigen::VectorXf::Zero(layer.bias.size()));
      biasMoment2.push_back(Eigen::VectorXf::Zero(layer.bias.size()));
    }
  }
};

// One batch forward and back: every layer's activation kept (after ReLU and dropout), then the gradients of
// the batch's summed loss with respect to every weight and bias. Buffers are kept from batch to batch.
class Backpropagation {
 public:
  explicit Backpropagation(const Network& network)
      : activations_(network.layers().size() + 1), dropMasks_(network.layers().size()) {
    for (const DenseLayer& layer : network.layers()) gradients_.push_back({layer.weights, layer.bias});
  }

  // Returns the batch's summed loss; gradients() then holds its gradients. dropout 0: none.
  double run(const Network& network, const std::vector<Head>& heads, const Eigen::Ref<const Eigen::MatrixXf>& inputs,
             const Eigen::Ref<const Eigen::MatrixXf>& targets, const Eigen::Ref<const Eigen::MatrixXf>& mask,
             double dropout, double inputNoise, std::mt19937& random) {
    const std::size_t layers = network.layers().size();
    const Eigen::Index n = inputs.cols();
    activations_[0] = network.inputScale().asDiagonal() * (inputs.colwise() - network.inputMean());
    if (inputNoise > 0.0) {
      std::normal_distribution<float> noise(0.0f, static_cast<float>(inputNoise));
      for (Eigen::Index i = 0; i < activations_[0].size(); ++i) activations_[0].data()[i] += noise(random);
    }
    const auto keepScale = static_cast<float>(1.0 / (1.0 - dropout));
    std::bernoulli_distribution keep(1.0 - dropout);
    for (std::size_t l = 0; l < layers; ++l) {
      const DenseLayer& layer = network.layers()[l];
      activations_[l + 1].noalias() = layer.weights * activations_[l];
      activations_[l + 1].colwise() += layer.bias;
      if (l + 1 < layers) {
        activations_[l + 1] = activations_[l + 1].cwiseMax(0.0f);
        if (dropout > 0.0) {
          dropMasks_[l].resize(activations_[l + 1].rows(), n);
          for (Eigen::Index i = 0; i < dropMasks_[l].size(); ++i)
            dropMasks_[l].data()[i] = keep(random) ? keepScale : 0.0f;
          activations_[l + 1].array() *= dropMasks_[l].array();
        }
      }
    }
    const double loss = headLosses(heads, activations_[layers], targets, mask, &gradient_);
    for (std::size_t l = layers; l-- > 0;) {
      gradients_[l].weights.noalias() = gradient_ * activations_[l].transpose();
      gradients_[l].bias = gradient_.rowwise().sum();
      if (l == 0) break;
      below_.noalias() = network.layers()[l].weights.transpose() * gradient_;
      // Through the ReLU and the dropout of the layer below: its activation is positive exactly where neither
      // cut the unit, and a kept unit was scaled by keepScale.
      below_.array() *= (activations_[l].array() > 0.0f).cast<float>();
      if (dropout > 0.0) below_ *= keepScale;
      gradient_.swap(below_);
    }
    return loss;
  }

  const std::vector<DenseLayer>& gradients() const { return gradients_; }

 private:
  std::vector<Eigen::MatrixXf> activations_, dropMasks_;
  Eigen::MatrixXf gradient_, below_;
  std::vector<DenseLayer> gradients_;
};

}  // namespace

double evaluateLoss(const Network& network, const std::vector<Head>& heads, const Frames& frames) {
  checkHeads(network, heads, frames);
  if (frames.size() == 0) return 0.0;
  double total = 0.0;
  constexpr Eigen::Index kChunk = 4096;
  for (Eigen::Index begin = 0; begin < frames.size(); begin += kChunk) {
    const Eigen::Index n = std::min(kChunk, frames.size() - begin);
    const Eigen::MatrixXf outputs = network.forward(frames.inputs.middleCols(begin, n));
    total += headLosses(heads, outputs, frames.targets.middleCols(begin, n), frames.mask.middleCols(begin, n), nullptr);
  }
  return total / static_cast<double>(frames.size());
}

std::vector<DenseLayer> lossGradients(const Network& network, const std::vector<Head>& heads, const Frames& frames) {
  checkHeads(network, heads, frames);
  if (frames.size() == 0) throw Error("network training: no frames");
  Backpropagation pass(network);
  std::mt19937 unused(1);
  pass.run(network, heads, frames.inputs, frames.targets, frames.mask, 0.0, 0.0, unused);
  std::vector<DenseLayer> gradients = pass.gradients();
  for (DenseLayer& g : gradients) {
    g.weights /= static_cast<float>(frames.size());
    g.bias /= static_cast<float>(frames.size());
  }
  return gradients;
}

namespace {

// One AdamW step on a batch of n frames' summed gradients (the step-th of totalSteps), with the learning rate on a
// cosine from its start to its final value over all steps.
void adamWStep(Network& network, const std::vector<DenseLayer>& gradients, AdamState& adam, long step, long totalSteps,
               Eigen::Index n, const TrainingOptions& options) {
  constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEpsilon = 1e-8;
  const double done = static_cast<double>(step - 1) / static_cast<double>(std::max(totalSteps - 1, 1L));
  const double rate = options.finalLearningRate + 0.5 * (options.learningRate - options.finalLearningRate) *
                                                      (1.0 + std::cos(3.14159265358979323846 * done));
  const double correction1 = 1.0 - std::pow(kBeta1, static_cast<double>(step));
  const double correction2 = 1.0 - std::pow(kBeta2, static_cast<double>(step));
  const auto stepSize = static_cast<float>(rate * std::sqrt(correction2) / correction1);
  const auto decay = static_cast<float>(1.0 - rate * options.weightDecay);
  const auto perFrame = 1.0f / static_cast<float>(n);
  for (std::size_t l = 0; l < network.layers().size(); ++l) {
    DenseLayer& layer = network.mutableLayers()[l];
    const DenseLayer& g = gradients[l];
    Eigen::MatrixXf& m1 = adam.weightMoment1[l];
    Eigen::MatrixXf& m2 = adam.weightMoment2[l];
    m1 = kBeta1 * m1 + ((1.0 - kBeta1) * perFrame) * g.weights;
    m2 = kBeta2 * m2 + ((1.0 - kBeta2) * perFrame * perFrame) * g.weights.cwiseAbs2();
    layer.weights *= decay;
    layer.weights.array() -= stepSize * m1.array() / (m2.array().sqrt() + static_cast<float>(kEpsilon));
    Eigen::VectorXf& b1 = adam.biasMoment1[l];
    Eigen::VectorXf& b2 = adam.biasMoment2[l];
    b1 = kBeta1 * b1 + ((1.0 - kBeta1) * perFrame) * g.bias;
    b2 = kBeta2 * b2 + ((1.0 - kBeta2) * perFrame * perFrame) * g.bias.cwiseAbs2();
    layer.bias.array() -= stepSize * b1.array() / (b2.array().sqrt() + static_cast<float>(kEpsilon));
  }
}

}  // namespace

TrainingReport train(Network& network, const std::vector<Head>& heads, const Frames& training, const Frames* validation,
                     const TrainingOptions& options, const std::function<void(int, int)>& progress) {
  options.check();
  checkHeads(network, heads, training);
  if (validation != nullptr) checkHeads(network, heads, *validation);
  if (training.size() == 0) throw Error("network training: no frames");

  std::mt19937 random(options.seed);
  std::vector<Eigen::Index> order(static_cast<std::size_t>(training.size()));
  std::iota(order.begin(), order.end(), 0);
  AdamState adam(network);
  Backpropagation pass(network);
  long step = 0;
  const Eigen::Index batchSize = std::min<Eigen::Index>(options.batchFrames, training.size());
  const auto batchesPerEpoch = static_cast<long>((training.size() + batchSize - 1) / batchSize);
  const long totalSteps = batchesPerEpoch * options.epochs;
  Eigen::MatrixXf inputs(network.inputs(), batchSize), targets(network.outputs(), batchSize),
      mask(static_cast<Eigen::Index>(heads.size()), batchSize);

  TrainingReport report;
  Network best = network;
  double bestLoss = std::numeric_limits<double>::infinity();
  for (int epoch = 0; epoch < options.epochs; ++epoch) {
    std::shuffle(order.begin(), order.end(), random);
    double epochLoss = 0.0;
    for (Eigen::Index begin = 0; begin < training.size(); begin += batchSize) {
      const Eigen::Index n = std::min(batchSize, training.size() - begin);
      for (Eigen::Index j = 0; j < n; ++j) {
        const Eigen::Index source = order[static_cast<std::size_t>(begin + j)];
        inputs.col(j) = training.inputs.col(source);
        targets.col(j) = training.targets.col(source);
        mask.col(j) = training.mask.col(source);
      }
      epochLoss += pass.run(network, heads, inputs.leftCols(n), targets.leftCols(n), mask.leftCols(n), options.dropout,
                            options.inputNoise, random);

      adamWStep(network, pass.gradients(), adam, ++step, totalSteps, n, options);
    }
    report.trainingLoss.push_back(epochLoss / static_cast<double>(training.size()));
    if (!std::isfinite(report.trainingLoss.back()))
      throw Error("network training: the loss is not finite at epoch " + std::to_string(epoch + 1) +
                  " (learning rate too high?)");
    if (validation != nullptr && validation->size() > 0) {
      report.validationLoss.push_back(evaluateLoss(network, heads, *validation));
      if (report.validationLoss.back() < bestLoss) {
        bestLoss = report.validationLoss.back();
        best = network;
        report.bestEpoch = epoch;
      }
    } else {
      report.bestEpoch = epoch;
    }
    if (progress) progress(epoch + 1, options.epochs);
  }
  if (validation != nullptr && validation->size() > 0) network = std::move(best);
  return report;
}

void applyHeads(const std::vector<Head>& heads, Eigen::Ref<Eigen::MatrixXf> outputs) {
  for (const Head& head : heads) {
    auto z = outputs.middleRows(head.firstOutput, head.size);
    if (head.kind == HeadKind::kSoftmax) {
      for (Eigen::Index t = 0; t < z.cols(); ++t) {
        const float top = z.col(t).maxCoeff();
        z.col(t) = (z.col(t).array() - top).exp().matrix();
        z.col(t) /= z.col(t).sum();
      }
    } else if (head.kind == HeadKind::kSigmoid) {
      z = (1.0f + (-z.array()).exp()).inverse().matrix();
    }
  }
}

}  // namespace th::nn
