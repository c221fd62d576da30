// Model files: save → load is bit-exact (parameters and log-likelihoods); every bad file is refused with one line
// naming the file and the field at fault; a failed save leaves the previous file (or nothing) and no temporary.
#include "hmm/model_file.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/temporary_file.h"
#include "hmm/forward_backward.h"
#include "hmm/sampling.h"
#include "hmm_test_models.h"
#include "support/files.h"

namespace th::hmm {
namespace {

using th::test::listFolder;
using th::test::readText;

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

using TemporaryFolder = th::TemporaryFolder;

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// Bit for bit, so that -0.0 against 0.0 or a last-bit difference counts.
::testing::AssertionResult sameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return ::testing::AssertionFailure() << "shapes differ";
  if (a.size() > 0 && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) != 0) {
    return ::testing::AssertionFailure() << "values differ:\n" << a << "\nvs\n" << b;
  }
  return ::testing::AssertionSuccess();
}

void expectIdentical(const HmmModel& a, const HmmModel& b) {
  EXPECT_TRUE(sameBits(a.initial, b.initial));
  EXPECT_TRUE(sameBits(a.transition, b.transition));
  ASSERT_EQ(a.numStates(), b.numStates());
  for (int j = 0; j < a.numStates(); ++j) {
    const auto& sa = a.states[static_cast<size_t>(j)];
    const auto& sb = b.states[static_cast<size_t>(j)];
    EXPECT_TRUE(sameBits(sa.weights(), sb.weights())) << "state " << j;
    ASSERT_EQ(sa.numComponents(), sb.numComponents());
    for (int m = 0; m < sa.numComponents(); ++m) {
      const Gaussian& ga = sa.components()[static_cast<size_t>(m)];
      const Gaussian& gb = sb.components()[static_cast<size_t>(m)];
      EXPECT_EQ(ga.type(), gb.type());
      EXPECT_TRUE(sameBits(ga.mean(), gb.mean())) << "state " << j << " component " << m;
      EXPECT_TRUE(sameBits(ga.covariance(), gb.covariance())) << "state " << j << " component " << m;
      EXPECT_TRUE(sameBits(Eigen::VectorXd::Constant(1, ga.logDeterminant()),
                           Eigen::VectorXd::Constant(1, gb.logDeterminant())));
    }
  }
  EXPECT_EQ(a.columnNames, b.columnNames);
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (size_t k = 0; k < a.blocks.size(); ++k) {
    EXPECT_EQ(a.blocks[k].name, b.blocks[k].name);
    EXPECT_EQ(a.blocks[k].begin, b.blocks[k].begin);
    EXPECT_EQ(a.blocks[k].size, b.blocks[k].size);
  }
}

// A model with names: columns x0.. and an audio | visual split.
HmmModel namedModel(int numStates, int numMixtures, int dimension, CovarianceType type, unsigned seed) {
  HmmModel model = test::randomModel(numStates, numMixtures, dimension, type, seed);
  for (int i = 0; i < dimension; ++i) model.columnNames.push_back("x" + std::to_string(i));
  if (dimension >= 2) model.blocks = {{"audio", 0, dimension - 1}, {"visual", dimension - 1, 1}};
  return model;
}

// ---------------------------------------------------------------------------------------------------------------
// Round trips

struct RoundTripCase {
  int numStates, numMixtures, dimension;
  CovarianceType type;
  unsigned seed;
};

class ModelFileRoundTrip : public ::testing::TestWithParam<RoundTripCase> {};

TEST_P(ModelFileRoundTrip, ParametersAndLogLikelihoodsAreBitIdentical) {
  const RoundTripCase c = GetParam();
  const HmmModel model = namedModel(c.numStates, c.numMixtures, c.dimension, c.type, c.seed);
  TemporaryFolder folder;
  const fs::path path = folder.path() / "model.json";
  const std::string training = R"({"iterations":3,"logLikelihoods":[-1234.5678,-1000.1],"options":{"z":0.5}})";
  saveModel(path, model, training);
  std::string trainingBack;
  const HmmModel loaded = loadModel(path, &trainingBack);
  expectIdentical(model, loaded);
  EXPECT_EQ(trainingBack, training);  // same keys, same order, same numbers

  std::mt19937 random(c.seed + 100);
  const Eigen::MatrixXd frames = sampleHmm(model, 300, random).frames;
  const Eigen::MatrixXd logB = model.emissionLogLikelihoods(frames);
  const Eigen::MatrixXd logBLoaded = loaded.emissionLogLikelihoods(frames);
  EXPECT_TRUE(sameBits(logB, logBLoaded));
  const double before = logLikelihood(model, logB);
  const double after = logLikelihood(loaded, logBLoaded);
  EXPECT_EQ(std::memcmp(&before, &after, sizeof(double)), 0) << before << " vs " << after;

  // Writing the loaded model again gives the same bytes: nothing drifts over repeated save/load.
  EXPECT_EQ(formatModel(loaded, trainingBack), readText(path));
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"model.json"});  // no temporary left
}

