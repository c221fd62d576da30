// A small feed-forward network (multi-layer perceptron) for frame-by-frame speech models, on Eigen, on the CPU.
//
//   th::nn::Network net = th::nn::Network::create({.inputs = 350, .hidden = {256, 256}, .outputs = 40}, seed);
//   Eigen::MatrixXf out = net.forward(frames);              // frames: inputs x T, one frame per column
//   th::nn::Inference one(net);                             // per frame, without allocating:
//   const Eigen::VectorXf& y = one.run(frame);
//
// Layout: the input is standardised by a fixed mean and scale (fitted on the training frames), then each hidden
// layer is h = relu(W x + b), and the output layer is linear: y = W h + b. What the outputs mean (class logits,
// regression targets, binary logits) is the caller's (training.h: heads). Single precision: the models are small
// and Eigen's float products run twice as fast as double's on the same cores; the results are deterministic for
// a given build.
// Matrices hold one frame per column, as everywhere in the engine (hmm/gaussian.h).
// Thread contract: a Network is a value, safe to share read-only; an Inference belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace th::nn {

struct NetworkShape {
  int inputs = 0;
  std::vector<int> hidden;  // units per hidden layer (ReLU); may be empty (a linear model)
  int outputs = 0;
  void check() const;  // throws th::Error naming the bad size
};

struct DenseLayer {
  Eigen::MatrixXf weights;  // outputs x inputs
  Eigen::VectorXf bias;     // outputs
};

class Network {
 public:
  Network() = default;
  // He-initialised weights (normal, variance 2 / fan-in), zero biases, identity standardisation.
  static Network create(const NetworkShape& shape, unsigned seed);
  // From parts (a model file); throws th::Error if the sizes do not chain or a value is not finite.
  static Network fromParts(Eigen::VectorXf inputMean, Eigen::VectorXf inputScale, std::vector<DenseLayer> layers);

  int inputs() const { return static_cast<int>(inputMean_.size()); }
  int outputs() const { return layers_.empty() ? 0 : static_cast<int>(layers_.back().bias.size()); }

  // The standardisation: x' = (x − mean) ⊙ scale (scale = 1 / the training frames' deviation).
  const Eigen::VectorXf& inputMean() const { return inputMean_; }
  const Eigen::VectorXf& inputScale() const { return inputScale_; }
  void setStandardisation(Eigen::VectorXf mean, Eigen::VectorXf scale);
  // Fits the standardisation to frames (inputs x T): their mean, and 1 / their deviation (1 where it is ~0).
  void fitStandardisation(const Eigen::Ref<const Eigen::MatrixXf>& frames);

  const std::vector<DenseLayer>& layers() const { return layers_; }
  std::vector<DenseLayer>& mutableLayers() { return layers_; }  // for training

  // outputs x T for frames inputs x T.
  Eigen::MatrixXf forward(const Eigen::Ref<const Eigen::MatrixXf>& frames) const;

 private:
  Eigen::VectorXf inputMean_, inputScale_;
  std::vector<DenseLayer> layers_;  // hidden layers, then the output layer
};

// One frame at a time through a network, with buffers made once (the live decoder's per-frame step).
class Inference {
 public:
  explicit Inference(const Network& network);  // the network must outlive this
  const Eigen::VectorXf& run(const Eigen::Ref<const Eigen::VectorXf>& frame);

 private:
  const Network& network_;
  std::vector<Eigen::VectorXf> activations_;  // per layer
};

}  // namespace th::nn
