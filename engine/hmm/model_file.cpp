#include "hmm/model_file.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <system_error>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_reading.h"
#include "core/text_files.h"

namespace th::hmm {
namespace {

constexpr std::string_view kFormatName = "talkinghead-hmm";
// Size guards, checked on the JSON arrays before anything is allocated for them. Far beyond any model this
// program trains (the papers use N ≤ 20, M ≤ 19, d ≈ 123): a file past them is a mistake (data saved where a
// model was expected, a forged header), and refusing it early keeps the message clear.
constexpr std::size_t kMaxStates = 10000;
constexpr std::size_t kMaxComponents = 1000;
constexpr std::size_t kMaxDimension = 10000;
// The model itself nests 7 deep; "training" may nest a little more. Deeper input is refused while parsing, so
// nothing later (nlohmann's dump() recurses) can run out of stack on a forged file.
constexpr int kMaxNestingDepth = 64;
// Means and covariance entries within ±1e150 and variances (or squared Cholesky pivots) of at least 1e-150: then
// squared distances and inverse variances stay finite in the density code, instead of turning into inf/NaN
// log-likelihoods far from the file that caused them.
constexpr double kMaxMagnitude = 1e150;
constexpr double kMinVariance = 1e-150;
constexpr double kSumTolerance = 1e-6;       // the same as HmmModel::check() and GaussianMixture
constexpr double kSymmetryTolerance = 1e-9;  // relative to the entries' scale (see checkSymmetric)

std::string formatNumber(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.10g", value);
  return buffer.data();
}

// Reads the validated parts of a model document. Every check names the field at fault ("states[3].weights");
// field paths are built only when something fails, since a model holds up to millions of numbers.
class ModelReader : public JsonFields {
 public:
  explicit ModelReader(const std::string& name) : JsonFields(name), name_(name) {}

  // An array of exactly `expected` finite numbers (`why` says where the length comes from).
  Eigen::VectorXd numbers(const Json& value, const std::string& field, std::size_t expected,
                          const std::string& why) const {
    array(value, field);
    if (value.size() != expected) {
      fail(field,
           "has " + std::to_string(value.size()) + " values; expected " + std::to_string(expected) + " (" + why + ")");
    }
    Eigen::VectorXd out(static_cast<Eigen::Index>(expected));
    for (std::size_t i = 0; i < expected; ++i) {
      const Json& item = value[i];
      if (!item.is_number()) fail(indexed(field, i), "is " + kindOf(item) + ", not a number");
      const double x = item.get<double>();
      // nlohmann refuses 1e999 while parsing, but a uint64 or a float must still come out finite here.
      if (!std::isfinite(x)) fail(indexed(field, i), "is not a finite number");
      out[static_cast<Eigen::Index>(i)] = x;
    }
    return out;
  }

  void bounded(const Eigen::VectorXd& values, const std::string& field) const {
    for (Eigen::Index i = 0; i < values.size(); ++i) {
      if (std::abs(values[i]) > kMaxMagnitude) {
        fail(indexed(field, static_cast<std::size_t>(i)),
             "is " + formatNumber(values[i]) + "; magnitudes above 1e150 are not supported");
      }
    }
  }

  // Non-negative and summing to 1 (π, a row of A, mixture weights).
  void probabilities(const Eigen::VectorXd& values, const std::string& field) const {
    for (Eigen::Index i = 0; i < values.size(); ++i) {
      if (values[i] < 0.0)
        fail(indexed(field, static_cast<std::size_t>(i)), "is negative (" + formatNumber(values[i]) + ")");
    }
    const double sum = values.sum();
    if (!(std::abs(sum - 1.0) <= kSumTolerance)) {
      fail(field, "sums to " + formatNumber(sum) + ", not 1 (the tolerance is 1e-6)");
    }
  }

  // Symmetric to kSymmetryTolerance relative to max(|aᵢₖ|, |aₖᵢ|, √(aᵢᵢ aₖₖ)): the diagonal sets the scale, so an
  // off-diagonal 1e-20 against 0 is not an asymmetry. (Gaussian then averages Σ and Σᵀ.)
  void checkSymmetric(const Eigen::MatrixXd& covariance, const std::string& field) const {
    for (Eigen::Index i = 0; i < covariance.rows(); ++i) {
      for (Eigen::Index k = 0; k < i; ++k) {
        const double a = covariance(i, k);
        const double b = covariance(k, i);
        const double scale =
            std::max({std::abs(a), std::abs(b), std::sqrt(std::abs(covariance(i, i) * covariance(k, k)))});
        if (std::abs(a - b) > kSymmetryTolerance * scale) {
          fail(field, "is not symmetric ([" + std::to_string(k) + "][" + std::to_string(i) + "] is " + formatNumber(b) +
                          " but [" + std::to_string(i) + "][" + std::to_string(k) + "] is " + formatNumber(a) + ")");
        }
      }
    }
  }