INSTANTIATE_TEST_SUITE_P(ModelFile, ModelFileRoundTrip,
                         ::testing::Values(RoundTripCase{1, 1, 1, CovarianceType::kFull, 1},
                                           RoundTripCase{3, 2, 4, CovarianceType::kFull, 2},
                                           RoundTripCase{5, 3, 7, CovarianceType::kFull, 3},
                                           RoundTripCase{4, 2, 23, CovarianceType::kFull, 4},
                                           RoundTripCase{1, 1, 1, CovarianceType::kDiagonal, 5},
                                           RoundTripCase{3, 2, 4, CovarianceType::kDiagonal, 6},
                                           RoundTripCase{19, 3, 12, CovarianceType::kDiagonal, 7}),
                         [](const ::testing::TestParamInfo<RoundTripCase>& testInfo) {
                           const RoundTripCase& c = testInfo.param;
                           return std::string(c.type == CovarianceType::kFull ? "full" : "diagonal") + "_N" +
                                  std::to_string(c.numStates) + "_M" + std::to_string(c.numMixtures) + "_d" +
                                  std::to_string(c.dimension);
                         });

TEST(ModelFile, AwkwardNumbersRoundTripExactly) {
  // Values whose shortest decimal form is long, denormals, -0, the extremes the loader allows.
  HmmModel model;
  model.initial = Eigen::Vector2d(0.1, 0.9);
  model.transition.resize(2, 2);
  model.transition << 1.0 / 3.0, 2.0 / 3.0, 5e-324, 1.0;
  const Eigen::Vector3d mean(-0.0, 1e149, 4.9406564584124654e-324);
  const Eigen::Vector3d variances(1e-150, 1e150, 0.30000000000000004);
  model.states.emplace_back(Eigen::VectorXd::Ones(1),
                            std::vector<Gaussian>{Gaussian(mean, variances.asDiagonal(), CovarianceType::kDiagonal)});
  model.states.emplace_back(
      Eigen::Vector2d(1e-300, 1.0 - 1e-300),
      std::vector<Gaussian>{Gaussian(-mean, Eigen::Matrix3d::Identity() * 7.0, CovarianceType::kDiagonal),
                            Gaussian(mean, Eigen::Matrix3d::Identity() * 1e-3, CovarianceType::kDiagonal)});
  const HmmModel loaded = parseModel(formatModel(model), "awkward.json");
  expectIdentical(model, loaded);
  EXPECT_TRUE(std::signbit(loaded.states[0].components()[0].mean()[0]));
}

TEST(ModelFile, TheFileHasTheDocumentedShape) {
  const HmmModel model = namedModel(2, 2, 3, CovarianceType::kFull, 11);
  const Json document = Json::parse(formatModel(model, R"({"iterations": 7})"));
  std::vector<std::string> keys;
  for (auto it = document.begin(); it != document.end(); ++it) keys.push_back(it.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"format", "version", "covariance", "columns", "blocks", "initial",
                                            "transition", "states", "training"}));
  EXPECT_EQ(document["format"], "talkinghead-hmm");
  EXPECT_EQ(document["version"], 1);
  EXPECT_EQ(document["covariance"], "full");
  EXPECT_EQ(document["columns"], Json({"x0", "x1", "x2"}));
  EXPECT_EQ(document["blocks"][1], Json({{"name", "visual"}, {"begin", 2}, {"size", 1}}));
  EXPECT_EQ(document["transition"].size(), 2u);
  EXPECT_EQ(document["states"][1]["weights"].size(), 2u);
  EXPECT_EQ(document["states"][1]["components"][0]["covariance"].size(), 3u);
  EXPECT_EQ(document["states"][1]["components"][0]["covariance"][2].size(), 3u);
  EXPECT_EQ(document["training"]["iterations"], 7);

  const Json diagonal = Json::parse(formatModel(namedModel(2, 1, 3, CovarianceType::kDiagonal, 12)));
  EXPECT_EQ(diagonal["covariance"], "diagonal");
  EXPECT_EQ(diagonal["states"][0]["components"][0]["variances"].size(), 3u);
  EXPECT_FALSE(diagonal["states"][0]["components"][0].contains("covariance"));
  EXPECT_FALSE(diagonal.contains("training"));  // none given: none written
}

