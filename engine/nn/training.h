// Training a network (network.h) on several tasks at once: its outputs are split into heads, each with its own
// loss, and each frame says which heads have a target for it (a frame with a phone label but no video trains
// the class head alone; a frame of tracked video without phones trains the shape heads alone).
//
//   std::vector<th::nn::Head> heads{{"class", th::nn::HeadKind::kSoftmax, 0, 17},
//                                   {"shape", th::nn::HeadKind::kRegression, 17, 4}};
//   th::nn::Frames data = ...;                 // inputs, targets (outputs x N), mask (heads x N)
//   th::nn::TrainingReport report = th::nn::train(net, heads, data, &validation, {.epochs = 30});
//
// Losses, per frame and head, weighed by the frame's mask value and the head's weight, averaged over the
// batch's frames: softmax cross-entropy against a target distribution (one-hot or soft), half the squared
// error of a regression, binary cross-entropy of a sigmoid. The optimiser is Adam with decoupled weight decay
// (AdamW: Loshchilov & Hutter 2019) and a cosine learning-rate schedule; dropout on the hidden units and
// Gaussian noise on the standardised inputs regularise, since the corpora here are small. With validation
// frames, the network kept is the one of the epoch with the lowest validation loss.
// Thread contract: train() runs on the caller's thread; the frames are read only.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "nn/network.h"

namespace th::nn {

enum class HeadKind { kSoftmax, kRegression, kSigmoid };

struct Head {
  std::string name;
  HeadKind kind = HeadKind::kRegression;
  int firstOutput = 0;
  int size = 1;
  double weight = 1.0;
};

struct Frames {
  Eigen::MatrixXf inputs;   // network inputs x N
  Eigen::MatrixXf targets;  // network outputs x N (rows of a head a frame has no target for are ignored)
  Eigen::MatrixXf mask;     // heads x N: each frame's weight for each head, 0 where it has no target
  Eigen::Index size() const { return inputs.cols(); }
};

struct TrainingOptions {
  int epochs = 30;
  int batchFrames = 256;
  double learningRate = 1e-3;       // at the start; falls along a cosine to finalLearningRate
  double finalLearningRate = 1e-5;  // at the last epoch
  double weightDecay = 1e-4;        // decoupled, per step, times the learning rate
  double dropout = 0.1;             // the share of hidden units dropped in training
  double inputNoise = 0.0;          // Gaussian noise on the standardised inputs (their deviation is 1)
  unsigned seed = 1;
  void check() const;  // throws th::Error naming the bad option
};

struct TrainingReport {
  std::vector<double> trainingLoss;    // per epoch, on the training frames as trained (dropout on)
  std::vector<double> validationLoss;  // per epoch (empty without validation frames)
  int bestEpoch = -1;                  // whose network was kept (the last without validation)
};

// Checks that the heads lie within the network's outputs without overlap and that the frames fit them.
void checkHeads(const Network& network, const std::vector<Head>& heads, const Frames& frames);

// The weighted loss per frame over `frames` (mean over frames of the heads' summed losses), no dropout.
double evaluateLoss(const Network& network, const std::vector<Head>& heads, const Frames& frames);

// The gradient of evaluateLoss with respect to every layer's weights and biases (no dropout, no noise): what
// training follows, exposed so that it can be checked against finite differences.
std::vector<DenseLayer> lossGradients(const Network& network, const std::vector<Head>& heads, const Frames& frames);

// Trains `network` in place (its standardisation as it is: fit it first). progress(epoch, epochs) after each.
TrainingReport train(Network& network, const std::vector<Head>& heads, const Frames& training, const Frames* validation,
                     const TrainingOptions& options, const std::function<void(int, int)>& progress = {});

// The heads' outputs made readable: softmax heads as probabilities, sigmoid heads as probabilities, regression
// heads as they are (in place on outputs x T).
void applyHeads(const std::vector<Head>& heads, Eigen::Ref<Eigen::MatrixXf> outputs);

}  // namespace th::nn
