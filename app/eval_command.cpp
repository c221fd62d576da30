// `talkinghead eval`: its subcommands; `eval pitch` here, its report eval/pitch_report.h's.
#include <iostream>
#include <memory>

#include "commands.h"
#include "eval/pitch_report.h"

namespace th::app {

void addEvalCommand(CLI::App& app) {
  CLI::App* eval = app.add_subcommand("eval", "Measure accuracy against references we did not write");
  eval->require_subcommand(1);
  auto arguments = std::make_shared<eval::PitchReportOptions>();
  CLI::App* pitch = eval->add_subcommand(
      "pitch", "F0 tracking: FFE, GPE, VDE and fine error of ours and of Praat, RAPT, SWIPE and aubio");
  pitch->add_option("--data", arguments->folder, "Folder of WAV + .f0ref pairs (default: shared FDA-UE)");
  pitch->add_option("--subset", arguments->subset, "all, tuning (001-005) or held-out (006-010)")
      ->check(CLI::IsMember({"all", "tuning", "held-out"}));
  pitch->add_flag("!--no-peers", arguments->peers, "Score only our tracker");
  pitch->add_option("--min-f0-hz,--min-f0", arguments->minF0Hz, "Lowest F0 searched, all trackers (Hz)");
  pitch->add_option("--max-f0-hz,--max-f0", arguments->maxF0Hz, "Highest F0 searched, all trackers (Hz)");
  auto& tuning = arguments->pitch;
  pitch->add_option("--window-ms", tuning.windowMs, "Our tracker: analysis window (ms)")->group("Tuning our tracker");
  pitch->add_option("--lag-frames,--lag", tuning.decisionLagFrames, "Our tracker: Viterbi decision lag (frames)")
      ->group("Tuning our tracker");
  pitch->add_option("--voicing-threshold", tuning.voicingThreshold, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--silence-threshold", tuning.silenceThreshold, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--octave-cost", tuning.octaveCost, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--octave-jump-cost", tuning.octaveJumpCost, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--short-window-ms", tuning.shortWindowMs, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--level-window-ms", tuning.levelWindowMs, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--normalisation", tuning.normalisation, "Our tracker: 0 window autocorrelation, 1 NCCF")
      ->group("Tuning our tracker");
  pitch->add_option("--subharmonic-penalty", tuning.subharmonicPenalty, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--subharmonic-ratio", tuning.subharmonicRatio, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--short-weight", tuning.shortWeight, "Our tracker")->group("Tuning our tracker");
  pitch->add_option("--vu-cost", tuning.voicedUnvoicedCost, "Our tracker")->group("Tuning our tracker");
  pitch->callback([arguments] { eval::reportPitchAccuracy(*arguments, std::cout); });
  addEvalHeadCommand(*eval);
  addEvalMouthCommand(*eval);
  addEvalVisemesCommand(*eval);
}

}  // namespace th::app
