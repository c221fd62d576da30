#include "eval/pitch_report.h"

#include <filesystem>

#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/print_to.h"
#include "core/subprocess.h"
#include "eval/peer_trackers.h"
#include "eval/pitch_corpus.h"
#include "features/online_features.h"

namespace th::eval {
namespace {

// Our defaults were tuned on utterances 001-005 of each speaker; 006-010 are held out.
bool isHeldOutFromTuning(const std::string& name) {
  return name.size() >= 5 && name.substr(2) > "005";
}

void writePitchRow(std::ostream& out, const std::string& name, const PitchScore& score, const std::string& note) {
  printTo(out, "  %-16s %6.2f %6.2f %6.2f %6.2f %6.2f %8.1f %8.1f   %s\n", name.c_str(), 100.0 * score.ffe(),
          100.0 * score.gpe(), 100.0 * score.vde(), 100.0 * score.missedVoicing(), 100.0 * score.falseVoicing(),
          score.fineMeanAbsCents(), score.fineStdCents(), note.c_str());
}

// Our tracker at `framesPerSecond`, streaming: in all, by sex and by tuning / held-out files.
void writeOurRows(std::ostream& out, const std::vector<PitchRecording>& corpus, const PitchReportOptions& options,
                  double framesPerSecond) {
  features::FeatureOptions features = features::batchFeatureOptions();
  features.framesPerSecond = framesPerSecond;
  features.pitch = options.pitch;
  features.pitch.minF0Hz = options.minF0Hz;
  features.pitch.maxF0Hz = options.maxF0Hz;
  PitchScore ours, male, female, tuning, heldOut;
  for (const auto& recording : corpus) {
    const auto clip = audio::readAudioFile(recording.wav);
    const auto score = scoreTrack(recording, ourF0Track(clip.samples, features), 1.0 / framesPerSecond);
    ours.merge(score);
    (recording.name.rfind("rl", 0) == 0 ? male : female).merge(score);
    (isHeldOutFromTuning(recording.name) ? heldOut : tuning).merge(score);
  }
  const features::OnlineFeatureExtractor probe(features);
  char note[128];
  std::snprintf(note, sizeof(note), "streaming, look-ahead %.1f ms", probe.lookahead().f0Ms);
  writePitchRow(out, "talkinghead", ours, note);
  writePitchRow(out, "  male (rl)", male, "");
  writePitchRow(out, "  female (sb)", female, "");
  writePitchRow(out, "  001-005", tuning, "the files our defaults were tuned on");
  writePitchRow(out, "  006-010", heldOut, "held out from tuning");
}

// Each peer on the whole files at the same hop and range.
void writePeerRows(std::ostream& out, const std::vector<PitchRecording>& corpus, const PitchReportOptions& options,
                   double framesPerSecond) {
  for (PeerTracker peer : allPeerTrackers()) {
    if (!programExists(peerProgram(peer)))
      throw Error(peerName(peer) + ": '" + peerProgram(peer) + "' is not installed (run scripts/setup.sh)");
    PeerSettings settings{1.0 / framesPerSecond, options.minF0Hz, options.maxF0Hz};
    PitchScore score;
    for (const auto& recording : corpus)
      score.merge(scoreTrack(recording, runPeerTracker(peer, recording.wav, settings), 1.0 / framesPerSecond));
    writePitchRow(out, peerName(peer), score, "offline (whole file)");
  }
}

}  // namespace

void reportPitchAccuracy(const PitchReportOptions& options, std::ostream& out) {
  const std::filesystem::path folder =
      options.folder.empty() ? sharedDataPath("speech/fda-ue") : std::filesystem::path(options.folder);
  auto corpus = loadPitchCorpus(folder, 0.015);
  if (options.subset != "all") {
    std::erase_if(corpus, [&](const auto& recording) {
      return isHeldOutFromTuning(recording.name) != (options.subset == "held-out");
    });
  }
  long long referenceFrames = 0;
  for (const auto& recording : corpus) referenceFrames += static_cast<long long>(recording.reference.f0Hz.size());
  printTo(out,
          "F0 accuracy on %s: %zu files, %lld reference frames (15 ms); every track sampled at the\n"
          "reference times (nearest frame within half its hop). Search range %.0f-%.0f Hz for every tracker.\n",
          folder.string().c_str(), corpus.size(), referenceFrames, options.minF0Hz, options.maxF0Hz);
  struct Hop {
    std::string label;
    double fps;
  };
  for (const Hop& hop : {Hop{"5 ms hop (200 frames/s)", 200.0}, Hop{"30 frames/s (33.3 ms hop)", 30.0}}) {
    printTo(out, "\n%s\n  %-16s %6s %6s %6s %6s %6s %8s %8s   %s\n", hop.label.c_str(), "tracker", "FFE%", "GPE%",
            "VDE%", "miss%", "false%", "|cents|", "sd cents", "notes");
    writeOurRows(out, corpus, options, hop.fps);
    if (options.peers) writePeerRows(out, corpus, options, hop.fps);
  }
}

}  // namespace th::eval