  // On ½(Σ + Σᵀ), the matrix Gaussian factors and stores: a model read back from its own file then passes the
  // same test on the same numbers. (Entries are bounded by kMaxMagnitude, so the sum cannot overflow.)
  void checkPositiveDefinite(const Eigen::MatrixXd& covariance, const std::string& field) const {
    const Eigen::LLT<Eigen::MatrixXd> cholesky(0.5 * (covariance + covariance.transpose()));
    // LLT only fails on a pivot ≤ 0; a NaN pivot (overflow inside the factorisation) passes it, so look at L too.
    const Eigen::MatrixXd lower = cholesky.matrixL();
    if (cholesky.info() != Eigen::Success || !lower.allFinite() || !(lower.diagonal().minCoeff() > 0.0)) {
      fail(field, "is not positive definite");
    }
    const double smallestPivot = lower.diagonal().minCoeff();
    if (smallestPivot * smallestPivot < kMinVariance) {
      fail(field, "is nearly singular (a Cholesky pivot of " + formatNumber(smallestPivot) +
                      "; its square must be at least 1e-150)");
    }
  }

  HmmModel read(const Json& document, std::string* trainingJson) {
    checkFormatAndVersion(document);

    const std::string& covarianceName = string(member(document, "covariance", ""), "covariance");
    if (covarianceName != "full" && covarianceName != "diagonal") {
      fail("covariance", "is \"" + printable(covarianceName) + "\"; expected \"full\" or \"diagonal\"");
    }
    const CovarianceType type = covarianceName == "full" ? CovarianceType::kFull : CovarianceType::kDiagonal;

    const Json& states = array(member(document, "states", ""), "states");
    if (states.empty()) fail("states", "is empty (a model needs at least one state)");
    if (states.size() > kMaxStates) {
      fail("states", "has " + std::to_string(states.size()) + " states; at most " + std::to_string(kMaxStates) +
                         " are supported");
    }
    const std::size_t numStates = states.size();

    HmmModel model;
    model.initial = numbers(member(document, "initial", ""), "initial", numStates, "one per state");
    probabilities(model.initial, "initial");

    const Json& transition = array(member(document, "transition", ""), "transition");
    if (transition.size() != numStates) {
      fail("transition", "has " + std::to_string(transition.size()) + " rows; expected " + std::to_string(numStates) +
                             " (one per state)");
    }
    const auto n = static_cast<Eigen::Index>(numStates);
    model.transition.resize(n, n);
    for (std::size_t i = 0; i < numStates; ++i) {
      const std::string rowField = indexed("transition", i);
      const Eigen::VectorXd row = numbers(transition[i], rowField, numStates, "one per state");
      probabilities(row, rowField);
      model.transition.row(static_cast<Eigen::Index>(i)) = row.transpose();
    }

    std::size_t dimension = 0;  // from states[0].components[0].mean
    for (std::size_t j = 0; j < numStates; ++j) model.states.push_back(readState(states[j], j, type, dimension));

    const Json& columns = array(member(document, "columns", ""), "columns");
    if (!columns.empty() && columns.size() != dimension) {
      fail("columns", "has " + std::to_string(columns.size()) + " names; expected " + std::to_string(dimension) +
                          " (one per dimension) or none");
    }
    for (std::size_t i = 0; i < columns.size(); ++i)
      model.columnNames.push_back(string(columns[i], indexed("columns", i)));

    model.blocks = readBlocks(array(member(document, "blocks", ""), "blocks"), dimension);

    const auto training = document.find("training");
    if (training != document.end()) object(*training, "training");
    if (trainingJson) *trainingJson = training != document.end() ? training->dump() : "{}";

    // Everything check() looks at was checked above with the field named; this is the model's own invariant.
    try {
      model.check();
    } catch (const Error& e) {
      throw fileError(name_, e.what());
    }
    return model;
  }

