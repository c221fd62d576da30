// HMM model files: versioned, self-describing JSON, validated on load, written atomically.
//
//   th::hmm::saveModel("head.json", model, R"({"iterations": 40, "logLikelihoods": [-1.2e5, -1.1e5]})");
//   std::string training;                                       // the file's "training" object, as JSON text
//   th::hmm::HmmModel loaded = th::hmm::loadModel("head.json", &training);
//   // any problem: th::Error, one line, "head.json: states[3].components[0].covariance is not positive definite"
//
// The file (other tools read it too, e.g. the Python reference in tools/, so the shape is fixed):
//   { "format": "talkinghead-hmm", "version": 1, "covariance": "full" | "diagonal",
//     "columns": [d names] or [], "blocks": [{"name": "audio", "begin": 0, "size": 121}, ...] or [],
//     "initial": [N], "transition": [N x [N]] (row i: from state i),
//     "states": [{"weights": [M], "components": [{"mean": [d], "covariance": [d x [d]]}        (full)
//                                               | {"mean": [d], "variances": [d]}]}],     (diagonal)
//     "training": { free-form } (optional) }
// Numbers are written in the shortest form that reads back as the same double, so save → load is bit-exact.
// Unknown fields are refused rather than ignored (a misspelt field would otherwise be silently dropped); a new
// field means a new version.
// Thread contract: free functions without shared state; safe to call from any thread.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "hmm/hmm_model.h"

namespace th::hmm {

inline constexpr int kModelFileVersion = 1;

// Writes `model` to `path` atomically (a temporary file renamed into place: the file is complete or absent).
// `trainingJson` is a JSON object (options, per-iteration log-likelihoods, ...) stored as "training"; empty
// means none. Refuses (th::Error "PATH: ...", nothing written) a model that loadModel would refuse.
void saveModel(const std::filesystem::path& path, const HmmModel& model, std::string_view trainingJson = {});

// The text saveModel writes; errors name `nameForErrors`.
std::string formatModel(const HmmModel& model, std::string_view trainingJson = {},
                        const std::string& nameForErrors = "model");

// Reads and validates a model file. `trainingJson`, if given, receives the "training" object as compact JSON
// ("{}" if the file has none). Throws th::Error "PATH: what is wrong" naming the offending field.
HmmModel loadModel(const std::filesystem::path& path, std::string* trainingJson = nullptr);

// The same from text in memory; errors start with "nameForErrors: ".
HmmModel parseModel(std::string_view text, const std::string& nameForErrors, std::string* trainingJson = nullptr);

}  // namespace th::hmm
