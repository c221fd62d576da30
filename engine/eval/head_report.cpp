#include "eval/head_report.h"

#include <cstdio>
#include <memory>
#include <vector>

#include "animation/head_data.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/print_to.h"
#include "eval/head_protocol.h"
#include "hmm/entropic_training.h"

namespace th::eval {
namespace {

using animation::HeadModel;
using animation::HeadRecording;

std::string pauseText(bool pauses, double ratio) {
  char text[16];
  std::snprintf(text, sizeof text, "%6.2f", ratio);
  return pauses ? text : "     -";
}

void writeHeader(std::ostream& out, const HeadSpeakerTruth& truth) {
  printTo(out, "  %-44s %6s  %-17s  %-17s  %6s  %6s  %5s  %7s  %5s  %5s  %5s  %5s\n", "", "E", "corr p / y / r",
          "std ratio p/y/r", "p95 v", "pause", "jump%", "FD", "BA", "(chance)", "beat/s", "div");
  printTo(out, "  %-44s %6s  %-17s  %5.1f %5.1f %5.1f  %6.1f  %s  %5s  %7s  %5.3f  %5.3f  %5.2f  %5.2f\n",
          "truth (std deg, p95 deg/s, pause/speech)", "", "", truth.poseStd[0], truth.poseStd[1], truth.poseStd[2],
          truth.speedP95, pauseText(truth.pauses, truth.pauseRatio).c_str(), "", "", truth.beatAlign, truth.chanceAlign,
          truth.beatRate, truth.diversity);
}

void writeRow(std::ostream& out, const HeadRow& r) {
  printTo(out,
          "  %-44s %6.3f  %5.2f %5.2f %5.2f  %5.2f %5.2f %5.2f  %6.2f  %s  %5.1f  %7.1f  %5.3f  %5.3f  %5.2f  %5.2f\n",
          r.name.c_str(), r.error, r.correlation[0], r.correlation[1], r.correlation[2], r.stdRatio[0], r.stdRatio[1],
          r.stdRatio[2], r.speedRatio, pauseText(r.pauses, r.pauseRatio).c_str(), r.jumpPercent, r.frechet, r.beatAlign,
          r.chanceAlign, r.beatRate, r.diversity);
}

void writeSpeaker(std::ostream& out, const HeadSpeakerResult& result) {
  printTo(out, "\n%s left out: %d frames (%.1f s) in %zu clip(s); the recipe trained on", result.speaker.c_str(),
          result.frames, result.frames / kHeadFramesPerSecond, result.clips);
  for (const auto& s : result.trainedOn) printTo(out, " %s", s.c_str());
  printTo(out, " (%d states, %.1f s)\n", result.states, result.trainingSeconds);
  writeHeader(out, result.truth);
  for (const auto& row : result.rows) writeRow(out, row);
  out << "  baselines:\n";
  for (const auto& row : result.baselines) writeRow(out, row);
  printTo(out, "  the default %s; its FD %s every baseline's\n", result.verdict.text().c_str(),
          result.belowBaselines ? "is below" : "is NOT below");
}

void writeSummary(std::ostream& out, const HeadSummary& summary) {
  std::string speed, pauses, beats;
  for (const auto& s : summary.speakers) {
    char text[160];
    std::snprintf(text, sizeof text, " %s %.2f", s.speaker.c_str(), s.speedRatio);
    speed += text;
    if (s.pauses) {
      std::snprintf(text, sizeof text, " %s %+.2f", s.speaker.c_str(), s.pauseExcess);
      pauses += text;
    }
    std::snprintf(text, sizeof text, "\n    %s %+.0f %% (over seeds: sd %.0f %%; the truth's over its chance %+.0f %%)",
                  s.speaker.c_str(), 100.0 * s.beatAlignChange, 100.0 * s.beatAlignSpread, 100.0 * s.truthOverChance);
    beats += text;
  }
  printTo(out, "\nThe default on the %zu held-out speakers:\n", summary.speakers.size());
  printTo(out,
          "  spread over the truth's, per axis: geometric mean %.2f (target 0.8-1.25), from %.2f to %.2f (0.6-1.6)\n",
          summary.spreadGeometricMean, summary.spreadLowest, summary.spreadHighest);
  printTo(out, "  p95 speed over the truth's (target <= 1.25):%s\n", speed.c_str());
  printTo(out, "  pause/speech less the truth's (target <= +0.15):%s\n", pauses.c_str());
  printTo(out, "  Beat Align against the truth's (target within 10 %%):%s\n", beats.c_str());
}

void writeBlinks(std::ostream& out, const HeadBlinkReport& report) {
  out << "\nBlinks (the idle behaviour on each take's sound, as animate and export add it): a minute in all, "
         "at pauses (in one or within 0.5 s after it begins) and in speech\n";
  for (const auto& take : report.takes)
    printTo(out, "  %-22s %5.1f s  %5.1f a minute;  at pauses %5.1f a minute (%4.1f s of such time), in speech %5.1f\n",
            take.name.c_str(), take.seconds, take.perMinute, take.atPausesPerMinute, take.pauseSeconds,
            take.inSpeechPerMinute);
  const HeadBlinkRow& all = report.all;
  printTo(out, "  %-22s %5.1f s  %5.1f a minute;  at pauses %5.1f a minute, in speech %5.1f\n", all.name.c_str(),
          all.seconds, all.perMinute, all.atPausesPerMinute, all.inSpeechPerMinute);
}

void writeStyleSpeaker(std::ostream& out, const HeadStyleSpeaker& result) {
  printTo(out, "\n%s left out:", result.speaker.c_str());
  for (std::size_t i = 0; i < result.scored.size(); ++i) {
    const animation::HeadStyle& style = result.styles[i];
    printTo(out, "\n  %s styled from %s (gain %.2f / %.2f / %.2f, smoothing %.2f, variation %.2f, pause gain %.2f)",
            result.scored[i].c_str(), result.styledFrom[i].c_str(), style.axisGain[0], style.axisGain[1],
            style.axisGain[2], style.smoothing, style.variation, style.pauseVariation);
  }
  out << '\n';
  writeHeader(out, result.truth);
  writeRow(out, result.unstyled);
  writeRow(out, result.styled);
  printTo(out,
          "  spread over the truth's (geometric mean over the axes): styled %.2f, unstyled %.2f; styled: speed %s, "
          "pauses %s, FD %s the unstyled one's, %s (no step longer than the person's longest)\n",
          result.styledSpread, result.unstyledSpread, result.speedMet ? "meets" : "MISSES",
          result.pausesMet ? "meet" : "MISS", result.frechetBelow ? "below" : "NOT below",
          result.noJumps ? "no jumps"
                         : ("JUMPS: " + std::to_string(result.styledJumps) + " of " + std::to_string(result.steps) +
                            " steps longer than the person's longest, the longest " +
                            std::to_string(result.longestStepRatio).substr(0, 4) + "x it")
                               .c_str());
}

// One's own clips with a head, named for the speaker; the rest named on `log`.
std::vector<HeadRecording> ownHeadClips(const tracking::VideoCorpus& clips, const std::string& speaker,
                                        std::ostream& log) {
  for (const auto& skipped : clips.skipped) log << "left out: " << skipped.reason << '\n';
  std::vector<HeadRecording> own;
  for (const auto& clip : clips.clips) {
    if (!clip.head) {
      log << "left out: " << clip.headMissing << '\n';
      continue;
    }
    own.push_back(*clip.head);
    own.back().speaker = speaker;
    own.back().name = clip.video.filename().string();
  }
  return own;
}

// Held out: every N-th clip (the last one too when there are fewer than N); a single clip's last quarter.
void holdOutOwnClips(const std::vector<HeadRecording>& own, int holdOutEvery, std::vector<HeadRecording>& training,
                     std::vector<HeadRecording>& heldOut) {
  if (own.size() == 1) {
    const int split = own.front().numFrames() * 3 / 4;
    training.push_back(animation::framesOf(own.front(), 0, split));
    heldOut.push_back(animation::framesOf(own.front(), split, own.front().numFrames() - split));
    heldOut.back().name += " (last quarter)";
    return;
  }
  for (std::size_t i = 0; i < own.size(); ++i) {
    const bool held = static_cast<int>(i % static_cast<std::size_t>(holdOutEvery)) == holdOutEvery - 1 ||
                      (own.size() < static_cast<std::size_t>(holdOutEvery) && i + 1 == own.size());
    (held ? heldOut : training).push_back(own[i]);
  }
}

// The held-out clips judged as eval head judges a speaker, the new model beside the shipped one (5 seeds each).
void judgeOwnClips(std::ostream& out, const std::vector<HeadRecording>& heldOut, const HeadModel& model,
                   const HeadModel& shipped) {
  std::vector<HeadJudgedClip> judged;
  for (const auto& clip : heldOut) judged.push_back(judgedClipOf(clip));
  const HeadSpeakerTruth truth = headTruthOf(judged);
  const auto seeded = [&](const std::string& name, const HeadModel& m) {
    std::vector<HeadRow> runs;
    for (unsigned seed = 1; seed <= 5; ++seed) {
      runs.push_back(judgeHead(name, judged, truth, [&](std::size_t i) {
        return animation::synthesiseHead(m, judged[i].clip->prosody, judged[i].clip->voiced, {.seed = seed});
      }));
    }
    return meanHeadRow(name + " (5 seeds)", runs);
  };
  out << "\nThe held-out clips (";
  for (std::size_t i = 0; i < heldOut.size(); ++i) printTo(out, "%s%s", i ? ", " : "", heldOut[i].name.c_str());
  out << "), as eval head judges a speaker:\n";
  writeHeader(out, truth);
  writeRow(out, seeded("trained with these clips", model));
  writeRow(out, seeded("the shipped model", shipped));
}

}  // namespace

void reportHeadLeaveOneSpeakerOut(const HeadReportOptions& options, std::ostream& out) {
  // The model files first: a bad one fails at once, before the training.
  std::unique_ptr<HeadModel> compare;
  if (!options.compare.empty()) compare = std::make_unique<HeadModel>(animation::loadHeadModel(options.compare));
  std::unique_ptr<HeadModel> judged;
  if (!options.judged.empty()) judged = std::make_unique<HeadModel>(animation::loadHeadModel(options.judged));
  const HeadCorpus corpus = loadHeadCorpus(options.trainingFraction);
  printTo(out,
          "Head motion, leave one speaker out: for each speaker, the recipe is trained on the others and judged on "
          "its speech (BEAT2's scott: the held-out last %.0f %% of the take).\n",
          100.0 * (1.0 - options.trainingFraction));
  out << "E: the paper's error; corr: per axis; std ratio: the estimate's spread over the truth's; p95 v: the "
         "95th percentile of the angular speed over the truth's; pause: mean speed in pauses over mean speed in "
         "speech (pause: 30 dB under the loud frames); jump%: steps over the truth's 99th percentile; FD: Fréchet "
         "distance of 1 s windows of pose and velocity; BA: Beat Align (SadTalker's) with the speech's onsets, "
         "(chance): the same with the onsets moved 1-3 s; beat/s: the motion's beats a second; div: the pose's "
         "spread (deg). Poses about each clip's own mean; the shipped model's rows the mean of 5 seeds.\n";
  const HeadProtocolResult result = evaluateHeadLeaveOneSpeakerOut(
      corpus, {.model = options.model, .lagFrames = options.lagFrames, .compare = compare.get()},
      [&out](const HeadSpeakerResult& speaker) { writeSpeaker(out, speaker); });
  writeSummary(out, result.summary);
  std::vector<const HeadRecording*> takes{&corpus.beat2Train, &corpus.beat2Test};
  for (const auto& clip : corpus.styleTalk) takes.push_back(&clip);
  writeBlinks(out, reportHeadBlinks(takes));
  if (judged) {
    const HeadModelJudgement judgement = judgeHeadModelOnBeat2(corpus, *judged);
    printTo(out, "\n%s on BEAT2's held-out part (trained on", options.judged.c_str());
    for (const auto& s : judged->speakers) printTo(out, " %s", s.c_str());
    out << ")\n";
    writeHeader(out, judgement.truth);
    writeRow(out, judgement.row);
  }
}

void reportHeadStyles(const HeadReportOptions& options, std::ostream& out) {
  const HeadCorpus corpus = loadHeadCorpus(options.trainingFraction);
  printTo(out,
          "Head style from another clip of the same speaker: for each speaker, the recipe trained on the others, "
          "styled from a clip of theirs that is not scored (BEAT2's scott: the first %.0f %% of his only posed "
          "take, %.1f s, scoring the rest; a speaker with one clip: each half from the other), beside it unstyled. "
          "The columns as eval head prints them; each row the mean of 5 seeds.\n",
          100.0 * options.trainingFraction, corpus.beat2Train.numFrames() / kHeadFramesPerSecond);
  const HeadStyleReport report =
      evaluateHeadStyles(corpus, {.model = options.model, .lagFrames = options.lagFrames},
                         [&out](const HeadStyleSpeaker& speaker) { writeStyleSpeaker(out, speaker); });
  printTo(out,
          "\nStyled, over the %zu held-out speakers: spread over the truth's, geometric mean %.2f (target 0.8-1.25; "
          "unstyled %.2f), from %.2f to %.2f (0.6-1.7)\n",
          report.speakers.size(), report.spreadGeometricMean, report.unstyledGeometricMean, report.spreadLowest,
          report.spreadHighest);
}

void trainHeadModelOnCorpora(const HeadTraining& training, std::ostream& log) {
  checkOutputTarget(training.output);
  const HeadCorpus corpus = loadHeadCorpus(training.trainingFraction);
  const std::vector<HeadRecording> parts =
      training.beat2Only ? std::vector<HeadRecording>{corpus.beat2Train} : headTrainingSet(corpus, "");
  int frames = 0;
  for (const auto& part : parts) frames += part.numFrames();
  double seconds = 0.0;
  const HeadModel model = trainHeadModelTimed(parts, training.model, &seconds);
  animation::saveHeadModel(training.output, model, training.model);
  log << "head model: " << model.hmm.numStates() << " states (from " << training.model.startStates << "), "
      << hmm::countTransitions(model.hmm) << " transitions, trained on " << frames << " frames of "
      << model.speakers.size() << " speakers in " << seconds << " s; wrote " << training.output.string() << '\n';
}

void trainHeadModelWithOwnClips(const tracking::VideoCorpus& clips, const std::filesystem::path& folder,
                                const HeadModel& shipped, const HeadTraining& training, std::ostream& out,
                                std::ostream& log) {
  const std::string speaker =
      folder.filename().empty() ? folder.parent_path().filename().string() : folder.filename().string();
  const std::vector<HeadRecording> own = ownHeadClips(clips, speaker, log);
  if (own.empty()) throw fileError(folder, "no clip has a head to train on");
  std::vector<HeadRecording> ownTraining, heldOut;
  holdOutOwnClips(own, training.holdOutEvery, ownTraining, heldOut);
  const HeadCorpus corpus = loadHeadCorpus(training.trainingFraction);
  std::vector<HeadRecording> parts = headTrainingSet(corpus, "");
  int ownFrames = 0;
  for (const auto& clip : ownTraining) {
    parts.push_back(clip);
    ownFrames += clip.numFrames();
  }
  double seconds = 0.0;
  const HeadModel model = trainHeadModelTimed(parts, training.model, &seconds);
  animation::saveHeadModel(training.output, model, training.model);
  printTo(out,
          "%s: %zu clips tracked, %zu trained on (%.1f s) beside the corpora, %zu held out; %d states, trained in "
          "%.1f s; wrote %s\n",
          speaker.c_str(), own.size(), ownTraining.size(), ownFrames / kHeadFramesPerSecond, heldOut.size(),
          model.hmm.numStates(), seconds, training.output.string().c_str());
  judgeOwnClips(out, heldOut, model, shipped);
}

}  // namespace th::eval