 private:
  // What the file says it is: a talkinghead HMM, of the version this reader reads, with no field it does not know.
  void checkFormatAndVersion(const Json& document) const {
    if (!document.is_object()) {
      throw fileError(name_, "not a talkinghead HMM model (the top level is " + kindOf(document) + ", not an object)");
    }
    if (!document.contains("format")) {
      throw fileError(name_, "not a talkinghead HMM model (it has no \"format\" field)");
    }
    const Json& format = member(document, "format", "");
    if (!format.is_string() || format.get_ref<const std::string&>() != kFormatName) {
      fail("format", "is " + describe(format) + ", not \"talkinghead-hmm\": not a talkinghead HMM model");
    }
    // The version before anything else: a newer file may well have fields this reader does not know.
    const std::int64_t version = integer(member(document, "version", ""), "version");
    const std::string thisVersion = std::to_string(kModelFileVersion);
    if (version > kModelFileVersion) {
      fail("version", "is " + std::to_string(version) +
                          ": the file was written by a newer talkinghead (this one reads version " + thisVersion + ")");
    }
    if (version < kModelFileVersion) {
      fail("version", "is " + std::to_string(version) +
                          ", which is not a version of this format (this talkinghead reads version " + thisVersion +
                          ")");
    }
    onlyKnownFields(
        document,
        {"format", "version", "covariance", "columns", "blocks", "initial", "transition", "states", "training"}, "",
        "a version-1 model file");
  }

  GaussianMixture readState(const Json& state, std::size_t j, CovarianceType type, std::size_t& dimension) const {
    const std::string field = indexed("states", j);
    object(state, field);
    onlyKnownFields(state, {"weights", "components"}, field, "a state");
    const Json& weightsJson = array(member(state, "weights", field), field + ".weights");
    const Json& components = array(member(state, "components", field), field + ".components");
    if (weightsJson.empty()) fail(field + ".weights", "is empty (a state needs at least one component)");
    if (weightsJson.size() > kMaxComponents) {
      fail(field + ".weights", "has " + std::to_string(weightsJson.size()) + " values; at most " +
                                   std::to_string(kMaxComponents) + " components per state are supported");
    }
    if (components.size() != weightsJson.size()) {
      fail(field + ".components", "has " + std::to_string(components.size()) + " components but " + field +
                                      ".weights has " + std::to_string(weightsJson.size()) + " weights");
    }
    Eigen::VectorXd weights = numbers(weightsJson, field + ".weights", weightsJson.size(), "one per component");
    probabilities(weights, field + ".weights");

    std::vector<Gaussian> gaussians;
    for (std::size_t m = 0; m < components.size(); ++m) {
      gaussians.push_back(readComponent(components[m], indexed(field + ".components", m), type, dimension));
    }
    try {
      return GaussianMixture(std::move(weights), std::move(gaussians));
    } catch (const Error& e) {
      fail(field, std::string("is not a valid mixture (") + e.what() + ")");
    }
  }

