#include "nn/network.h"

#include <cmath>
#include <random>
#include <string>

#include "core/error.h"

namespace th::nn {

void NetworkShape::check() const {
  if (inputs < 1) throw Error("network: " + std::to_string(inputs) + " inputs (at least 1)");
  if (outputs < 1) throw Error("network: " + std::to_string(outputs) + " outputs (at least 1)");
  for (const int units : hidden)
    if (units < 1) throw Error("network: a hidden layer of " + std::to_string(units) + " units (at least 1)");
}

Network Network::create(const NetworkShape& shape, unsigned seed) {
  shape.check();
  std::mt19937 random(seed);
  Network network;
  network.inputMean_ = Eigen::VectorXf::Zero(shape.inputs);
  network.inputScale_ = Eigen::VectorXf::Ones(shape.inputs);
  int fanIn = shape.inputs;
  std::vector<int> sizes = shape.hidden;
  sizes.push_back(shape.outputs);
  for (const int units : sizes) {
    // He et al. 2015: variance 2 / fan-in keeps a ReLU layer's activations at the scale of its inputs.
    std::normal_distribution<float> normal(0.0f, std::sqrt(2.0f / static_cast<float>(fanIn)));
    DenseLayer layer;
    layer.weights.resize(units, fanIn);
    for (Eigen::Index i = 0; i < layer.weights.size(); ++i) layer.weights.data()[i] = normal(random);
    layer.bias = Eigen::VectorXf::Zero(units);
    network.layers_.push_back(std::move(layer));
    fanIn = units;
  }
  return network;
}

Network Network::fromParts(Eigen::VectorXf inputMean, Eigen::VectorXf inputScale, std::vector<DenseLayer> layers) {
  if (layers.empty()) throw Error("network: no layers");
  if (inputMean.size() != inputScale.size() || inputMean.size() == 0)
    throw Error("network: the input standardisation's mean and scale differ in size or are empty");
  if (!inputMean.allFinite() || !inputScale.allFinite())
    throw Error("network: the input standardisation is not finite");
  Eigen::Index fanIn = inputMean.size();
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const DenseLayer& layer = layers[i];
    if (layer.weights.cols() != fanIn || layer.weights.rows() != layer.bias.size() || layer.bias.size() == 0)
      throw Error("network: layer " + std::to_string(i + 1) + " is " + std::to_string(layer.weights.rows()) + " x " +
                  std::to_string(layer.weights.cols()) + " with " + std::to_string(layer.bias.size()) +
                  " biases after " + std::to_string(fanIn) + " values");
    if (!layer.weights.allFinite() || !layer.bias.allFinite())
      throw Error("network: layer " + std::to_string(i + 1) + " holds a value that is not finite");
    fanIn = layer.bias.size();
  }
  Network network;
  network.inputMean_ = std::move(inputMean);
  network.inputScale_ = std::move(inputScale);
  network.layers_ = std::move(layers);
  return network;
}

void Network::setStandardisation(Eigen::VectorXf mean, Eigen::VectorXf scale) {
  if (mean.size() != inputs() || scale.size() != inputs())
    throw Error("network: a standardisation of " + std::to_string(mean.size()) + " values for " +
                std::to_string(inputs()) + " inputs");
  inputMean_ = std::move(mean);
  inputScale_ = std::move(scale);
}

void Network::fitStandardisation(const Eigen::Ref<const Eigen::MatrixXf>& frames) {
  if (frames.rows() != inputs() || frames.cols() < 2)
    throw Error("network: standardisation needs at least 2 frames of " + std::to_string(inputs()) + " inputs");
  const Eigen::VectorXd mean = frames.cast<double>().rowwise().mean();
  const Eigen::VectorXd deviation =
      ((frames.cast<double>().colwise() - mean).array().square().rowwise().sum() / static_cast<double>(frames.cols()))
          .sqrt();
  inputMean_ = mean.cast<float>();
  inputScale_ = (deviation.array() > 1e-6).select(deviation.cwiseInverse(), 1.0).cast<float>();
}

Eigen::MatrixXf Network::forward(const Eigen::Ref<const Eigen::MatrixXf>& frames) const {
  if (frames.rows() != inputs())
    throw Error("network: frames of " + std::to_string(frames.rows()) + " values for " + std::to_string(inputs()) +
                " inputs");
  Eigen::MatrixXf x = inputScale_.asDiagonal() * (frames.colwise() - inputMean_);
  for (std::size_t i = 0; i < layers_.size(); ++i) {
    Eigen::MatrixXf y = layers_[i].weights * x;
    y.colwise() += layers_[i].bias;
    if (i + 1 < layers_.size()) y = y.cwiseMax(0.0f);
    x = std::move(y);
  }
  return x;
}

Inference::Inference(const Network& network) : network_(network) {
  activations_.emplace_back(network.inputs());
  for (const DenseLayer& layer : network.layers()) activations_.emplace_back(layer.bias.size());
}

const Eigen::VectorXf& Inference::run(const Eigen::Ref<const Eigen::VectorXf>& frame) {
  activations_[0] = network_.inputScale().cwiseProduct(frame - network_.inputMean());
  const std::vector<DenseLayer>& layers = network_.layers();
  for (std::size_t i = 0; i < layers.size(); ++i) {
    Eigen::VectorXf& y = activations_[i + 1];
    y.noalias() = layers[i].weights * activations_[i];
    y += layers[i].bias;
    if (i + 1 < layers.size()) y = y.cwiseMax(0.0f);
  }
  return activations_.back();
}

}  // namespace th::nn