TEST(ModelFile, AcceptsWhatOtherWritersMayProduce) {
  Json document = Json::parse(formatModel(test::stickyModel1d(2, 0.9)));
  // Integers where numbers are expected, a row off by less than the tolerance, keys in another order, no
  // "training", a slightly asymmetric covariance (which the loader averages with its transpose).
  document["initial"] = Json::array({1, 0});
  document["transition"][0] = Json::array({0.9 + 5e-7, 0.1});
  document["states"][0]["components"][0]["covariance"] = Json::array({Json::array({2})});
  std::string training;
  const HmmModel loaded = parseModel(document.dump(), "other.json", &training);
  EXPECT_EQ(loaded.initial[0], 1.0);
  EXPECT_EQ(loaded.transition(0, 0), 0.9 + 5e-7);
  EXPECT_EQ(loaded.states[0].components()[0].covariance()(0, 0), 2.0);
  EXPECT_EQ(training, "{}");

  const HmmModel full = test::randomModel(1, 1, 2, CovarianceType::kFull, 5);
  Json nearlySymmetric = Json::parse(formatModel(full));
  const double offDiagonal = full.states[0].components()[0].covariance()(0, 1);
  nearlySymmetric["states"][0]["components"][0]["covariance"][0][1] = offDiagonal * (1.0 + 1e-12);
  const HmmModel averaged = parseModel(nearlySymmetric.dump(), "nearly.json");
  const Eigen::MatrixXd& covariance = averaged.states[0].components()[0].covariance();
  EXPECT_EQ(covariance(0, 1), covariance(1, 0));
  EXPECT_NEAR(covariance(0, 1), offDiagonal, 1e-12 * std::abs(offDiagonal));
}

// ---------------------------------------------------------------------------------------------------------------
// Bad files: each case changes one thing in a valid document; the error must be one line, start with the file's
// name and contain `expected` (the field and what is wrong with it).

struct BadCase {
  std::string name;
  bool diagonal = false;              // which valid document to start from
  std::function<void(Json&)> change;  // applied to the document
  std::string expected;
};

Json validDocument(bool diagonal) {
  // N = 3, M = 2, d = 3; columns a, b, c; blocks audio [0, 2) and visual [2, 3).
  HmmModel model = test::randomModel(3, 2, 3, diagonal ? CovarianceType::kDiagonal : CovarianceType::kFull, 21);
  model.columnNames = {"a", "b", "c"};
  model.blocks = {{"audio", 0, 2}, {"visual", 2, 1}};
  return Json::parse(formatModel(model, R"({"iterations": 2})"));
}

Json& component(Json& document, int state, int m) {
  return document["states"][state]["components"][m];
}