  Gaussian readComponent(const Json& component, const std::string& field, CovarianceType type,
                         std::size_t& dimension) const {
    const bool full = type == CovarianceType::kFull;
    object(component, field);
    onlyKnownFields(component, {"mean", full ? "covariance" : "variances"}, field,
                    full ? "a full-covariance component" : "a diagonal-covariance component");
    const Json& meanJson = array(member(component, "mean", field), field + ".mean");
    if (dimension == 0) {  // the first component sets the dimension for the whole model
      if (meanJson.empty()) fail(field + ".mean", "is empty (observations need at least one dimension)");
      if (meanJson.size() > kMaxDimension) {
        fail(field + ".mean", "has " + std::to_string(meanJson.size()) + " values; at most " +
                                  std::to_string(kMaxDimension) + " dimensions are supported");
      }
      dimension = meanJson.size();
    }
    const std::string why = "the dimension, set by states[0].components[0].mean";
    Eigen::VectorXd mean = numbers(meanJson, field + ".mean", dimension, why);
    bounded(mean, field + ".mean");

    const auto d = static_cast<Eigen::Index>(dimension);
    Eigen::MatrixXd covariance(d, d);
    if (full) {
      const std::string covarianceField = field + ".covariance";
      const Json& rows = array(member(component, "covariance", field), covarianceField);
      if (rows.size() != dimension) {
        fail(covarianceField,
             "has " + std::to_string(rows.size()) + " rows; expected " + std::to_string(dimension) + " (" + why + ")");
      }
      for (std::size_t i = 0; i < dimension; ++i) {
        const std::string rowField = indexed(covarianceField, i);
        const Eigen::VectorXd row = numbers(rows[i], rowField, dimension, why);
        bounded(row, rowField);
        covariance.row(static_cast<Eigen::Index>(i)) = row.transpose();
      }
      checkSymmetric(covariance, covarianceField);
      checkPositiveDefinite(covariance, covarianceField);
    } else {
      const std::string variancesField = field + ".variances";
      const Eigen::VectorXd variances = numbers(member(component, "variances", field), variancesField, dimension, why);
      bounded(variances, variancesField);
      for (Eigen::Index i = 0; i < d; ++i) {
        const std::string itemField = indexed(variancesField, static_cast<std::size_t>(i));
        if (!(variances[i] > 0.0)) fail(itemField, "is not positive (" + formatNumber(variances[i]) + ")");
        if (variances[i] < kMinVariance) {
          fail(itemField, "is " + formatNumber(variances[i]) + "; variances below 1e-150 are not supported");
        }
      }
      covariance = variances.asDiagonal();
    }
    try {
      return Gaussian(std::move(mean), covariance, type);
    } catch (const Error& e) {
      fail(field, std::string("is not a valid Gaussian (") + e.what() + ")");
    }
  }

  std::vector<ObservationBlock> readBlocks(const Json& blocksJson, std::size_t dimension) const {
    std::vector<ObservationBlock> blocks;
    std::set<std::string> names;
    const auto d = static_cast<std::int64_t>(dimension);
    std::int64_t next = 0;
    for (std::size_t b = 0; b < blocksJson.size(); ++b) {
      const std::string field = indexed("blocks", b);
      const Json& block = object(blocksJson[b], field);
      onlyKnownFields(block, {"name", "begin", "size"}, field, "a block");
      const std::string& name = string(member(block, "name", field), field + ".name");
      if (name.empty()) fail(field + ".name", "is empty");
      if (!names.insert(name).second) fail(field + ".name", "\"" + printable(name) + "\" is used by an earlier block");
      const std::int64_t begin = integer(member(block, "begin", field), field + ".begin");
      const std::int64_t size = integer(member(block, "size", field), field + ".size");
      if (begin != next) {
        fail(field + ".begin", "is " + std::to_string(begin) + "; expected " + std::to_string(next) +
                                   " (blocks tile the dimensions in order, each starting where the previous one ends)");
      }
      if (size <= 0) fail(field + ".size", "is " + std::to_string(size) + "; a block has at least one dimension");
      if (size > d - begin) {
        fail(field + ".size", "is " + std::to_string(size) +
                                  ": the block would end past the last dimension (there are " + std::to_string(d) +
                                  ")");
      }
      blocks.push_back({name, static_cast<int>(begin), static_cast<int>(size)});
      next = begin + size;
    }
    if (!blocks.empty() && next != d) {
      fail("blocks", "cover dimensions 0 to " + std::to_string(next - 1) + " of " + std::to_string(d) +
                         "; together they must cover every dimension");
    }
    return blocks;
  }

