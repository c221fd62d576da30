// `talkinghead hmm train|info|decode|invert`: the HMM engine from the command line, on CSV files.
#include <iostream>
#include <memory>

#include "commands.h"
#include "hmm/table_tools.h"

namespace th::app {

void addHmmCommand(CLI::App& app) {
  CLI::App* hmmCommand =
      app.add_subcommand("hmm", "Train, inspect, decode and invert Gaussian-mixture HMMs on CSV data");
  hmmCommand->require_subcommand(1);

  auto train = std::make_shared<hmm::TableTraining>();
  CLI::App* trainCommand =
      hmmCommand->add_subcommand("train", "Train an HMM (Baum-Welch, optionally with Brand's entropic prior)");
  trainCommand->add_option("--data", train->data, "CSV with a header; a 'seq' column splits sequences")->required();
  trainCommand->add_option("--states", train->states, "Number of states (a generous start when entropic)")
      ->required()
      ->check(CLI::Range(1, 1000));
  trainCommand->add_option("--mixtures", train->mixtures, "Gaussians per state")->check(CLI::Range(1, 100));
  trainCommand->add_option("--covariance", train->covariance, "full or diag")->check(CLI::IsMember({"full", "diag"}));
  trainCommand->add_option("--entropic", train->entropic,
                           "Entropic prior weight Z on pi, transitions and mixture weights (0: maximum likelihood); "
                           "absolute, so set it against the number of frames");
  trainCommand->add_option("--covariance-prior", train->covariancePrior, "Entropic prior weight on covariances");
  trainCommand->add_option("--warmup", train->warmup, "Maximum-likelihood iterations before the prior starts");
  trainCommand->add_option("--ramp", train->ramp, "Iterations over which Z rises to its full value");
  trainCommand
      ->add_option("--merge-candidates", train->mergeCandidates,
                   "With the entropic prior: most similar state pairs tried for merging per iteration once Z "
                   "has settled; a merge is kept only if the log posterior rises (0: never)")
      ->check(CLI::Range(0, 100));
  trainCommand->add_flag("--no-trim", train->noTrim,
                         "With the entropic prior: no parameter extinction, state deletion or merging");
  trainCommand->add_option("--iterations", train->iterations, "Maximum EM iterations")->check(CLI::Range(1, 100000));
  trainCommand->add_option("--seed", train->seed, "Seed of the k-means++ initialisation");
  trainCommand->add_option("--visual-columns", train->visualColumns,
                           "Comma-separated columns forming the visual block");
  trainCommand->add_option("-o,--output", train->output, "Model file (JSON) to write")->required();
  trainCommand->callback([train] { hmm::trainHmmOnTable(*train, std::cerr); });

  auto infoPath = std::make_shared<std::string>();
  CLI::App* info = hmmCommand->add_subcommand("info", "Print a model's structure and training summary as JSON");
  info->add_option("model", *infoPath, "Model file")->required();
  info->callback([infoPath] { hmm::writeModelInfo(*infoPath, std::cout); });

  auto decode = std::make_shared<hmm::TableDecoding>();
  CLI::App* decodeCommand = hmmCommand->add_subcommand("decode", "Most likely state of every frame (Viterbi)");
  decodeCommand->add_option("model", decode->model, "Model file")->required();
  decodeCommand->add_option("--data", decode->data, "CSV with the model's columns")->required();
  decodeCommand->add_flag("--online", decode->online, "Online Viterbi (convergence points); adds a lag_frames column");
  decodeCommand->add_option("--max-lag", decode->maxLag, "Online: force a decision after this many frames");
  decodeCommand->add_option("-o,--output", decode->output, "CSV to write (column 'state')")->required();
  decodeCommand->callback([decode] { hmm::decodeTable(*decode); });

  auto invert = std::make_shared<hmm::TableInversion>();
  CLI::App* invertCommand =
      hmmCommand->add_subcommand("invert", "Visual columns from audio columns by HMM inversion or MMSE");
  invertCommand->add_option("model", invert->model, "Model file with 'audio' and 'visual' blocks")->required();
  invertCommand->add_option("--data", invert->data, "CSV with the model's audio columns")->required();
  invertCommand->add_option("--method", invert->method, "inversion or mmse")
      ->check(CLI::IsMember({"inversion", "mmse"}));
  invertCommand->add_option("--window-frames,--window", invert->window, "Frames per EM window (0: whole sequence)")
      ->check(CLI::Range(0, 1000000));
  invertCommand->add_option("--start", invert->start, "mean (conditional mean) or random")
      ->check(CLI::IsMember({"mean", "random"}));
  invertCommand->add_option("-o,--output", invert->output, "CSV of the visual columns")->required();
  invertCommand->callback([invert] { hmm::invertTable(*invert); });
}

}  // namespace th::app
