// `talkinghead eval pitch`: our F0 tracker and the Debian peers on the same files, at the same hops.
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>

#include "audio/audio_file.h"
#include "commands.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/subprocess.h"
#include "eval/peer_trackers.h"
#include "eval/pitch_corpus.h"

namespace th::app {
namespace {

struct EvalPitchArguments {
  std::string folder;
  bool peers = true;
  double minF0Hz = 60.0;
  double maxF0Hz = 500.0;
  features::PitchOptions pitch;
  std::string subset = "all";
};

// Our defaults were tuned on utterances 001-005 of each speaker; 006-010 are held out.
bool isHeldOut(const std::string& name) {
  return name.size() >= 5 && name.substr(2) > "005";
}

void printRow(const std::string& name, const eval::PitchScore& score, const std::string& note) {
  std::printf("  %-16s %6.2f %6.2f %6.2f %6.2f %6.2f %8.1f %8.1f   %s\n", name.c_str(), 100.0 * score.ffe(),
              100.0 * score.gpe(), 100.0 * score.vde(), 100.0 * score.missedVoicing(), 100.0 * score.falseVoicing(),
              score.fineMeanAbsCents(), score.fineStdCents(), note.c_str());
}

void runEvalPitch(const EvalPitchArguments& arguments) {
  const std::filesystem::path folder =
      arguments.folder.empty() ? sharedDataPath("speech/fda-ue") : std::filesystem::path(arguments.folder);
  auto corpus = eval::loadPitchCorpus(folder, 0.015);
  if (arguments.subset != "all") {
    std::erase_if(corpus,
                  [&](const auto& recording) { return isHeldOut(recording.name) != (arguments.subset == "held-out"); });
  }
  long long referenceFrames = 0;
  for (const auto& recording : corpus) referenceFrames += static_cast<long long>(recording.reference.f0Hz.size());
  std::printf(
      "F0 accuracy on %s: %zu files, %lld reference frames (15 ms); every track sampled at the\n"
      "reference times (nearest frame within half its hop). Search range %.0f-%.0f Hz for every tracker.\n",
      folder.string().c_str(), corpus.size(), referenceFrames, arguments.minF0Hz, arguments.maxF0Hz);

  struct Hop {
    std::string label;
    double fps;
  };
  for (const Hop& hop : {Hop{"5 ms hop (200 frames/s)", 200.0}, Hop{"30 frames/s (33.3 ms hop)", 30.0}}) {
    std::printf("\n%s\n  %-16s %6s %6s %6s %6s %6s %8s %8s   %s\n", hop.label.c_str(), "tracker", "FFE%", "GPE%",
                "VDE%", "miss%", "false%", "|cents|", "sd cents", "notes");
    features::FeatureOptions options = features::batchFeatureOptions();
    options.framesPerSecond = hop.fps;
    options.pitch = arguments.pitch;
    options.pitch.minF0Hz = arguments.minF0Hz;
    options.pitch.maxF0Hz = arguments.maxF0Hz;
    eval::PitchScore ours;
    eval::PitchScore oursMale;
    eval::PitchScore oursFemale;
    eval::PitchScore oursTuning;
    eval::PitchScore oursHeldOut;
    for (const auto& recording : corpus) {
      const auto clip = audio::readAudioFile(recording.wav);
      const auto score = eval::scoreTrack(recording, eval::ourF0Track(clip.samples, options), 1.0 / hop.fps);
      ours.merge(score);
      (recording.name.rfind("rl", 0) == 0 ? oursMale : oursFemale).merge(score);
      (isHeldOut(recording.name) ? oursHeldOut : oursTuning).merge(score);
    }
    const features::OnlineFeatureExtractor probe(options);
    char note[128];
    std::snprintf(note, sizeof(note), "streaming, look-ahead %.1f ms", probe.lookahead().f0Ms);
    printRow("talkinghead", ours, note);
    printRow("  male (rl)", oursMale, "");
    printRow("  female (sb)", oursFemale, "");
    printRow("  001-005", oursTuning, "the files our defaults were tuned on");
    printRow("  006-010", oursHeldOut, "held out from tuning");
    if (!arguments.peers) continue;
    for (eval::PeerTracker peer : eval::allPeerTrackers()) {
      if (!programExists(eval::peerProgram(peer))) {
        throw Error(eval::peerName(peer) + ": '" + eval::peerProgram(peer) +
                    "' is not installed (run scripts/setup.sh)");
      }
      eval::PeerSettings settings{1.0 / hop.fps, arguments.minF0Hz, arguments.maxF0Hz};
      eval::PitchScore score;
      for (const auto& recording : corpus) {
        score.merge(eval::scoreTrack(recording, eval::runPeerTracker(peer, recording.wav, settings), 1.0 / hop.fps));
      }
      printRow(eval::peerName(peer), score, "offline (whole file)");
    }
  }
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  CLI::App* eval = app.add_subcommand("eval", "Measure accuracy against references we did not write");
  eval->require_subcommand(1);
  auto arguments = std::make_shared<EvalPitchArguments>();
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
  pitch->callback([arguments] { runEvalPitch(*arguments); });
  addEvalHeadCommand(*eval);
  addEvalMouthCommand(*eval);
  addEvalVisemesCommand(*eval);
}

}  // namespace th::app