  const std::string& name_;
};

Json vectorJson(const Eigen::VectorXd& values) {
  Json out = Json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) out.push_back(values[i]);
  return out;
}

// The document, laid out for people: one line per top-level field, per transition row and per component
// (a whole covariance on one line: a file of one number per line would be tens of thousands of lines).
std::string layOut(const HmmModel& model, CovarianceType type, const Json* training) {
  std::string text = "{\n";
  text += "  \"format\": " + Json(std::string(kFormatName)).dump() + ",\n";
  text += "  \"version\": " + std::to_string(kModelFileVersion) + ",\n";
  text += std::string("  \"covariance\": ") + (type == CovarianceType::kFull ? "\"full\"" : "\"diagonal\"") + ",\n";
  text += "  \"columns\": " + Json(model.columnNames).dump() + ",\n";
  Json blocks = Json::array();
  for (const auto& block : model.blocks)
    blocks.push_back({{"name", block.name}, {"begin", block.begin}, {"size", block.size}});
  text += "  \"blocks\": " + blocks.dump() + ",\n";
  text += "  \"initial\": " + vectorJson(model.initial).dump() + ",\n";
  text += "  \"transition\": [\n";
  for (Eigen::Index i = 0; i < model.transition.rows(); ++i) {
    text += "    " + vectorJson(model.transition.row(i).transpose()).dump() +
            (i + 1 < model.transition.rows() ? ",\n" : "\n");
  }
  text += "  ],\n";
  text += "  \"states\": [\n";
  for (std::size_t j = 0; j < model.states.size(); ++j) {
    const GaussianMixture& state = model.states[j];
    text += "    {\"weights\": " + vectorJson(state.weights()).dump() + ", \"components\": [\n";
    for (std::size_t m = 0; m < state.components().size(); ++m) {
      const Gaussian& gaussian = state.components()[m];
      Json component;
      component["mean"] = vectorJson(gaussian.mean());
      if (type == CovarianceType::kFull) {
        Json rows = Json::array();
        for (Eigen::Index i = 0; i < gaussian.covariance().rows(); ++i) {
          rows.push_back(vectorJson(gaussian.covariance().row(i).transpose()));
        }
        component["covariance"] = std::move(rows);
      } else {
        component["variances"] = vectorJson(gaussian.covariance().diagonal());
      }
      text += "      " + component.dump() + (m + 1 < state.components().size() ? ",\n" : "\n");
    }
    text += std::string("    ]}") + (j + 1 < model.states.size() ? ",\n" : "\n");
  }
  text += "  ]";
  if (training) text += ",\n  \"training\": " + training->dump();
  text += "\n}\n";
  return text;
}

}  // namespace

std::string formatModel(const HmmModel& model, std::string_view trainingJson, const std::string& nameForErrors) {
  try {
    model.check();
  } catch (const Error& e) {
    throw fileError(nameForErrors, std::string("cannot be written: ") + e.what());
  }
  const CovarianceType type = model.covarianceType();
  for (std::size_t j = 0; j < model.states.size(); ++j) {
    for (std::size_t m = 0; m < model.states[j].components().size(); ++m) {
      if (model.states[j].components()[m].type() != type) {
        throw fileError(nameForErrors, "cannot be written: states[" + std::to_string(j) + "].components[" +
                                           std::to_string(m) +
                                           "] differs in covariance type from states[0].components[0]");
      }
    }
  }
  Json training;
  if (!trainingJson.empty()) {
    training =
        parseJson(trainingJson, nameForErrors,
                  {.maxDepth = kMaxNestingDepth, .depthNote = "a model needs 7", .subject = "the training metadata"});
    if (!training.is_object())
      throw fileError(nameForErrors,
                      "the training metadata is " + JsonFields::kindOf(training) + ", not a JSON object");
  }
  std::string text;
  try {
    text = layOut(model, type, trainingJson.empty() ? nullptr : &training);
  } catch (const Json::exception& e) {  // dump() refuses strings that are not UTF-8 (a Latin-1 column name)
    throw fileError(nameForErrors,
                    "cannot be written: a column or block name is not UTF-8 text (" + jsonReason(e.what()) + ")");
  }
  // Read it back with the loader's checks, so that no file is written that loadModel would refuse (a magnitude
  // beyond its limits, a name that does not survive): the error comes now, naming the field, not at load time.
  static_cast<void>(parseModel(text, nameForErrors));
  return text;
}

void saveModel(const std::filesystem::path& path, const HmmModel& model, std::string_view trainingJson) {
  const std::string text = formatModel(model, trainingJson, path.string());
  AtomicFile out(path);
  out.stream() << text;
  out.commit();
}

HmmModel parseModel(std::string_view text, const std::string& nameForErrors, std::string* trainingJson) {
  const Json document =
      parseJson(text, nameForErrors, {.maxDepth = kMaxNestingDepth, .depthNote = "a model needs 7", .subject = ""});
  try {
    return ModelReader(nameForErrors).read(document, trainingJson);
  } catch (const Json::exception& e) {
    // Every access in ModelReader checks the type first; this only keeps a missed case from escaping as an
    // nlohmann exception, which callers do not expect.
    throw fileError(nameForErrors, "is malformed (" + jsonReason(e.what()) + ")");
  }
}

HmmModel loadModel(const std::filesystem::path& path, std::string* trainingJson) {
  const std::string text = readTextFile(path, "model file");
  return parseModel(text, path.string(), trainingJson);
}

}  // namespace th::hmm
