// `talkinghead train head` and `talkinghead eval head`: the prosody → head-motion model trained on several
// speakers (BEAT2's training part and StyleTalk's clips), and judged leave-one-speaker-out beside baselines that
// show whether the voice matters, by the paper's error and by what a viewer sees (speed, spread, stillness in
// pauses, the distribution of the motion).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "animation/head_data.h"
#include "animation/head_model.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "eval/head_protocol.h"
#include "face/face_model.h"
#include "hmm/entropic_training.h"
#include "pipeline/options.h"
#include "tracking/video_training.h"
#include "video_folder.h"

namespace th::app {
namespace {

using animation::HeadModel;
using animation::HeadRecording;

struct HeadArguments {
  std::string model;    // eval: judge this model file too (trained on what it was trained on)
  std::string compare;  // eval: another model file to judge beside (e.g. an older default)
  std::string output;   // train: where to write it
  double trainingFraction = 0.75;
  int lagFrames = animation::kLiveHeadLagFrames;
  bool beat2Only = false;  // train: the single-speaker model of the paper's setting
  bool styleFrom = false;  // eval: the head style from another clip of each held-out speaker
  std::string video;       // train: a folder of the user's own talking videos, trained on beside the corpora
  std::string tracks;      // train --video: where the tracks are kept (default: beside the output)
  int holdOutEvery = 5;    // train --video: every N-th clip held out
  bool outputGiven = false;
  animation::HeadModelOptions options;
};

void addModelOptions(CLI::App* command, HeadArguments& arguments) {
  command
      ->add_option("--train-fraction", arguments.trainingFraction,
                   "The first this fraction of the BEAT2 take trains, the rest is held out")
      ->check(CLI::Range(0.1, 0.95))
      ->capture_default_str();
  command->add_option("--start-states", arguments.options.startStates, "Fully connected states to start from")
      ->check(CLI::Range(2, 100))
      ->capture_default_str();
  command
      ->add_option("--entropic", arguments.options.entropicWeightPerFrame,
                   "Entropic prior weight per training frame (Z = this x frames)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  command->add_option("--seed", arguments.options.seed, "Seed of the k-means++ start")->capture_default_str();
  command->add_option("--iterations", arguments.options.maxIterations, "Most Baum-Welch iterations of the motion HMM")
      ->check(CLI::Range(5, 1000))
      ->capture_default_str();
  command->add_flag(
      "--residual-from-training", [&arguments](std::int64_t) { arguments.options.residualFromHeldOutSpeakers = false; },
      "Size the residual motion on the model's own training speech (one training instead of one more "
      "per speaker; the residual comes out smaller on new voices)");
  command->add_flag(
      "--no-speaker-normalisation", [&arguments](std::int64_t) { arguments.options.normaliseSpeakers = false; },
      "Keep each speaker's motion in degrees instead of in units of its own spread");
}

HeadModel train(const std::vector<HeadRecording>& parts, const animation::HeadModelOptions& options, double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  HeadModel model = animation::trainHeadModel(parts, options);
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return model;
}

void runTrainVideo(const HeadArguments& arguments);

void runTrain(const HeadArguments& arguments) {
  if (!arguments.video.empty()) {
    runTrainVideo(arguments);
    return;
  }
  checkOutputTarget(arguments.output);
  const eval::HeadCorpus corpus = eval::loadHeadCorpus(arguments.trainingFraction);
  const std::vector<HeadRecording> parts =
      arguments.beat2Only ? std::vector<HeadRecording>{corpus.beat2Train} : eval::headTrainingSet(corpus, "");
  int frames = 0;
  for (const auto& part : parts) frames += part.numFrames();
  double seconds = 0.0;
  const HeadModel model = train(parts, arguments.options, &seconds);
  animation::saveHeadModel(arguments.output, model, arguments.options);
  std::cerr << "head model: " << model.hmm.numStates() << " states (from " << arguments.options.startStates << "), "
            << hmm::countTransitions(model.hmm) << " transitions, trained on " << frames << " frames of "
            << model.speakers.size() << " speakers in " << seconds << " s; wrote " << arguments.output << '\n';
}

// ---- eval: the protocol is eval/head_protocol.h's; here it is printed ----

using eval::HeadRow;
using eval::HeadSpeakerTruth;

constexpr double kFps = eval::kHeadFramesPerSecond;

std::string pauseText(bool pauses, double ratio) {
  char text[16];
  std::snprintf(text, sizeof text, "%6.2f", ratio);
  return pauses ? text : "     -";
}

void printHeader(const HeadSpeakerTruth& truth) {
  std::printf("  %-44s %6s  %-17s  %-17s  %6s  %6s  %5s  %7s  %5s  %5s  %5s  %5s\n", "", "E", "corr p / y / r",
              "std ratio p/y/r", "p95 v", "pause", "jump%", "FD", "BA", "(chance)", "beat/s", "div");
  std::printf("  %-44s %6s  %-17s  %5.1f %5.1f %5.1f  %6.1f  %s  %5s  %7s  %5.3f  %5.3f  %5.2f  %5.2f\n",
              "truth (std deg, p95 deg/s, pause/speech)", "", "", truth.poseStd[0], truth.poseStd[1], truth.poseStd[2],
              truth.speedP95, pauseText(truth.pauses, truth.pauseRatio).c_str(), "", "", truth.beatAlign,
              truth.chanceAlign, truth.beatRate, truth.diversity);
}

void printRow(const HeadRow& r) {
  std::printf(
      "  %-44s %6.3f  %5.2f %5.2f %5.2f  %5.2f %5.2f %5.2f  %6.2f  %s  %5.1f  %7.1f  %5.3f  %5.3f  %5.2f  %5.2f\n",
      r.name.c_str(), r.error, r.correlation[0], r.correlation[1], r.correlation[2], r.stdRatio[0], r.stdRatio[1],
      r.stdRatio[2], r.speedRatio, pauseText(r.pauses, r.pauseRatio).c_str(), r.jumpPercent, r.frechet, r.beatAlign,
      r.chanceAlign, r.beatRate, r.diversity);
}

void printSpeaker(const eval::HeadSpeakerResult& result) {
  std::printf("\n%s left out: %d frames (%.1f s) in %zu clip(s); the recipe trained on", result.speaker.c_str(),
              result.frames, result.frames / kFps, result.clips);
  for (const auto& s : result.trainedOn) std::printf(" %s", s.c_str());
  std::printf(" (%d states, %.1f s)\n", result.states, result.trainingSeconds);
  printHeader(result.truth);
  for (const auto& row : result.rows) printRow(row);
  std::printf("  baselines:\n");
  for (const auto& row : result.baselines) printRow(row);
  std::printf("  the default %s; its FD %s every baseline's\n", result.verdict.text().c_str(),
              result.belowBaselines ? "is below" : "is NOT below");
}

void printSummary(const eval::HeadSummary& summary) {
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
  std::printf("\nThe default on the %zu held-out speakers:\n", summary.speakers.size());
  std::printf(
      "  spread over the truth's, per axis: geometric mean %.2f (target 0.8-1.25), from %.2f to %.2f (0.6-1.6)\n",
      summary.spreadGeometricMean, summary.spreadLowest, summary.spreadHighest);
  std::printf("  p95 speed over the truth's (target <= 1.25):%s\n", speed.c_str());
  std::printf("  pause/speech less the truth's (target <= +0.15):%s\n", pauses.c_str());
  std::printf("  Beat Align against the truth's (target within 10 %%):%s\n", beats.c_str());
}

void printBlinks(const eval::HeadBlinkReport& report) {
  std::printf(
      "\nBlinks (the idle behaviour on each take's sound, as animate and export add it): a minute in all, "
      "at pauses (in one or within 0.5 s after it begins) and in speech\n");
  for (const auto& take : report.takes)
    std::printf("  %-22s %5.1f s  %5.1f a minute;  at pauses %5.1f a minute (%4.1f s of such time), in speech %5.1f\n",
                take.name.c_str(), take.seconds, take.perMinute, take.atPausesPerMinute, take.pauseSeconds,
                take.inSpeechPerMinute);
  const eval::HeadBlinkRow& all = report.all;
  std::printf("  %-22s %5.1f s  %5.1f a minute;  at pauses %5.1f a minute, in speech %5.1f\n", all.name.c_str(),
              all.seconds, all.perMinute, all.atPausesPerMinute, all.inSpeechPerMinute);
}

void printStyleSpeaker(const eval::HeadStyleSpeaker& result) {
  std::printf("\n%s left out:", result.speaker.c_str());
  for (std::size_t i = 0; i < result.scored.size(); ++i) {
    const animation::HeadStyle& style = result.styles[i];
    std::printf("\n  %s styled from %s (gain %.2f / %.2f / %.2f, smoothing %.2f, variation %.2f, pause gain %.2f)",
                result.scored[i].c_str(), result.styledFrom[i].c_str(), style.axisGain[0], style.axisGain[1],
                style.axisGain[2], style.smoothing, style.variation, style.pauseVariation);
  }
  std::printf("\n");
  printHeader(result.truth);
  printRow(result.unstyled);
  printRow(result.styled);
  std::printf(
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

// `train head --video DIR`: the corpora and the user's own clips (one more speaker), every N-th clip held out
// and judged as eval head judges a speaker, beside the shipped model.
void runTrainVideo(const HeadArguments& arguments) {
  if (!arguments.outputGiven) throw Error("train head --video: give -o FILE.json (the shipped model stays as it is)");
  const std::filesystem::path output = arguments.output;
  if (output.extension() != ".json") throw fileError(output, "a model is written as JSON: give a .json name");
  checkOutputTarget(output);
  if (arguments.beat2Only) throw Error("train head --video: --beat2 trains BEAT2's speaker alone; leave it out");
  const std::filesystem::path tracks = tracksFolderFor(output, arguments.tracks);
  const std::vector<std::filesystem::path> videos = tracking::listVideos(arguments.video);
  const HeadModel shipped = animation::loadHeadModel(pipeline::ModelOptions{}.headModelPath());

  tracking::VideoCorpusOptions withHeads;
  withHeads.heads = true;
  const tracking::VideoCorpus clips = trackVideos(videos, tracks, withHeads);
  for (const auto& skipped : clips.skipped) std::cerr << "left out: " << skipped.reason << '\n';
  const std::string speaker = std::filesystem::path(arguments.video).filename().empty()
                                  ? std::filesystem::path(arguments.video).parent_path().filename().string()
                                  : std::filesystem::path(arguments.video).filename().string();
  std::vector<HeadRecording> own;
  for (const auto& clip : clips.clips) {
    if (!clip.head) {
      std::cerr << "left out: " << clip.headMissing << '\n';
      continue;
    }
    own.push_back(*clip.head);
    own.back().speaker = speaker;
    own.back().name = clip.video.filename().string();
  }
  if (own.empty()) throw fileError(arguments.video, "no clip has a head to train on");
  // Held out: every N-th clip; a single clip's last quarter.
  std::vector<HeadRecording> training, heldOut;
  if (own.size() == 1) {
    const int split = own.front().numFrames() * 3 / 4;
    training.push_back(animation::framesOf(own.front(), 0, split));
    heldOut.push_back(animation::framesOf(own.front(), split, own.front().numFrames() - split));
    heldOut.back().name += " (last quarter)";
  } else {
    for (std::size_t i = 0; i < own.size(); ++i) {
      const bool held =
          static_cast<int>(i % static_cast<std::size_t>(arguments.holdOutEvery)) == arguments.holdOutEvery - 1 ||
          (own.size() < static_cast<std::size_t>(arguments.holdOutEvery) && i + 1 == own.size());
      (held ? heldOut : training).push_back(own[i]);
    }
  }
  const eval::HeadCorpus corpus = eval::loadHeadCorpus(arguments.trainingFraction);
  std::vector<HeadRecording> parts = eval::headTrainingSet(corpus, "");
  int ownFrames = 0;
  for (const auto& clip : training) {
    parts.push_back(clip);
    ownFrames += clip.numFrames();
  }
  double seconds = 0.0;
  const HeadModel model = train(parts, arguments.options, &seconds);
  animation::saveHeadModel(output, model, arguments.options);
  std::printf(
      "%s: %zu clips tracked, %zu trained on (%.1f s) beside the corpora, %zu held out; %d states, trained in "
      "%.1f s; wrote %s\n",
      speaker.c_str(), own.size(), training.size(), ownFrames / kFps, heldOut.size(), model.hmm.numStates(), seconds,
      output.string().c_str());

  std::vector<eval::HeadJudgedClip> judged;
  for (const auto& clip : heldOut) judged.push_back(eval::judgedClipOf(clip));
  const HeadSpeakerTruth truth = eval::headTruthOf(judged);
  const auto seeded = [&](const std::string& name, const HeadModel& m) {
    std::vector<HeadRow> runs;
    for (unsigned seed = 1; seed <= 5; ++seed) {
      runs.push_back(eval::judgeHead(name, judged, truth, [&](std::size_t i) {
        return animation::synthesiseHead(m, judged[i].clip->prosody, judged[i].clip->voiced, {.seed = seed});
      }));
    }
    return eval::meanHeadRow(name + " (5 seeds)", runs);
  };
  std::printf("\nThe held-out clips (");
  for (std::size_t i = 0; i < heldOut.size(); ++i) std::printf("%s%s", i ? ", " : "", heldOut[i].name.c_str());
  std::printf("), as eval head judges a speaker:\n");
  printHeader(truth);
  printRow(seeded("trained with these clips", model));
  printRow(seeded("the shipped model", shipped));
}

void runStyleEval(const HeadArguments& arguments) {
  const eval::HeadCorpus corpus = eval::loadHeadCorpus(arguments.trainingFraction);
  std::printf(
      "Head style from another clip of the same speaker: for each speaker, the recipe trained on the others, "
      "styled from a clip of theirs that is not scored (BEAT2's scott: the first %.0f %% of his only posed take, "
      "%.1f s, scoring the rest; a speaker with one clip: each half from the other), beside it unstyled. The "
      "columns as eval head prints them; each row the mean of 5 seeds.\n",
      100.0 * arguments.trainingFraction, corpus.beat2Train.numFrames() / kFps);
  const eval::HeadStyleReport report = eval::evaluateHeadStyles(
      corpus, {.model = arguments.options, .lagFrames = arguments.lagFrames}, printStyleSpeaker);
  std::printf(
      "\nStyled, over the %zu held-out speakers: spread over the truth's, geometric mean %.2f (target 0.8-1.25; "
      "unstyled %.2f), from %.2f to %.2f (0.6-1.7)\n",
      report.speakers.size(), report.spreadGeometricMean, report.unstyledGeometricMean, report.spreadLowest,
      report.spreadHighest);
}

void runEval(const HeadArguments& arguments) {
  if (arguments.styleFrom) {
    runStyleEval(arguments);
    return;
  }
  // The model files first: a bad one fails at once, before the training.
  std::unique_ptr<HeadModel> compare;
  if (!arguments.compare.empty()) compare = std::make_unique<HeadModel>(animation::loadHeadModel(arguments.compare));
  std::unique_ptr<HeadModel> judged;
  if (!arguments.model.empty()) judged = std::make_unique<HeadModel>(animation::loadHeadModel(arguments.model));
  const eval::HeadCorpus corpus = eval::loadHeadCorpus(arguments.trainingFraction);
  std::printf(
      "Head motion, leave one speaker out: for each speaker, the recipe is trained on the others and judged on "
      "its speech (BEAT2's scott: the held-out last %.0f %% of the take).\n",
      100.0 * (1.0 - arguments.trainingFraction));
  std::printf(
      "E: the paper's error; corr: per axis; std ratio: the estimate's spread over the truth's; p95 v: the "
      "95th percentile of the angular speed over the truth's; pause: mean speed in pauses over mean speed in "
      "speech (pause: 30 dB under the loud frames); jump%%: steps over the truth's 99th percentile; FD: Fréchet "
      "distance of 1 s windows of pose and velocity; BA: Beat Align (SadTalker's) with the speech's onsets, "
      "(chance): the same with the onsets moved 1-3 s; beat/s: the motion's beats a second; div: the pose's "
      "spread (deg). Poses about each clip's own mean; the shipped model's rows the mean of 5 seeds.\n");
  const eval::HeadProtocolResult result = eval::evaluateHeadLeaveOneSpeakerOut(
      corpus, {.model = arguments.options, .lagFrames = arguments.lagFrames, .compare = compare.get()}, printSpeaker);
  printSummary(result.summary);
  std::vector<const HeadRecording*> takes{&corpus.beat2Train, &corpus.beat2Test};
  for (const auto& clip : corpus.styleTalk) takes.push_back(&clip);
  printBlinks(eval::reportHeadBlinks(takes));
  if (judged) {
    const eval::HeadModelJudgement judgement = eval::judgeHeadModelOnBeat2(corpus, *judged);
    std::printf("\n%s on BEAT2's held-out part (trained on", arguments.model.c_str());
    for (const auto& s : judged->speakers) std::printf(" %s", s.c_str());
    std::printf(")\n");
    printHeader(judgement.truth);
    printRow(judgement.row);
  }
}

}  // namespace

void addTrainCommand(CLI::App& app) {
  CLI::App* train = app.add_subcommand("train", "Train the animation models from the shared recordings");
  train->require_subcommand(0, 1);  // none with --video
  auto arguments = std::make_shared<HeadArguments>();
  arguments->output = "models/head.json";
  CLI::App* head =
      train->add_subcommand("head", "Prosody -> head motion HMM from BEAT2's training part and StyleTalk's speakers");
  addModelOptions(head, *arguments);
  head->add_option("-o,--output", arguments->output, "Model file to write")->capture_default_str();
  head->add_flag("--beat2", arguments->beat2Only, "BEAT2's one speaker only (the paper's setting)");
  head->add_option("--video", arguments->video,
                   "A folder of your own talking videos (one person), tracked and trained on beside the corpora; "
                   "every N-th clip held out and judged (give -o)");
  head->add_option("--tracks", arguments->tracks,
                   "With --video: where the tracks are kept and re-used (default: beside the output, NAME_tracks)");
  head->add_option("--hold-out-every", arguments->holdOutEvery, "With --video: every N-th clip is held out")
      ->check(CLI::Range(2, 100))
      ->capture_default_str();
  head->callback([arguments, head] {
    arguments->outputGiven = head->count("--output") > 0;
    runTrain(*arguments);
  });
  addTrainMouthCommand(*train);
  addTrainVisemesCommand(*train);
  addTrainArticulationCommand(*train);
  addTrainVideoOptions(*train);
}

void addEvalHeadCommand(CLI::App& eval) {
  auto arguments = std::make_shared<HeadArguments>();
  CLI::App* head = eval.add_subcommand(
      "head",
      "Head motion from prosody, leave one speaker out: the paper's E, speed, spread, pauses, jumps and the "
      "Fréchet distance beside baselines");
  addModelOptions(head, *arguments);
  head->add_option("--model", arguments->model, "Also judge this model file on BEAT2's held-out part");
  head->add_option("--compare", arguments->compare, "Judge this model file beside the recipe (e.g. an older default)");
  head->add_option("--lag-frames,--lag", arguments->lagFrames, "Decoding lag of the online variant, frames")
      ->check(CLI::Range(0, 300))
      ->capture_default_str();
  head->add_flag("--style-from", arguments->styleFrom,
                 "Instead: each held-out speaker's head style from another clip of theirs, styled beside unstyled");
  head->callback([arguments] { runEval(*arguments); });
}

}  // namespace th::app
