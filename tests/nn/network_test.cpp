// The network, its training and its file form: gradients against finite differences, learning problems a
// linear model cannot solve, masks that keep a head out, exact round trips and errors that name the field.
#include "nn/network.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "nn/network_json.h"
#include "nn/training.h"

namespace th::nn {
namespace {

// Frames of the XOR-like problem: the class is whether x·y > 0, the regression target sin(2x) + y².
Frames xorFrames(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  Frames frames;
  frames.inputs.resize(2, count);
  frames.targets = Eigen::MatrixXf::Zero(3, count);
  frames.mask = Eigen::MatrixXf::Ones(2, count);
  for (int t = 0; t < count; ++t) {
    const float x = uniform(random), y = uniform(random);
    frames.inputs.col(t) << x, y;
    frames.targets(x * y > 0.0f ? 1 : 0, t) = 1.0f;
    frames.targets(2, t) = std::sin(2.0f * x) + y * y;
  }
  return frames;
}

const std::vector<Head> kXorHeads{{"class", HeadKind::kSoftmax, 0, 2, 1.0},
                                  {"value", HeadKind::kRegression, 2, 1, 1.0}};

double accuracy(const Network& network, const Frames& frames) {
  const Eigen::MatrixXf out = network.forward(frames.inputs);
  int right = 0;
  for (Eigen::Index t = 0; t < frames.size(); ++t) {
    Eigen::Index predicted = 0, truth = 0;
    out.col(t).head(2).maxCoeff(&predicted);
    frames.targets.col(t).head(2).maxCoeff(&truth);
    right += predicted == truth ? 1 : 0;
  }
  return static_cast<double>(right) / static_cast<double>(frames.size());
}

TEST(NetworkTest, GradientsMatchFiniteDifferencesForEveryKindOfHead) {
  std::mt19937 random(3);
  std::normal_distribution<float> normal;
  Frames frames;
  frames.inputs.resize(4, 7);
  for (Eigen::Index i = 0; i < frames.inputs.size(); ++i) frames.inputs.data()[i] = normal(random);
  frames.targets = Eigen::MatrixXf::Zero(7, 7);
  frames.mask = Eigen::MatrixXf::Ones(3, 7);
  for (int t = 0; t < 7; ++t) {
    frames.targets(t % 3, t) = 1.0f;                                                 // softmax over 3
    frames.targets(3, t) = normal(random), frames.targets(4, t) = normal(random);    // regression of 2
    frames.targets(5, t) = static_cast<float>(t % 2), frames.targets(6, t) = 0.25f;  // two sigmoids
  }
  frames.mask(1, 2) = 0.0f;  // one frame without a regression target
  frames.mask(2, 4) = 0.5f;  // and one that counts half for the sigmoids
  const std::vector<Head> heads{{"c", HeadKind::kSoftmax, 0, 3, 1.0},
                                {"r", HeadKind::kRegression, 3, 2, 0.7},
                                {"s", HeadKind::kSigmoid, 5, 2, 1.3}};
  Network network = Network::create({.inputs = 4, .hidden = {6, 5}, .outputs = 7}, 11);
  network.setStandardisation(Eigen::VectorXf::Constant(4, 0.1f), Eigen::VectorXf::Constant(4, 0.9f));
  const std::vector<DenseLayer> analytic = lossGradients(network, heads, frames);
  ASSERT_EQ(analytic.size(), 3u);
  // Central differences in double precision would be ideal; in float, a step of 1e-2 keeps the rounding error
  // of the loss (~1e-7 relative) far below the curvature's.
  constexpr float kStep = 1e-2f;
  int checked = 0;
  for (std::size_t l = 0; l < analytic.size(); ++l) {
    for (Eigen::Index i = 0; i < analytic[l].weights.size(); i += 3) {
      Network plus = network, minus = network;
      plus.mutableLayers()[l].weights.data()[i] += kStep;
      minus.mutableLayers()[l].weights.data()[i] -= kStep;
      const double numeric = (evaluateLoss(plus, heads, frames) - evaluateLoss(minus, heads, frames)) / (2.0 * kStep);
      EXPECT_NEAR(analytic[l].weights.data()[i], numeric, 2e-3 + 2e-2 * std::abs(numeric))
          << "layer " << l << " w" << i;
      ++checked;
    }
    for (Eigen::Index i = 0; i < analytic[l].bias.size(); ++i) {
      Network plus = network, minus = network;
      plus.mutableLayers()[l].bias[i] += kStep;
      minus.mutableLayers()[l].bias[i] -= kStep;
      const double numeric = (evaluateLoss(plus, heads, frames) - evaluateLoss(minus, heads, frames)) / (2.0 * kStep);
      EXPECT_NEAR(analytic[l].bias[i], numeric, 2e-3 + 2e-2 * std::abs(numeric)) << "layer " << l << " b" << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
}

TEST(NetworkTest, LearnsWhatALinearModelCannot) {
  const Frames training = xorFrames(4000, 1), test = xorFrames(1000, 2);
  Network linear = Network::create({.inputs = 2, .hidden = {}, .outputs = 3}, 1);
  Network deep = Network::create({.inputs = 2, .hidden = {32, 32}, .outputs = 3}, 1);
  linear.fitStandardisation(training.inputs);
  deep.fitStandardisation(training.inputs);
  const TrainingOptions options{.epochs = 40, .batchFrames = 64, .learningRate = 3e-3, .dropout = 0.0};
  train(linear, kXorHeads, training, nullptr, options);
  const TrainingReport report = train(deep, kXorHeads, training, nullptr, options);
  EXPECT_LT(report.trainingLoss.back(), 0.5 * report.trainingLoss.front());
  EXPECT_LT(accuracy(linear, test), 0.7);  // XOR: no line separates it
  EXPECT_GT(accuracy(deep, test), 0.95);
  // The regression head learnt too: its error well below the target's variance (about 0.5).
  const Eigen::MatrixXf out = deep.forward(test.inputs);
  const double mse = (out.row(2) - test.targets.row(2)).squaredNorm() / static_cast<double>(test.size());
  EXPECT_LT(mse, 0.02);
}

TEST(NetworkTest, AHeadMaskedOutOfEveryFrameLearnsNothing) {
  Frames training = xorFrames(2000, 4);
  training.mask.row(1).setZero();  // no regression targets
  Network network = Network::create({.inputs = 2, .hidden = {16}, .outputs = 3}, 2);
  network.fitStandardisation(training.inputs);
  const Network before = network;
  train(network, kXorHeads, training, nullptr, {.epochs = 5, .weightDecay = 0.0, .dropout = 0.0});
  // The regression output's own weights and bias never moved; the class outputs' did.
  const DenseLayer& out = network.layers().back();
  const DenseLayer& old = before.layers().back();
  EXPECT_EQ(out.weights.row(2), old.weights.row(2));
  EXPECT_EQ(out.bias[2], old.bias[2]);
  EXPECT_NE(out.weights.row(0), old.weights.row(0));
}

TEST(NetworkTest, ValidationKeepsTheBestEpochAndTrainingIsDeterministic) {
  const Frames training = xorFrames(500, 5), validation = xorFrames(300, 6);
  const auto run = [&] {
    Network network = Network::create({.inputs = 2, .hidden = {16}, .outputs = 3}, 3);
    network.fitStandardisation(training.inputs);
    const TrainingReport report =
        train(network, kXorHeads, training, &validation, {.epochs = 12, .dropout = 0.2, .inputNoise = 0.1});
    return std::make_pair(network, report);
  };
  const auto [first, report] = run();
  const auto [second, again] = run();
  ASSERT_EQ(report.validationLoss.size(), 12u);
  const auto best = std::min_element(report.validationLoss.begin(), report.validationLoss.end());
  EXPECT_EQ(report.bestEpoch, best - report.validationLoss.begin());
  EXPECT_NEAR(evaluateLoss(first, kXorHeads, validation), *best, 1e-6);
  EXPECT_EQ(report.trainingLoss, again.trainingLoss);
  EXPECT_EQ(first.layers()[0].weights, second.layers()[0].weights);
}

TEST(NetworkTest, InferenceFrameByFrameEqualsTheBatch) {
  Network network = Network::create({.inputs = 5, .hidden = {8, 8}, .outputs = 4}, 9);
  network.setStandardisation(Eigen::VectorXf::LinSpaced(5, -1.0f, 1.0f), Eigen::VectorXf::Constant(5, 2.0f));
  const Eigen::MatrixXf frames = Eigen::MatrixXf::Random(5, 20);
  const Eigen::MatrixXf batch = network.forward(frames);
  Inference one(network);
  for (Eigen::Index t = 0; t < frames.cols(); ++t) EXPECT_TRUE(one.run(frames.col(t)).isApprox(batch.col(t), 1e-6f));
}

TEST(NetworkTest, HeadsBecomeProbabilities) {
  Eigen::MatrixXf outputs(4, 2);
  outputs << 1.0f, -3.0f, 2.0f, 0.0f, 0.0f, 0.0f, 5.0f, -5.0f;
  applyHeads({{"c", HeadKind::kSoftmax, 0, 2, 1.0},
              {"r", HeadKind::kRegression, 2, 1, 1.0},
              {"s", HeadKind::kSigmoid, 3, 1, 1.0}},
             outputs);
  EXPECT_NEAR(outputs(0, 0) + outputs(1, 0), 1.0f, 1e-6f);
  EXPECT_NEAR(outputs(1, 0), 1.0f / (1.0f + std::exp(-1.0f)), 1e-6f);
  EXPECT_EQ(outputs(2, 0), 0.0f);
  EXPECT_NEAR(outputs(3, 0), 1.0f / (1.0f + std::exp(-5.0f)), 1e-6f);
}

TEST(NetworkJsonTest, Base64IsRfc4648LittleEndian) {
  const float one = 1.0f;  // 0x3F800000: bytes 00 00 80 3F
  EXPECT_EQ(encodeFloats(&one, 1), "AACAPw==");
  const std::vector<float> back = decodeFloats("AACAPw==", 1);
  EXPECT_EQ(back, std::vector<float>{1.0f});
  const std::vector<float> three{-2.5f, 1e-30f, 3.0e38f};
  EXPECT_EQ(decodeFloats(encodeFloats(three.data(), 3), 3), three);
  EXPECT_THROW(decodeFloats("AACAPw=", 1), Error);   // not a multiple of 4
  EXPECT_THROW(decodeFloats("AAC*Pw==", 1), Error);  // not in the alphabet
  EXPECT_THROW(decodeFloats("AACAPw==", 2), Error);  // too few values
}

TEST(NetworkJsonTest, RoundTripIsExact) {
  Network network = Network::create({.inputs = 3, .hidden = {4}, .outputs = 2}, 5);
  network.setStandardisation(Eigen::Vector3f(0.5f, -1.0f, 2.0f), Eigen::Vector3f(1.0f, 3.0f, 0.25f));
  const Json json = networkJson(network);
  const Network back = networkFromJson(Json::parse(json.dump()), JsonFields("m.json"), "network");
  EXPECT_EQ(back.inputMean(), network.inputMean());
  EXPECT_EQ(back.inputScale(), network.inputScale());
  ASSERT_EQ(back.layers().size(), 2u);
  for (std::size_t l = 0; l < 2; ++l) {
    EXPECT_EQ(back.layers()[l].weights, network.layers()[l].weights);
    EXPECT_EQ(back.layers()[l].bias, network.layers()[l].bias);
  }
}

TEST(NetworkJsonTest, ErrorsNameTheField) {
  const Network network = Network::create({.inputs = 3, .hidden = {4}, .outputs = 2}, 5);
  const auto failure = [&](const std::function<void(Json&)>& spoil) {
    Json json = networkJson(network);
    spoil(json);
    try {
      networkFromJson(json, JsonFields("m.json"), "network");
    } catch (const Error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(failure([](Json& j) { j["layers"][1]["rows"] = 3; }).find("network.layers[1]"), std::string::npos);
  EXPECT_NE(failure([](Json& j) { j["input_scale"] = "AAAA"; }).find("network.input_scale"), std::string::npos);
  EXPECT_NE(failure([](Json& j) { j["format"] = "float64"; }).find("network.format"), std::string::npos);
  EXPECT_NE(failure([](Json& j) { j["extra"] = 1; }).find("extra"), std::string::npos);
  const float nan = std::nanf("");
  EXPECT_NE(failure([&](Json& j) {
              j["layers"][0]["bias"] = encodeFloats(std::vector<float>{nan, 0, 0, 0}.data(), 4);
            }).find("not finite"),
            std::string::npos);
  EXPECT_EQ(failure([](Json&) {}), "no error");
  EXPECT_EQ(failure([](Json& j) { j["layers"][0]["rows"] = 5; }).rfind("m.json: network.layers[0]", 0), 0u);
}

}  // namespace
}  // namespace th::nn