std::vector<BadCase> badCases() {
  auto full = [](std::string name, std::function<void(Json&)> change, std::string expected) {
    return BadCase{std::move(name), false, std::move(change), std::move(expected)};
  };
  auto diag = [](std::string name, std::function<void(Json&)> change, std::string expected) {
    return BadCase{std::move(name), true, std::move(change), std::move(expected)};
  };
  return {
      // What the file is.
      full(
          "topLevelArray",
          [](Json& j) {
            j = Json::array({1, 2});
          },
          "not a talkinghead HMM model (the top level is an array"),
      full(
          "missingFormat", [](Json& j) { j.erase("format"); },
          "not a talkinghead HMM model (it has no \"format\" field)"),
      full(
          "otherFormat", [](Json& j) { j["format"] = "some-other-hmm"; },
          "format is \"some-other-hmm\", not \"talkinghead-hmm\""),
      full(
          "formatNotString", [](Json& j) { j["format"] = 3; }, "format is 3, not \"talkinghead-hmm\""),
      full(
          "missingVersion", [](Json& j) { j.erase("version"); }, "version is missing"),
      full(
          "newerVersion", [](Json& j) { j["version"] = 2; },
          "version is 2: the file was written by a newer talkinghead (this one reads version 1)"),
      // A newer file may have fields this version does not know: the version is what to report, not the field.
      full(
          "newerVersionWithNewField",
          [](Json& j) {
            j["version"] = 3;
            j["cholesky"] = Json::array();
          },
          "version is 3: the file was written by a newer"),
      full(
          "olderVersion", [](Json& j) { j["version"] = 0; }, "version is 0, which is not a version of this format"),
      full(
          "negativeVersion", [](Json& j) { j["version"] = -1; }, "version is -1, which is not a version"),
      full(
          "versionString", [](Json& j) { j["version"] = "1"; }, "version is \"1\", not an integer"),
      full(
          "versionFraction", [](Json& j) { j["version"] = 1.5; }, "version is 1.5, not an integer"),
      full(
          "unknownField", [](Json& j) { j["comment"] = "hi"; }, "comment is not a field of a version-1 model file"),
      full(
          "missingCovariance", [](Json& j) { j.erase("covariance"); }, "covariance is missing"),
      full(
          "unknownCovariance", [](Json& j) { j["covariance"] = "spherical"; },
          "covariance is \"spherical\"; expected \"full\" or \"diagonal\""),
      full(
          "covarianceSaysDiagonal", [](Json& j) { j["covariance"] = "diagonal"; },
          "states[0].components[0].covariance is not a field of a diagonal-covariance component"),
      // Sizes.
      full(
          "missingStates", [](Json& j) { j.erase("states"); }, "states is missing"),
      full(
          "statesNotArray", [](Json& j) { j["states"] = Json::object(); }, "states is an object, not an array"),
      full(
          "noStates", [](Json& j) { j["states"] = Json::array(); },
          "states is empty (a model needs at least one state)"),
      full(
          "tooManyStates", [](Json& j) { j["states"] = Json(std::vector<Json>(10001)); },
          "states has 10001 states; at most 10000"),
      full(
          "tooManyComponents", [](Json& j) { j["states"][0]["weights"] = Json(std::vector<double>(1001, 0.0)); },
          "states[0].weights has 1001 values; at most 1000 components per state"),
      full(
          "noComponents",
          [](Json& j) {
            j["states"][1]["weights"] = Json::array();
            j["states"][1]["components"] = Json::array();
          },
          "states[1].weights is empty (a state needs at least one component)"),
      full(
          "moreWeightsThanComponents", [](Json& j) { j["states"][1]["weights"].push_back(0.0); },
          "states[1].components has 2 components but states[1].weights has 3 weights"),
      full(
          "zeroDimension", [](Json& j) { component(j, 0, 0)["mean"] = Json::array(); },
          "states[0].components[0].mean is empty"),
      full(
          "tooManyDimensions", [](Json& j) { component(j, 0, 0)["mean"] = Json(std::vector<double>(10001, 0.0)); },
          "states[0].components[0].mean has 10001 values; at most 10000 dimensions"),
      // π and A.
      full(
          "missingInitial", [](Json& j) { j.erase("initial"); }, "initial is missing"),
      full(
          "initialTooShort",
          [](Json& j) {
            j["initial"] = Json::array({0.5, 0.5});
          },
          "initial has 2 values; expected 3 (one per state)"),
      full(
          "initialNotNumber", [](Json& j) { j["initial"][1] = "0.3"; }, "initial[1] is a string, not a number"),
      full(
          "initialNull", [](Json& j) { j["initial"][2] = nullptr; }, "initial[2] is null, not a number"),
      full(
          "initialNegative",
          [](Json& j) {
            j["initial"] = Json::array({-0.25, 0.75, 0.5});
          },
          "initial[0] is negative (-0.25)"),
      full(
          "initialSum",
          [](Json& j) {
            j["initial"] = Json::array({0.5, 0.5, 0.5});
          },
          "initial sums to 1.5, not 1"),
      full(
          "transitionNotArray", [](Json& j) { j["transition"] = "identity"; }, "transition is a string, not an array"),
      full(
          "transitionTooFewRows", [](Json& j) { j["transition"].erase(2); },
          "transition has 2 rows; expected 3 (one per state)"),
      full(
          "transitionShortRow", [](Json& j) { j["transition"][1].erase(0); }, "transition[1] has 2 values; expected 3"),
      full(
          "transitionRowNotArray", [](Json& j) { j["transition"][1] = 1.0; },
          "transition[1] is a number, not an array"),
      full(
          "transitionRowSum",
          [](Json& j) {
            j["transition"][2] = Json::array({0.5, 0.5, 2e-6});
          },
          "transition[2] sums to 1.000002, not 1 (the tolerance is 1e-6)"),
      full(
          "transitionNegative",
          [](Json& j) {
            j["transition"][0] = Json::array({1.5, -0.5, 0.0});
          },
          "transition[0][1] is negative (-0.5)"),
      // Mixtures.
      full(
          "stateNotObject", [](Json& j) { j["states"][1] = Json::array(); }, "states[1] is an array, not an object"),
      full(
          "stateUnknownField", [](Json& j) { j["states"][1]["name"] = "s1"; },
          "states[1].name is not a field of a state"),
      full(
          "weightsMissing", [](Json& j) { j["states"][2].erase("weights"); }, "states[2].weights is missing"),
      full(
          "weightsSum",
          [](Json& j) {
            j["states"][1]["weights"] = Json::array({0.5, 0.4});
          },
          "states[1].weights sums to 0.9, not 1"),
      full(
          "weightNegative",
          [](Json& j) {
            j["states"][1]["weights"] = Json::array({1.5, -0.5});
          },
          "states[1].weights[1] is negative"),
      // Components, full.
      full(
          "componentNotObject", [](Json& j) { component(j, 2, 1) = 4; },
          "states[2].components[1] is an integer, not an object"),
      full(
          "componentMisspeltField",
          [](Json& j) { component(j, 0, 1)["covarience"] = component(j, 0, 1)["covariance"]; },
          "states[0].components[1].covarience is not a field of a full-covariance component"),
      full(
          "meanMissing", [](Json& j) { component(j, 1, 0).erase("mean"); }, "states[1].components[0].mean is missing"),
      full(
          "meanWrongDimension", [](Json& j) { component(j, 2, 1)["mean"].erase(0); },
          "states[2].components[1].mean has 2 values; expected 3 (the dimension, set by states[0].components[0].mean)"),
      full(
          "meanNotNumber", [](Json& j) { component(j, 1, 1)["mean"][2] = Json::array(); },
          "states[1].components[1].mean[2] is an array, not a number"),
      full(
          "meanHuge", [](Json& j) { component(j, 1, 1)["mean"][0] = -1e200; },
          "states[1].components[1].mean[0] is -1e+200; magnitudes above 1e150 are not supported"),
      full(
          "covarianceMissing", [](Json& j) { component(j, 1, 0).erase("covariance"); },
          "states[1].components[0].covariance is missing"),
      full(
          "covarianceTooFewRows", [](Json& j) { component(j, 1, 0)["covariance"].erase(1); },
          "states[1].components[0].covariance has 2 rows; expected 3"),
      full(
          "covarianceShortRow", [](Json& j) { component(j, 1, 0)["covariance"][1].erase(1); },
          "states[1].components[0].covariance[1] has 2 values; expected 3"),
      full(
          "covarianceHuge", [](Json& j) { component(j, 1, 0)["covariance"][2][2] = 1e151; },
          "states[1].components[0].covariance[2][2] is 1e+151; magnitudes above 1e150"),
      full(
          "covarianceAsymmetric",
          [](Json& j) {
            component(j, 2, 0)["covariance"][0][2] = 0.123;
            component(j, 2, 0)["covariance"][2][0] = 0.124;
          },
          "states[2].components[0].covariance is not symmetric ([0][2] is 0.123 but [2][0] is 0.124)"),
      full(
          "covarianceIndefinite",
          [](Json& j) { component(j, 2, 1)["covariance"] = Json::parse("[[1, 2, 0], [2, 1, 0], [0, 0, 1]]"); },
          "states[2].components[1].covariance is not positive definite"),
      full(
          "covarianceNegative",
          [](Json& j) { component(j, 0, 0)["covariance"] = Json::parse("[[-1, 0, 0], [0, 1, 0], [0, 0, 1]]"); },
          "states[0].components[0].covariance is not positive definite"),
      full(
          "covarianceZero",
          [](Json& j) { component(j, 0, 0)["covariance"] = Json::parse("[[0, 0, 0], [0, 0, 0], [0, 0, 0]]"); },
          "states[0].components[0].covariance is not positive definite"),
      full(
          "covarianceNearlySingular",
          [](Json& j) { component(j, 0, 1)["covariance"] = Json::parse("[[1, 0, 0], [0, 1e-160, 0], [0, 0, 1]]"); },
          "states[0].components[1].covariance is nearly singular"),
      // Components, diagonal.
      diag(
          "variancesMissing", [](Json& j) { component(j, 1, 1).erase("variances"); },
          "states[1].components[1].variances is missing"),
      diag(
          "diagonalWithMatrix", [](Json& j) { component(j, 1, 1)["covariance"] = Json::array(); },
          "states[1].components[1].covariance is not a field of a diagonal-covariance component"),
      diag(
          "variancesWrongLength", [](Json& j) { component(j, 2, 0)["variances"].push_back(1.0); },
          "states[2].components[0].variances has 4 values; expected 3"),
      diag(
          "varianceZero", [](Json& j) { component(j, 0, 1)["variances"][1] = 0.0; },
          "states[0].components[1].variances[1] is not positive (0)"),
      diag(
          "varianceNegative", [](Json& j) { component(j, 0, 1)["variances"][2] = -2.5; },
          "states[0].components[1].variances[2] is not positive (-2.5)"),
      diag(
          "varianceTiny", [](Json& j) { component(j, 0, 1)["variances"][0] = 1e-200; },
          "states[0].components[1].variances[0] is 1e-200; variances below 1e-150"),
      diag(
          "varianceHuge", [](Json& j) { component(j, 0, 1)["variances"][0] = 1e300; },
          "states[0].components[1].variances[0] is 1e+300; magnitudes above 1e150"),
      diag(
          "diagonalMeanWrongDimension", [](Json& j) { component(j, 1, 0)["mean"].push_back(0.0); },
          "states[1].components[0].mean has 4 values; expected 3"),
      // Names.
      full(
          "columnsMissing", [](Json& j) { j.erase("columns"); }, "columns is missing"),
      full(
          "columnsWrongCount",
          [](Json& j) {
            j["columns"] = Json::array({"a", "b"});
          },
          "columns has 2 names; expected 3 (one per dimension) or none"),
      full(
          "columnNotString", [](Json& j) { j["columns"][1] = 7; }, "columns[1] is an integer, not a string"),
      full(
          "blocksMissing", [](Json& j) { j.erase("blocks"); }, "blocks is missing"),
      full(
          "blocksNotArray", [](Json& j) { j["blocks"] = "audio"; }, "blocks is a string, not an array"),
      full(
          "blockGap", [](Json& j) { j["blocks"][1]["begin"] = 3; },
          "blocks[1].begin is 3; expected 2 (blocks tile the dimensions in order"),
      full(
          "blockOverlap", [](Json& j) { j["blocks"][1]["begin"] = 1; }, "blocks[1].begin is 1; expected 2"),
      full(
          "blockNotFromZero", [](Json& j) { j["blocks"][0]["begin"] = 1; }, "blocks[0].begin is 1; expected 0"),
      full(
          "blockEmpty", [](Json& j) { j["blocks"][0]["size"] = 0; },
          "blocks[0].size is 0; a block has at least one dimension"),
      full(
          "blockNegativeSize", [](Json& j) { j["blocks"][0]["size"] = -2; },
          "blocks[0].size is -2; a block has at least one dimension"),
      full(
          "blockPastTheEnd", [](Json& j) { j["blocks"][1]["size"] = 5; },
          "blocks[1].size is 5: the block would end past the last dimension (there are 3)"),
      full(
          "blocksShort", [](Json& j) { j["blocks"].erase(1); },
          "blocks cover dimensions 0 to 1 of 3; together they must cover every dimension"),
      full(
          "blockBeginFraction", [](Json& j) { j["blocks"][0]["begin"] = 0.5; },
          "blocks[0].begin is 0.5, not an integer"),
      full(
          "blockSizeHuge", [](Json& j) { j["blocks"][1]["size"] = std::numeric_limits<std::uint64_t>::max(); },
          "blocks[1].size is 18446744073709551615, out of range"),
      full(
          "blockNameMissing", [](Json& j) { j["blocks"][0].erase("name"); }, "blocks[0].name is missing"),
      full(
          "blockNameEmpty", [](Json& j) { j["blocks"][0]["name"] = ""; }, "blocks[0].name is empty"),
      full(
          "blockNameTwice", [](Json& j) { j["blocks"][1]["name"] = "audio"; },
          "blocks[1].name \"audio\" is used by an earlier block"),
      full(
          "blockUnknownField", [](Json& j) { j["blocks"][1]["end"] = 3; }, "blocks[1].end is not a field of a block"),
      // Free-form metadata still has to be an object.
      full(
          "trainingNotObject", [](Json& j) { j["training"] = Json::array({1}); },
          "training is an array, not an object"),
  };
}

