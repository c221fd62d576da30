// An independent cross-check of the HMM engine on real speech features: models trained by trainHmm, saved with
// saveModel, are scored by tools/hmm_reference.py (textbook formulas in numpy, log-domain forward algorithm,
// numpy.linalg.slogdet/solve) and the total log-likelihoods must agree to 1e-6 relative; one Baum-Welch iteration
// must re-estimate the same parameters; and for one state, our log-likelihood of the parameters scikit-learn's
// GaussianMixture fitted (read back with loadModel) must equal sklearn's own score_samples sum.
//
//   ctest --test-dir build -L crosscheck --output-on-failure
//
// Data: F0/energy/deltas (d = 4) and MFCC c1..c11 (d = 11) of the three BEAT2 recordings in the shared data
// folder (about 5 800 frames at 30 fps), each recording cut in two, so six sequences.
// Needs /usr/bin/python3 with python3-numpy and python3-sklearn (scripts/packages.txt): missing, the tests fail.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/temporary_file.h"
#include "features/online_features.h"
#include "hmm/forward_backward.h"
#include "hmm/model_file.h"
#include "hmm/training.h"

namespace th::hmm {
namespace {

constexpr const char* kPython = "/usr/bin/python3";
constexpr double kRelativeTolerance = 1e-6;

std::string referenceScript() {
  return std::string(TALKINGHEAD_SOURCE_DIR) + "/tools/hmm_reference.py";
}

std::string shellQuote(const std::string& argument) {
  std::string quoted = "'";
  for (char c : argument) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

struct ProcessResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

// Runs the reference with one BLAS thread, so a loaded machine gives the same numbers as an idle one.
ProcessResult runReference(const std::vector<std::string>& arguments) {
  std::string command = "OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 " + shellQuote(kPython);
  for (const auto& argument : arguments) command += " " + shellQuote(argument);
  command += " </dev/null 2>&1";
  ProcessResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer{};
  size_t got = 0;
  while ((got = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), got);
  const int status = ::pclose(pipe);
  result.exitCode = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// The last line the reference printed, as a number (it prints the score with repr(): round-trip precision).
double lastNumber(const ProcessResult& result) {
  std::istringstream lines(result.output);
  std::string line;
  std::string last;
  while (std::getline(lines, line)) {
    if (!line.empty()) last = line;
  }
  size_t used = 0;
  const double value = std::stod(last, &used);
  if (used != last.size()) throw std::runtime_error("not a number: " + last);
  return value;
}

double relativeDifference(double ours, double reference) {
  return std::abs(ours - reference) / std::max(std::abs(reference), 1e-300);
}

// Observation sets drawn from the feature rows (FeatureLayout).
struct FeatureSet {
  const char* name;
  int begin;  // first column in the feature row
  int size;
};
constexpr FeatureSet kProsody{"prosody", features::FeatureLayout::kF0Hz, 4};  // f0_hz, energy, d_f0, d_energy
constexpr FeatureSet kMfcc{"mfcc", features::FeatureLayout::kMfccBegin, 11};  // mfcc1 .. mfcc11

struct FeatureData {
  std::vector<std::string> columns;
  std::vector<Eigen::MatrixXd> sequences;  // each d x T
  int numFrames() const {
    int total = 0;
    for (const auto& s : sequences) total += static_cast<int>(s.cols());
    return total;
  }
};

// Feature rows of the three BEAT2 recordings (computed once per test binary).
const std::vector<features::FeatureMatrix>& recordings() {
  static const std::vector<features::FeatureMatrix> all = [] {
    std::vector<features::FeatureMatrix> matrices;
    for (const char* file :
         {"beat2/2_scott_0_1_1.wav", "beat2/audio_only/2_scott_0_2_2.wav", "beat2/audio_only/2_scott_0_4_4.wav"}) {
      const audio::AudioClip clip = audio::readAudioFile(sharedDataPath(file));
      matrices.push_back(features::computeFeatures(clip.samples));
    }
    return matrices;
  }();
  return all;
}

FeatureData featureData(const FeatureSet& set) {
  FeatureData data;
  const auto& matrices = recordings();
  const std::vector<std::string> names = matrices.front().layout.columnNames();
  data.columns.assign(names.begin() + set.begin, names.begin() + set.begin + set.size);
  for (const auto& matrix : matrices) {
    const int half = matrix.numFrames() / 2;
    for (const auto& [first, count] : {std::pair{0, half}, std::pair{half, matrix.numFrames() - half}}) {
      Eigen::MatrixXd frames(set.size, count);
      for (int t = 0; t < count; ++t) {
        const auto row = matrix.row(first + t);
        for (int k = 0; k < set.size; ++k) frames(k, t) = row[static_cast<size_t>(set.begin + k)];
      }
      data.sequences.push_back(std::move(frames));
    }
  }
  return data;
}

// Header "seq,<columns>", one frame per row, every value with 17 significant digits (exact for doubles).
void writeCsv(const std::filesystem::path& path, const FeatureData& data) {
  std::ofstream out(path);
  out << "seq";
  for (const auto& name : data.columns) out << ',' << name;
  out << '\n';
  char number[32];
  for (size_t s = 0; s < data.sequences.size(); ++s) {
    const Eigen::MatrixXd& frames = data.sequences[s];
    for (Eigen::Index t = 0; t < frames.cols(); ++t) {
      out << s;
      for (Eigen::Index k = 0; k < frames.rows(); ++k) {
        std::snprintf(number, sizeof number, "%.17g", frames(k, t));
        out << ',' << number;
      }
      out << '\n';
    }
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

double ourLogLikelihood(const HmmModel& model, const FeatureData& data) {
  double total = 0.0;
  for (const auto& frames : data.sequences) total += logLikelihood(model, model.emissionLogLikelihoods(frames));
  return total;
}

TEST(ReferenceCheck, PythonNumpyAndSklearnAreInstalled) {
  const ProcessResult result =
      runReference({"-c", "import numpy, sklearn; print(numpy.__version__, sklearn.__version__)"});
  ASSERT_EQ(result.exitCode, 0) << kPython << " with numpy and sklearn is needed for the cross-check "
                                << "(apt-get install python3-numpy python3-sklearn; scripts/packages.txt):\n"
                                << result.output;
  ASSERT_TRUE(std::filesystem::exists(referenceScript())) << referenceScript();
  std::cout << "numpy, sklearn: " << result.output;
}

struct TrainedCase {
  const FeatureSet* features;
  CovarianceType covariance;
  int numStates;
  int numMixtures;
};

std::string caseName(const testing::TestParamInfo<TrainedCase>& info) {
  const TrainedCase& c = info.param;
  return std::string(c.features->name) + (c.covariance == CovarianceType::kFull ? "_full" : "_diag") + "_N" +
         std::to_string(c.numStates) + "_M" + std::to_string(c.numMixtures);
}

void PrintTo(const TrainedCase& c, std::ostream* out) {
  *out << caseName({c, 0});
}

class TrainedModelCheck : public testing::TestWithParam<TrainedCase> {
 protected:
  static TrainingOptions options(const TrainedCase& c) {
    TrainingOptions o;
    o.numStates = c.numStates;
    o.numMixtures = c.numMixtures;
    o.covariance = c.covariance;
    o.maxIterations = 8;  // a model from the middle of training is as good a test as a converged one
    o.seed = 3;
    return o;
  }
};

// Our forward algorithm (scaled) and the reference's (log domain) on a model our training produced.
TEST_P(TrainedModelCheck, LogLikelihoodAgreesWithTheNumpyReference) {
  const TrainedCase& c = GetParam();
  const FeatureData data = featureData(*c.features);
  TrainingResult trained = trainHmm(data.sequences, options(c));
  trained.model.columnNames = data.columns;
  const TemporaryFile csv(".csv");
  const TemporaryFile modelFile(".json");
  writeCsv(csv.path(), data);
  saveModel(modelFile.path(), trained.model);

  const double ours = ourLogLikelihood(trained.model, data);
  const ProcessResult result =
      runReference({referenceScript(), "loglik", modelFile.path().string(), csv.path().string(), "--seq"});
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const double reference = lastNumber(result);
  std::printf("%-24s frames %d  ours %.10f  numpy %.10f  relative difference %.2e\n", caseName({c, 0}).c_str(),
              data.numFrames(), ours, reference, relativeDifference(ours, reference));
  EXPECT_LE(relativeDifference(ours, reference), kRelativeTolerance) << "ours " << ours << ", numpy " << reference;
  // The training history's last entry is the log-likelihood of the model returned, by the same forward pass.
  EXPECT_NEAR(trained.history.back().logLikelihood, ours, 1e-9 * std::abs(ours));
}

INSTANTIATE_TEST_SUITE_P(RealFeatures, TrainedModelCheck,
                         testing::Values(TrainedCase{&kProsody, CovarianceType::kFull, 3, 1},
                                         TrainedCase{&kProsody, CovarianceType::kFull, 5, 2},
                                         TrainedCase{&kProsody, CovarianceType::kDiagonal, 8, 2},
                                         TrainedCase{&kMfcc, CovarianceType::kFull, 4, 2},
                                         TrainedCase{&kMfcc, CovarianceType::kFull, 8, 1},
                                         TrainedCase{&kMfcc, CovarianceType::kDiagonal, 6, 2},
                                         TrainedCase{&kMfcc, CovarianceType::kDiagonal, 3, 1}),
                         caseName);

// Largest |a - b| over all parameters, relative to the largest |b| of the same kind.
double worstRelative(const Eigen::MatrixXd& ours, const Eigen::MatrixXd& reference) {
  return (ours - reference).cwiseAbs().maxCoeff() / std::max(reference.cwiseAbs().maxCoeff(), 1e-300);
}

// One Baum-Welch (EM) iteration from the same model: the E-step statistics and the M-step formulas of the two
// implementations must give the same parameters. MFCCs only: the F0 columns hold exact zeros in unvoiced frames,
// where a state's variance is set by the floor, which the textbook reference does not have.
TEST(ReferenceCheck, OneBaumWelchIterationGivesTheSameParameters) {
  const FeatureData data = featureData(kMfcc);
  const TemporaryFile csv(".csv");
  writeCsv(csv.path(), data);
  for (const CovarianceType covariance : {CovarianceType::kFull, CovarianceType::kDiagonal}) {
    SCOPED_TRACE(covariance == CovarianceType::kFull ? "full" : "diagonal");
    TrainingOptions options;
    options.numStates = 5;
    options.numMixtures = 2;
    options.covariance = covariance;
    options.maxIterations = 3;
    HmmModel start = trainHmm(data.sequences, options).model;
    start.columnNames = data.columns;
    const TemporaryFile before(".json");
    const TemporaryFile after(".json");
    saveModel(before.path(), start);

    HmmModel ours = start;
    // A floor far below any variance here, so that it never acts (the reference has none).
    const Eigen::VectorXd floor = Eigen::VectorXd::Constant(ours.dimension(), 1e-12);
    const IterationRecord record = baumWelchIteration(ours, data.sequences, floor, {});
    const ProcessResult result = runReference(
        {referenceScript(), "bw-iteration", before.path().string(), csv.path().string(), "-o", after.path().string()});
    ASSERT_EQ(result.exitCode, 0) << result.output;
    const HmmModel reference = loadModel(after.path());
    ASSERT_EQ(reference.numStates(), ours.numStates());

    double worstInitial = worstRelative(ours.initial, reference.initial);
    double worstTransition = worstRelative(ours.transition, reference.transition);
    double worstWeight = 0.0;
    double worstMean = 0.0;
    double worstCovariance = 0.0;
    for (int j = 0; j < ours.numStates(); ++j) {
      const GaussianMixture& a = ours.states[static_cast<size_t>(j)];
      const GaussianMixture& b = reference.states[static_cast<size_t>(j)];
      ASSERT_EQ(a.numComponents(), b.numComponents());
      worstWeight = std::max(worstWeight, worstRelative(a.weights(), b.weights()));
      for (int m = 0; m < a.numComponents(); ++m) {
        const Gaussian& ga = a.components()[static_cast<size_t>(m)];
        const Gaussian& gb = b.components()[static_cast<size_t>(m)];
        worstMean = std::max(worstMean, worstRelative(ga.mean(), gb.mean()));
        worstCovariance = std::max(worstCovariance, worstRelative(ga.covariance(), gb.covariance()));
      }
    }
    std::printf(
        "one EM iteration (%s): worst relative difference pi %.1e, A %.1e, weights %.1e, means %.1e, "
        "covariances %.1e; log P(X) before: ours %.10f\n",
        covariance == CovarianceType::kFull ? "full" : "diagonal", worstInitial, worstTransition, worstWeight,
        worstMean, worstCovariance, record.logLikelihood);
    EXPECT_LE(worstInitial, kRelativeTolerance);
    EXPECT_LE(worstTransition, kRelativeTolerance);
    EXPECT_LE(worstWeight, kRelativeTolerance);
    EXPECT_LE(worstMean, kRelativeTolerance);
    EXPECT_LE(worstCovariance, kRelativeTolerance);
    // And the reference's log-likelihood of the starting model (printed by bw-iteration) matches ours.
    const auto at = result.output.find("log P(X) = ");
    ASSERT_NE(at, std::string::npos) << result.output;
    const double referenceLogLikelihood = std::stod(result.output.substr(at + std::string("log P(X) = ").size()));
    EXPECT_LE(relativeDifference(record.logLikelihood, referenceLogLikelihood), kRelativeTolerance);
  }
}

struct SklearnCase {
  const FeatureSet* features;
  const char* covariance;  // sklearn's name: full | diag
  int numComponents;
};

std::string sklearnCaseName(const testing::TestParamInfo<SklearnCase>& info) {
  return std::string(info.param.features->name) + "_" + info.param.covariance + "_M" +
         std::to_string(info.param.numComponents);
}

void PrintTo(const SklearnCase& c, std::ostream* out) {
  *out << sklearnCaseName({c, 0});
}

class SklearnCheck : public testing::TestWithParam<SklearnCase> {};

// A single-state HMM is a Gaussian mixture: our likelihood of sklearn's fitted parameters = sklearn's score.
TEST_P(SklearnCheck, OurLogLikelihoodOfItsFitEqualsItsScore) {
  const SklearnCase& c = GetParam();
  const FeatureData data = featureData(*c.features);
  const TemporaryFile csv(".csv");
  const TemporaryFile modelFile(".json");
  writeCsv(csv.path(), data);
  const ProcessResult result =
      runReference({referenceScript(), "gmm-sklearn", csv.path().string(), "--components",
                    std::to_string(c.numComponents), "--covariance", c.covariance, "-o", modelFile.path().string()});
  ASSERT_EQ(result.exitCode, 0) << result.output;
  const double sklearnScore = lastNumber(result);

  const HmmModel model = loadModel(modelFile.path());
  ASSERT_EQ(model.numStates(), 1);
  ASSERT_EQ(model.states.front().numComponents(), c.numComponents);
  EXPECT_EQ(model.covarianceType(),
            std::string(c.covariance) == "full" ? CovarianceType::kFull : CovarianceType::kDiagonal);
  EXPECT_EQ(model.columnNames, data.columns);
  const double ours = ourLogLikelihood(model, data);
  std::printf("sklearn GaussianMixture %-16s frames %d  ours %.10f  sklearn %.10f  relative difference %.2e\n",
              sklearnCaseName({c, 0}).c_str(), data.numFrames(), ours, sklearnScore,
              relativeDifference(ours, sklearnScore));
  EXPECT_LE(relativeDifference(ours, sklearnScore), kRelativeTolerance)
      << "ours " << ours << ", sklearn " << sklearnScore;
}

INSTANTIATE_TEST_SUITE_P(RealFeatures, SklearnCheck,
                         testing::Values(SklearnCase{&kProsody, "full", 1}, SklearnCase{&kProsody, "full", 3},
                                         SklearnCase{&kProsody, "diag", 2}, SklearnCase{&kMfcc, "full", 1},
                                         SklearnCase{&kMfcc, "full", 2}, SklearnCase{&kMfcc, "diag", 4}),
                         sklearnCaseName);

}  // namespace
}  // namespace th::hmm
