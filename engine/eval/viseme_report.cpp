#include "eval/viseme_report.h"

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/print_to.h"
#include "eval/viseme_corpus.h"
#include "face/visemes.h"

namespace th::eval {
namespace {

constexpr double kVisemeFramesPerSecond = 30.0;

std::vector<std::string> namesOf(const auto& list) {
  std::vector<std::string> out;
  for (std::string_view name : list) out.emplace_back(name);
  return out;
}

void writeVisemeScores(std::ostream& out, const std::string& what, const VisemeScores& scores) {
  const double fps = kVisemeFramesPerSecond;
  const HoldTimes& holds = scores.holds();
  printTo(out, "  %-34s %6.1f%% %8.1f%% %8.1f%%", what.c_str(), 100.0 * scores.oculusAccuracy(),
          100.0 * scores.rhubarbAccuracy(), 100.0 * scores.classAccuracy());
  if (holds.runFrames.empty()) {
    printTo(out, "   %8s %9s %8s %7s\n", "-", "-", "-", "0");  // one viseme throughout
    return;
  }
  printTo(out, "   %5.0f ms %6.0f ms %7.1f%% %7.1f\n", 1000.0 * holds.shortest() / fps,
          1000.0 * holds.medianFrames() / fps, 100.0 * holds.shortRunShare(2),
          holds.switchesPerSecond(fps, scores.frames()));
}

// The confusion matrices of the whole-recording decoder, against the phones' own visemes.
void writeConfusions(std::ostream& out, const VisemeEvaluation& result) {
  printTo(out, "\nOculus visemes, HMM whole recording (rows: the phones' viseme; %% of its frames decoded as each)\n%s",
          formatConfusion(result.batch.oculusConfusion(), namesOf(face::kOculusVisemeNames)).c_str());
  std::vector<std::string> shapes;
  for (char shape : face::kRhubarbShapes) shapes.emplace_back(1, shape);
  printTo(out, "\nRhubarb shapes, HMM whole recording\n%s",
          formatConfusion(result.batch.rhubarbConfusion(), shapes).c_str());
}

// The minimum hold and the emission scale, each varied with the rest of the recipe as given.
void writeVisemeSweep(std::ostream& out, const std::vector<VisemeRecording>& corpus,
                      const VisemeReportOptions& options) {
  out << "\nMinimum hold (frames) against accuracy and flicker, whole recording:\n";
  for (int hold : {1, 2, 3, 4, 5}) {
    animation::VisemeModelOptions model = options.model;
    model.minHoldFrames = hold;
    writeVisemeScores(out, "min hold " + std::to_string(hold),
                      leaveOneSpeakerOut(corpus, model, options.lagFrames).batch);
  }
  out << "\nEmission scale:\n";
  for (double scale : {0.1, 0.2, 0.35, 0.5, 1.0}) {
    animation::VisemeModelOptions model = options.model;
    model.emissionScale = scale;
    char label[64];
    std::snprintf(label, sizeof label, "emission scale %.2f", scale);
    writeVisemeScores(out, label, leaveOneSpeakerOut(corpus, model, options.lagFrames).batch);
  }
}

int visemeFramesOf(const std::vector<VisemeRecording>& corpus) {
  int frames = 0;
  for (const VisemeRecording& r : corpus) frames += r.speech.numFrames();
  return frames;
}

}  // namespace

void reportVisemes(const VisemeReportOptions& options, std::ostream& out) {
  const double fps = kVisemeFramesPerSecond;
  const std::vector<VisemeRecording> corpus = loadVisemeCorpus();
  const VisemeEvaluation result = leaveOneSpeakerOut(corpus, options.model, options.lagFrames);
  const int frames = visemeFramesOf(corpus);
  printTo(out, "Visemes from speech, leave one speaker out (%zu speakers:", result.speakers.size());
  for (const std::string& speaker : result.speakers) printTo(out, " %s", speaker.c_str());
  printTo(out, "; %d frames, %.0f s, %d with a phone)\n", frames, frames / fps, result.batch.labelledFrames());
  printTo(out, "  %-34s %7s %9s %9s   %8s %9s %8s %7s\n", "", "Oculus", "Rhubarb", "classes", "shortest", "median",
          "<=2 fr", "per s");
  writeVisemeScores(out, "HMM, whole recording (animate)", result.batch);
  writeVisemeScores(out, "HMM, streamed, lag " + std::to_string(options.lagFrames) + " (live)", result.stream);
  writeVisemeScores(out, "each frame alone (no HMM)", result.frameByFrame);
  writeVisemeScores(out, "the most frequent class", result.majority);
  const HoldTimes& truth = result.batch.referenceHolds();
  printTo(out, "  %-34s %7s %9s %9s   %5.0f ms %6.0f ms %7.1f%% %7.1f\n", "the phones' own classes", "", "", "",
          1000.0 * truth.shortest() / fps, 1000.0 * truth.medianFrames() / fps, 100.0 * truth.shortRunShare(2),
          truth.switchesPerSecond(fps, result.batch.frames()));
  writeConfusions(out, result);
  if (options.sweep) writeVisemeSweep(out, corpus, options);
}

void trainVisemesOnCorpus(const std::filesystem::path& output, const animation::VisemeModelOptions& model,
                          std::ostream& out) {
  checkOutputTarget(output);
  const std::vector<VisemeRecording> corpus = loadVisemeCorpus();
  const animation::VisemeModel trained = animation::trainVisemeModel(labelledSpeechOf(corpus), model);
  animation::saveVisemeModel(output, trained);
  out << "wrote " << output.string() << ": " << face::kNumMouthClasses << " mouth classes from " << corpus.size()
      << " recordings (" << visemeFramesOf(corpus) << " frames), min hold " << trained.minHoldFrames << " frames\n";
}

}  // namespace th::eval