class ModelFileBadInput : public ::testing::TestWithParam<BadCase> {};

void expectOneLineError(const std::function<void()>& action, const std::string& name, const std::string& expected) {
  try {
    action();
    ADD_FAILURE() << "accepted; expected an error containing: " << expected;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(name + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST_P(ModelFileBadInput, IsRefusedWithTheFieldNamed) {
  const BadCase& c = GetParam();
  Json document = validDocument(c.diagonal);
  c.change(document);
  const std::string text = document.dump();
  expectOneLineError([&] { parseModel(text, "memory.json"); }, "memory.json", c.expected);
  // The same through the file: the message starts with the path.
  TemporaryFolder folder;
  const fs::path path = folder.path() / (c.name + ".json");
  writeText(path, text);
  expectOneLineError([&] { loadModel(path); }, path.string(), c.expected);
}

INSTANTIATE_TEST_SUITE_P(ModelFile, ModelFileBadInput, ::testing::ValuesIn(badCases()),
                         [](const ::testing::TestParamInfo<BadCase>& testInfo) { return testInfo.param.name; });

TEST(ModelFile, TheValidDocumentsOfTheBadCasesAreValid) {
  // Otherwise every bad case could pass for the wrong reason.
  EXPECT_NO_THROW(parseModel(validDocument(false).dump(), "full.json"));
  EXPECT_NO_THROW(parseModel(validDocument(true).dump(), "diagonal.json"));
}

// Text that is not a JSON document at all, or one nlohmann cannot hold.
TEST(ModelFile, RefusesTextThatIsNotAModel) {
  const std::string name = "text.json";
  expectOneLineError([&] { parseModel("", name); }, name, "is empty");
  expectOneLineError([&] { parseModel(" \n\t ", name); }, name, "is empty");
  expectOneLineError([&] { parseModel("{", name); }, name, "not valid JSON (parse error at line 1, column 2");
  expectOneLineError([&] { parseModel("talkinghead-hmm 1", name); }, name, "not valid JSON");
  expectOneLineError([&] { parseModel("{\"format\": \"talkinghead-hmm\",\n \"version\": 1,}", name); }, name,
                     "not valid JSON (parse error at line 2");
  expectOneLineError([&] { parseModel("null", name); }, name, "the top level is null");
  expectOneLineError([&] { parseModel("\"talkinghead-hmm\"", name); }, name, "the top level is a string");
  expectOneLineError([&] { parseModel(std::string("{\"format\": \"\xff\"}"), name); }, name, "not valid JSON");
  expectOneLineError([&] { parseModel(std::string("{\"format\": \"a\x01\"}"), name); }, name, "not valid JSON");
  // Bytes after the document.
  expectOneLineError([&] { parseModel(validDocument(false).dump() + "x", name); }, name, "not valid JSON");

  // 1e999 does not fit a double: nlohmann refuses it without a position, so the loader finds it.
  Json document = validDocument(false);
  document["states"][1]["components"][0]["mean"][1] = "@@";
  std::string text = document.dump(1);
  text.replace(text.find("\"@@\""), 4, "1e999");
  expectOneLineError([&] { parseModel(text, name); }, name, "the number 1e999 at line ");
  expectOneLineError([&] { parseModel(text, name); }, name, "is out of the range of a double");
  // 1e-999 underflows to 0, which is then judged as a value: a variance of 0 is refused.
  Json diagonal = validDocument(true);
  diagonal["states"][0]["components"][0]["variances"][0] = "@@";
  text = diagonal.dump();
  text.replace(text.find("\"@@\""), 4, "1e-999");
  expectOneLineError([&] { parseModel(text, name); }, name, "states[0].components[0].variances[0] is not positive (0)");
}

TEST(ModelFile, RefusesDeepNestingWithoutRunningOutOfStack) {
  const std::string name = "deep.json";
  expectOneLineError([&] { parseModel(std::string(100000, '[') + std::string(100000, ']'), name); }, name,
                     "nests arrays and objects more than 64 deep");
  Json document = validDocument(false);
  Json nested = Json::array();
  for (int i = 0; i < 70; ++i) nested = Json::array({nested});
  document["training"] = {{"deep", nested}};
  expectOneLineError([&] { parseModel(document.dump(), name); }, name, "nests arrays and objects more than 64 deep");
  // A little nesting in "training" is fine.
  Json shallow = Json::array();
  for (int i = 0; i < 20; ++i) shallow = Json::array({shallow});
  document["training"] = {{"deep", shallow}};
  std::string training;
  EXPECT_NO_THROW(parseModel(document.dump(), name, &training));
  EXPECT_EQ(Json::parse(training)["deep"], shallow);
}

TEST(ModelFile, RefusesFilesThatCannotBeRead) {
  TemporaryFolder folder;
  const fs::path missing = folder.path() / "missing.json";
  expectOneLineError([&] { loadModel(missing); }, missing.string(), "does not exist");
  const fs::path inMissingFolder = folder.path() / "no" / "model.json";
  expectOneLineError([&] { loadModel(inMissingFolder); }, inMissingFolder.string(), "does not exist");
  expectOneLineError([&] { loadModel(folder.path()); }, folder.path().string(), "is a directory, not a model file");
  const fs::path empty = folder.path() / "empty.json";
  writeText(empty, "");
  expectOneLineError([&] { loadModel(empty); }, empty.string(), "is empty");
  if (::geteuid() != 0) {  // root reads anything
    const fs::path locked = folder.path() / "locked.json";
    saveModel(locked, test::stickyModel1d(2, 0.9));
    fs::permissions(locked, fs::perms::none);
    expectOneLineError([&] { loadModel(locked); }, locked.string(), "cannot be read");
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Saving

TEST(ModelFile, SaveRefusesAModelTheLoaderWouldRefuseAndWritesNothing) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "model.json";

  HmmModel rowOff = test::stickyModel1d(3, 0.8);
  rowOff.transition(1, 1) += 0.1;
  expectOneLineError([&] { saveModel(path, rowOff); }, path.string(), "cannot be written: HMM: transition row 1");

  // Gaussian accepts a mean of 1e200; the loader does not (squared distances would overflow).
  HmmModel huge = test::stickyModel1d(2, 0.8);
  huge.states[1] = GaussianMixture(
      Eigen::VectorXd::Ones(1),
      {Gaussian(Eigen::VectorXd::Constant(1, 1e200), Eigen::MatrixXd::Identity(1, 1), CovarianceType::kFull)});
  expectOneLineError([&] { saveModel(path, huge); }, path.string(), "states[1].components[0].mean[0] is 1e+200");

  HmmModel mixed = test::stickyModel1d(2, 0.8);
  mixed.states[1] =
      GaussianMixture(Eigen::VectorXd::Ones(1),
                      {Gaussian(Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Identity(1, 1), CovarianceType::kDiagonal)});
  expectOneLineError([&] { saveModel(path, mixed); }, path.string(),
                     "states[1].components[0] differs in covariance type");

  HmmModel latin1 = test::stickyModel1d(2, 0.8);
  latin1.columnNames = {"f0_\xe9"};
  expectOneLineError([&] { saveModel(path, latin1); }, path.string(),
                     "cannot be written: a column or block name is not UTF-8 text");

  const HmmModel good = test::stickyModel1d(2, 0.8);
  expectOneLineError([&] { saveModel(path, good, "iterations: 3"); }, path.string(),
                     "the training metadata is not valid JSON");
  expectOneLineError([&] { saveModel(path, good, "[1, 2]"); }, path.string(),
                     "the training metadata is an array, not a JSON object");

  EXPECT_TRUE(listFolder(folder.path()).empty());
}

TEST(ModelFile, SaveWhereNoFileCanBeLeavesNothing) {
  TemporaryFolder folder;
  const HmmModel model = test::stickyModel1d(2, 0.8);
  const fs::path inMissingFolder = folder.path() / "no" / "model.json";
  expectOneLineError([&] { saveModel(inMissingFolder, model); }, inMissingFolder.string(), "does not exist");
  writeText(folder.path() / "file", "x");
  const fs::path underAFile = folder.path() / "file" / "model.json";
  expectOneLineError([&] { saveModel(underAFile, model); }, underAFile.string(), "does not exist");
  expectOneLineError([&] { saveModel(folder.path(), model); }, folder.path().string(), "is a directory");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"file"});
}

// Limits the size of files this process may write (as a full disk would), and restores it.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    previousHandler_ = std::signal(SIGXFSZ, SIG_IGN);  // a failed write, not a killed process
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previousHandler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*previousHandler_)(int) = nullptr;
};

