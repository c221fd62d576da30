// HMMs on CSV tables, as `talkinghead hmm train|info|decode|invert` runs them: a table's rows are frames, its
// `seq` column (if any) splits them into sequences wherever its value changes, and its other columns are the
// observation (time_s is left out). A model trained with visual columns has an "audio" and a "visual" block
// (its columns named in the file), and inversion estimates the visual columns from the audio ones.
//
//   th::hmm::trainHmmOnTable({.data = "frames.csv", .output = "model.json", .states = 8}, std::cerr);
//   th::hmm::decodeTable({.model = "model.json", .data = "frames.csv", .output = "states.csv"});
//
// Thread contract: pure functions of the files they name.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

namespace th::hmm {

// Baum-Welch, with Brand's entropic prior when `entropic` or `covariancePrior` is not 0; the model file keeps
// the options and the per-iteration history. One line on `log`.
struct TableTraining {
  std::string data;
  std::string output;
  int states = 8;
  int mixtures = 1;
  std::string covariance = "full";  // or "diag"
  double entropic = 0.0;            // the prior's weight Z on π, transitions and mixture weights (absolute)
  double covariancePrior = 0.0;     // its weight on the covariances
  int warmup = 0;                   // maximum-likelihood iterations before the prior starts
  int ramp = 0;                     // iterations over which Z rises to its full value
  int mergeCandidates = 8;
  bool noTrim = false;
  int iterations = 100;
  unsigned seed = 1;
  std::string visualColumns;  // comma-separated: the visual block (the rest but seq and time_s: audio)
};
void trainHmmOnTable(const TableTraining& arguments, std::ostream& log);

// The model's structure and, if it has one, its training's final likelihood per frame, as indented JSON.
void writeModelInfo(const std::filesystem::path& path, std::ostream& out);

// The Viterbi state of every frame (column "state"); online, also the frames each decision waited (lag_frames).
struct TableDecoding {
  std::string model;
  std::string data;
  std::string output;
  bool online = false;
  int maxLag = -1;  // online: a decision forced after this many frames (-1: never)
};
void decodeTable(const TableDecoding& arguments);

// The visual columns from the audio columns, by HMM inversion (EM, from the conditional mean or a random start)
// or by the MMSE estimate.
struct TableInversion {
  std::string model;
  std::string data;
  std::string output;
  std::string method = "inversion";  // or "mmse"
  int window = 0;                    // frames per EM window (0: the whole sequence)
  std::string start = "mean";        // or "random"
};
void invertTable(const TableInversion& arguments);

}  // namespace th::hmm