TEST(ModelFile, AWriteThatFailsHalfwayLeavesThePreviousFileAndNoTemporary) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "model.json";
  const HmmModel small = test::stickyModel1d(2, 0.8);
  saveModel(path, small, R"({"run": "first"})");
  const std::string before = readText(path);
  ASSERT_LT(before.size(), 4096u);

  const HmmModel large = test::randomModel(6, 3, 20, CovarianceType::kFull, 3);
  ASSERT_GT(formatModel(large).size(), 4u * 4096u);
  {
    FileSizeLimit limit(4096);
    expectOneLineError([&] { saveModel(path, large, R"({"run": "second"})"); }, path.string(), "write failed");
  }
  EXPECT_EQ(readText(path), before);
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"model.json"});

  // And with no previous file: nothing at all.
  const fs::path fresh = folder.path() / "fresh.json";
  {
    FileSizeLimit limit(4096);
    expectOneLineError([&] { saveModel(fresh, large); }, fresh.string(), "write failed");
  }
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"model.json"});
}

TEST(ModelFile, SaveReplacesAnExistingFile) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "model.json";
  saveModel(path, test::stickyModel1d(2, 0.8), R"({"run": 1})");
  const HmmModel second = namedModel(3, 2, 2, CovarianceType::kDiagonal, 9);
  saveModel(path, second, R"({"run": 2})");
  std::string training;
  expectIdentical(second, loadModel(path, &training));
  EXPECT_EQ(training, R"({"run":2})");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"model.json"});
}

}  // namespace
}  // namespace th::hmm
