// `talkinghead train head` and `talkinghead eval head`: the prosody → head-motion model trained on several
// speakers (BEAT2's training part and StyleTalk's clips), and judged leave-one-speaker-out beside baselines that
// show whether the voice matters, by the paper's error and by what a viewer sees (speed, spread, stillness in
// pauses, the distribution of the motion).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "animation/head_data.h"
#include "animation/head_model.h"
#include "animation/idle_motion.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "eval/head_corpus.h"
#include "eval/head_evaluation.h"
#include "hmm/entropic_training.h"

namespace th::app {
namespace {

using animation::HeadModel;
using animation::HeadRecording;
using animation::HeadSynthesisOptions;
using animation::HeadVariant;

struct HeadArguments {
  std::string model;    // eval: judge this model file too (trained on what it was trained on)
  std::string compare;  // eval: another model file to judge beside (e.g. an older default)
  std::string output;   // train: where to write it
  double trainingFraction = 0.75;
  int lagFrames = animation::kLiveHeadLagFrames;
  bool beat2Only = false;  // train: the single-speaker model of the paper's setting
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

// Every recording with head pose: BEAT2's take split by time (its held-out part is never trained on) and
// StyleTalk's clips.
struct HeadCorpus {
  HeadRecording beat2Train;
  HeadRecording beat2Test;
  std::vector<HeadRecording> styleTalk;
};

HeadCorpus loadHeadCorpus(double trainingFraction) {
  HeadCorpus corpus;
  std::tie(corpus.beat2Train, corpus.beat2Test) = animation::splitByTime(eval::loadBeat2Head(), trainingFraction);
  corpus.styleTalk = eval::loadStyleTalkHeads();
  return corpus;
}

// The training recordings without `heldOut` ("" keeps every speaker).
std::vector<HeadRecording> trainingSet(const HeadCorpus& corpus, const std::string& heldOut) {
  std::vector<HeadRecording> parts;
  if (heldOut != corpus.beat2Train.speaker) parts.push_back(corpus.beat2Train);
  for (const auto& clip : corpus.styleTalk)
    if (clip.speaker != heldOut) parts.push_back(clip);
  return parts;
}

HeadModel train(const std::vector<HeadRecording>& parts, const animation::HeadModelOptions& options, double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  HeadModel model = animation::trainHeadModel(parts, options);
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return model;
}

void runTrain(const HeadArguments& arguments) {
  checkOutputTarget(arguments.output);
  const HeadCorpus corpus = loadHeadCorpus(arguments.trainingFraction);
  const std::vector<HeadRecording> parts =
      arguments.beat2Only ? std::vector<HeadRecording>{corpus.beat2Train} : trainingSet(corpus, "");
  int frames = 0;
  for (const auto& part : parts) frames += part.numFrames();
  double seconds = 0.0;
  const HeadModel model = train(parts, arguments.options, &seconds);
  animation::saveHeadModel(arguments.output, model, arguments.options);
  std::cerr << "head model: " << model.hmm.numStates() << " states (from " << arguments.options.startStates << "), "
            << hmm::countTransitions(model.hmm) << " transitions, trained on " << frames << " frames of "
            << model.speakers.size() << " speakers in " << seconds << " s; wrote " << arguments.output << '\n';
}

// ---- eval ----

// One held-out clip: its truth (about its own mean pose), its pauses, and what the estimators make of it.
struct JudgedClip {
  const HeadRecording* clip = nullptr;
  Eigen::MatrixXd truth;
  Eigen::RowVectorXd pauses;
};

// The measures of one estimator over a speaker's clips (means weighted by frames; the distribution distance
// over all the clips' windows).
struct Row {
  std::string name;
  double error = 0.0;
  Eigen::Vector3d correlation = Eigen::Vector3d::Zero();
  Eigen::Vector3d stdRatio = Eigen::Vector3d::Zero();
  double speedRatio = 0.0;
  double pauseRatio = 0.0;
  double jumpPercent = 0.0;
  double frechet = 0.0;
  double beatAlign = 0.0;        // SadTalker's Beat Align with the speech's onsets
  double chanceAlign = 0.0;      // the same with the onsets moved 1-3 s
  double beatRate = 0.0;         // motion beats a second
  double diversity = 0.0;        // the pose's mean spread, degrees
  double beatAlignSpread = 0.0;  // over seeds: the standard deviation of beatAlign (0 for one run)
  bool pauses = true;            // the speech has pauses (else pauseRatio means nothing)
};

struct SpeakerTruth {
  double speedP95 = 0.0;
  double pauseRatio = 0.0;
  bool pauses = false;
  Eigen::Vector3d poseStd = Eigen::Vector3d::Zero();
  double beatAlign = 0.0;
  double chanceAlign = 0.0;
  double beatRate = 0.0;
  double diversity = 0.0;
  double frames = 0.0;
};

constexpr double kFps = 30.0;

SpeakerTruth truthOf(const std::vector<JudgedClip>& clips) {
  SpeakerTruth truth;
  for (const auto& c : clips) truth.frames += c.clip->numFrames();
  for (const auto& c : clips) {
    const double w = c.clip->numFrames() / truth.frames;
    const eval::HeadMotionStatistics s = eval::motionStatistics(c.truth, c.pauses, kFps);
    truth.speedP95 += w * s.speedP95;
    truth.pauseRatio += w * s.pauseSpeechRatio;
    truth.poseStd += w * s.poseStd;
    const std::vector<int> speech = eval::speechBeats(c.clip->levelDb), motion = eval::motionBeats(c.truth);
    truth.beatAlign += w * eval::beatAlign(speech, motion);
    truth.chanceAlign += w * eval::chanceBeatAlign(speech, motion, c.clip->numFrames());
    truth.beatRate += static_cast<double>(motion.size()) / (truth.frames / kFps);
    truth.diversity += w * eval::poseDiversity(c.truth);
    truth.pauses = truth.pauses || c.pauses.sum() >= kFps;  // a second of pauses at least
  }
  return truth;
}

// estimate(clip index) → 3 x T rotations; averaged over `repeats` calls with different seeds when random.
template <typename Estimate>
Row judge(const std::string& name, const std::vector<JudgedClip>& clips, const SpeakerTruth& truth, Estimate estimate) {
  Row row;
  row.name = name;
  row.pauses = truth.pauses;
  std::vector<Eigen::MatrixXd> predictions, truths;
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const JudgedClip& c = clips[i];
    const double w = c.clip->numFrames() / truth.frames;
    const Eigen::MatrixXd predicted = estimate(i);
    const eval::HeadMetrics m = eval::evaluateHead(predicted, c.truth, eval::stepQuantile(c.truth, 0.99));
    const eval::HeadMotionStatistics s = eval::motionStatistics(predicted, c.pauses, kFps);
    row.error += w * m.error;
    row.correlation += w * m.correlation;
    row.stdRatio += w * s.poseStd.cwiseQuotient(truth.poseStd);
    row.speedRatio += w * s.speedP95 / truth.speedP95;
    row.pauseRatio += w * s.pauseSpeechRatio;
    row.jumpPercent += w * 100.0 * m.jumpRate;
    const std::vector<int> speech = eval::speechBeats(c.clip->levelDb), motion = eval::motionBeats(predicted);
    row.beatAlign += w * eval::beatAlign(speech, motion);
    row.chanceAlign += w * eval::chanceBeatAlign(speech, motion, c.clip->numFrames());
    row.beatRate += static_cast<double>(motion.size()) / (truth.frames / kFps);
    row.diversity += w * eval::poseDiversity(predicted);
    predictions.push_back(predicted);
    truths.push_back(c.truth);
  }
  row.frechet = eval::frechetDistance(predictions, truths, kFps);
  return row;
}

// The mean of rows of one estimator under different seeds.
Row meanRow(const std::string& name, const std::vector<Row>& rows) {
  Row mean;
  mean.name = name;
  mean.pauses = rows.front().pauses;
  mean.correlation.setZero();
  mean.stdRatio.setZero();
  const double n = static_cast<double>(rows.size());
  for (const Row& r : rows) {
    mean.error += r.error / n;
    mean.correlation += r.correlation / n;
    mean.stdRatio += r.stdRatio / n;
    mean.speedRatio += r.speedRatio / n;
    mean.pauseRatio += r.pauseRatio / n;
    mean.jumpPercent += r.jumpPercent / n;
    mean.frechet += r.frechet / n;
    mean.beatAlign += r.beatAlign / n;
    mean.chanceAlign += r.chanceAlign / n;
    mean.beatRate += r.beatRate / n;
    mean.diversity += r.diversity / n;
  }
  for (const Row& r : rows) mean.beatAlignSpread += (r.beatAlign - mean.beatAlign) * (r.beatAlign - mean.beatAlign);
  mean.beatAlignSpread = rows.size() > 1 ? std::sqrt(mean.beatAlignSpread / (n - 1.0)) : 0.0;
  return mean;
}

std::string pauseText(bool pauses, double ratio) {
  char text[16];
  std::snprintf(text, sizeof text, "%6.2f", ratio);
  return pauses ? text : "     -";
}

void printHeader(const SpeakerTruth& truth) {
  std::printf("  %-44s %6s  %-17s  %-17s  %6s  %6s  %5s  %7s  %5s  %5s  %5s  %5s\n", "", "E", "corr p / y / r",
              "std ratio p/y/r", "p95 v", "pause", "jump%", "FD", "BA", "(chance)", "beat/s", "div");
  std::printf("  %-44s %6s  %-17s  %5.1f %5.1f %5.1f  %6.1f  %s  %5s  %7s  %5.3f  %5.3f  %5.2f  %5.2f\n",
              "truth (std deg, p95 deg/s, pause/speech)", "", "", truth.poseStd[0], truth.poseStd[1], truth.poseStd[2],
              truth.speedP95, pauseText(truth.pauses, truth.pauseRatio).c_str(), "", "", truth.beatAlign,
              truth.chanceAlign, truth.beatRate, truth.diversity);
}

void printRow(const Row& r) {
  std::printf(
      "  %-44s %6.3f  %5.2f %5.2f %5.2f  %5.2f %5.2f %5.2f  %6.2f  %s  %5.1f  %7.1f  %5.3f  %5.3f  %5.2f  %5.2f\n",
      r.name.c_str(), r.error, r.correlation[0], r.correlation[1], r.correlation[2], r.stdRatio[0], r.stdRatio[1],
      r.stdRatio[2], r.speedRatio, pauseText(r.pauses, r.pauseRatio).c_str(), r.jumpPercent, r.frechet, r.beatAlign,
      r.chanceAlign, r.beatRate, r.diversity);
}

// Whether a row meets the targets, given the truth's pause ratio.
std::string verdict(const Row& r, const SpeakerTruth& truth) {
  std::string missed;
  if (r.speedRatio > 1.25) missed += " speed";
  if (r.stdRatio.minCoeff() < 0.7 || r.stdRatio.maxCoeff() > 1.3) missed += " spread";
  if (truth.pauses && r.pauseRatio > truth.pauseRatio + 0.15) missed += " pauses";
  return missed.empty() ? "meets speed, spread and pauses" : "misses:" + missed;
}

// A clip of another speaker's real motion, as long as `frames` (repeated from its start when shorter).
Eigen::MatrixXd otherMotion(const HeadRecording& other, int frames) {
  const Eigen::MatrixXd centred = other.rotations.colwise() - other.rotations.rowwise().mean();
  Eigen::MatrixXd out(3, frames);
  for (int t = 0; t < frames; ++t) out.col(t) = centred.col(t % centred.cols());
  return out;
}

// What the summary reads of each held-out speaker: the truth and the default's row.
struct SpeakerResult {
  SpeakerTruth truth;
  Row shipped;
};

void evaluateSpeaker(const HeadCorpus& corpus, const std::string& speaker,
                     const std::vector<const HeadRecording*>& heldOut, const HeadArguments& arguments,
                     const HeadModel* compare, const HeadModel& oneSpeaker, std::map<std::string, SpeakerResult>& all) {
  double seconds = 0.0;
  const std::vector<HeadRecording> parts = trainingSet(corpus, speaker);
  const HeadModel model = train(parts, arguments.options, &seconds);
  std::vector<JudgedClip> clips;
  int frames = 0;
  for (const HeadRecording* clip : heldOut) {
    clips.push_back(
        {clip, clip->rotations.colwise() - clip->rotations.rowwise().mean(), eval::pauseFrames(clip->levelDb)});
    frames += clip->numFrames();
  }
  const SpeakerTruth truth = truthOf(clips);
  std::set<std::string> trainedOn(model.speakers.begin(), model.speakers.end());
  std::printf("\n%s left out: %d frames (%.1f s) in %zu clip(s); the recipe trained on", speaker.c_str(), frames,
              frames / kFps, heldOut.size());
  for (const auto& s : trainedOn) std::printf(" %s", s.c_str());
  std::printf(" (%d states, %.1f s)\n", model.hmm.numStates(), seconds);
  printHeader(truth);

  std::vector<Row> rows;
  const auto synthesise = [&](const HeadModel& m, const HeadSynthesisOptions& options) {
    return [&, options](std::size_t i) {
      return animation::synthesiseHead(m, clips[i].clip->prosody, clips[i].clip->voiced, options);
    };
  };
  // The residual motion is random: the trajectory's rows are the mean over kSeeds seeds.
  constexpr unsigned kSeeds = 5;
  const auto seeded = [&](const std::string& name, HeadSynthesisOptions options) {
    std::vector<Row> runs;
    for (unsigned seed = 1; seed <= kSeeds; ++seed) {
      options.seed = seed;
      runs.push_back(judge(name, clips, truth, synthesise(model, options)));
    }
    return meanRow(name + " (" + std::to_string(kSeeds) + " seeds)", runs);
  };
  rows.push_back(seeded("trajectory (the default)", {}));
  rows.push_back(
      seeded("online (live, lag " + std::to_string(arguments.lagFrames) + ")", {.maxLagFrames = arguments.lagFrames}));
  rows.push_back(
      judge("Viterbi state means (paper)", clips, truth, synthesise(model, {.variant = HeadVariant::kStateMeans})));
  rows.push_back(
      judge("trajectory, unvoiced frames decoded too", clips, truth, synthesise(model, {.voicedOnly = false})));
  if (compare != nullptr) {
    rows.push_back(judge("compared model, its own settings", clips, truth, [&](std::size_t i) {
      return animation::synthesiseHead(*compare, clips[i].clip->prosody, Eigen::RowVectorXd(), {.voicedOnly = false});
    }));
  }
  for (const auto& row : rows) printRow(row);
  std::printf("  baselines:\n");
  std::vector<Row> baselines;
  // The old default: the paper's model of one speaker (BEAT2's first part; for scott, not left out).
  baselines.push_back(judge(
      std::string("old default (one speaker, paper") + (speaker == corpus.beat2Train.speaker ? "; his own)" : ")"),
      clips, truth, [&](std::size_t i) {
        return animation::synthesiseHead(oneSpeaker, clips[i].clip->prosody, Eigen::RowVectorXd(),
                                         {.variant = HeadVariant::kStateMeans, .voicedOnly = false});
      }));
  baselines.push_back(judge("the mean pose", clips, truth, [&](std::size_t i) {
    return Eigen::MatrixXd::Zero(3, clips[i].clip->numFrames()).eval();
  }));
  // Another speaker's real motion: the longest training clip of a speaker other than this one.
  const HeadRecording* other = nullptr;
  for (const auto& part : parts)
    if (other == nullptr || part.numFrames() > other->numFrames()) other = &part;
  baselines.push_back(judge("another clip's real motion (" + other->name + ")", clips, truth,
                            [&](std::size_t i) { return otherMotion(*other, clips[i].clip->numFrames()); }));
  // A random walk with the training speakers' statistics (their mean pose std and step std), mean of 10 seeds.
  Eigen::Vector3d poseStd = Eigen::Vector3d::Zero(), stepStd = Eigen::Vector3d::Zero();
  for (const auto& part : parts) {
    const eval::HeadMetrics self = eval::evaluateHead(part.rotations, part.rotations, 1e9);
    poseStd += self.truthPoseStd / static_cast<double>(parts.size());
    stepStd += self.truthVelocityStd / static_cast<double>(parts.size());
  }
  constexpr unsigned kWalks = 10;
  std::vector<Row> walkRuns;
  for (unsigned seed = 1; seed <= kWalks; ++seed) {
    walkRuns.push_back(judge("", clips, truth, [&](std::size_t i) {
      return eval::matchedRandomWalk(poseStd, stepStd, clips[i].clip->numFrames(),
                                     seed * 100 + static_cast<unsigned>(i));
    }));
  }
  const Row walks = meanRow("random walk, matched statistics (mean of 10)", walkRuns);
  baselines.push_back(walks);
  for (const auto& row : baselines) printRow(row);
  double bestBaseline = 1e300;
  for (const auto& row : baselines) bestBaseline = std::min(bestBaseline, row.frechet);
  std::printf("  the default %s; its FD %s every baseline's\n", verdict(rows.front(), truth).c_str(),
              rows.front().frechet < bestBaseline ? "is below" : "is NOT below");
  all[speaker] = {truth, rows.front()};
}

// The default over the held-out speakers beside the targets: per-axis spread 0.8-1.25 of the truth's on average
// (geometric mean over speakers and axes) and no take below 0.6 or above 1.6; p95 speed at most 1.25; pauses at
// most the truth's + 0.15; Beat Align within 10 % of the truth's.
void printSummary(const std::map<std::string, SpeakerResult>& all) {
  double logSpread = 0.0, lowest = 1e300, highest = 0.0;
  int axes = 0;
  std::string speed, pauses, beats;
  for (const auto& [speaker, result] : all) {
    for (int axis = 0; axis < 3; ++axis) {
      logSpread += std::log(result.shipped.stdRatio[axis]);
      lowest = std::min(lowest, result.shipped.stdRatio[axis]);
      highest = std::max(highest, result.shipped.stdRatio[axis]);
      ++axes;
    }
    char text[160];
    std::snprintf(text, sizeof text, " %s %.2f", speaker.c_str(), result.shipped.speedRatio);
    speed += text;
    if (result.truth.pauses) {
      std::snprintf(text, sizeof text, " %s %+.2f", speaker.c_str(),
                    result.shipped.pauseRatio - result.truth.pauseRatio);
      pauses += text;
    }
    std::snprintf(text, sizeof text, "\n    %s %+.0f %% (over seeds: sd %.0f %%; the truth's over its chance %+.0f %%)",
                  speaker.c_str(), 100.0 * (result.shipped.beatAlign / result.truth.beatAlign - 1.0),
                  100.0 * result.shipped.beatAlignSpread / result.truth.beatAlign,
                  100.0 * (result.truth.beatAlign / result.truth.chanceAlign - 1.0));
    beats += text;
  }
  std::printf("\nThe default on the %zu held-out speakers:\n", all.size());
  std::printf(
      "  spread over the truth's, per axis: geometric mean %.2f (target 0.8-1.25), from %.2f to %.2f (0.6-1.6)\n",
      std::exp(logSpread / axes), lowest, highest);
  std::printf("  p95 speed over the truth's (target <= 1.25):%s\n", speed.c_str());
  std::printf("  pause/speech less the truth's (target <= +0.15):%s\n", pauses.c_str());
  std::printf("  Beat Align against the truth's (target within 10 %%):%s\n", beats.c_str());
}

// The idle behaviour's blinks on each take's sound: how many a minute, and how many start in the sound's pauses
// (30 dB under its loud frames, as above) or within half a second after one begins, per minute of such time,
// against those that start while the voice goes on.
void reportBlinks(const std::vector<const HeadRecording*>& takes) {
  std::printf(
      "\nBlinks (the idle behaviour on each take's sound, as animate and export add it): a minute in all, "
      "at pauses (in one or within 0.5 s after it begins) and in speech\n");
  double allMinutes = 0.0, allBlinks = 0.0, pauseMinutes = 0.0, pauseBlinks = 0.0;
  for (const HeadRecording* take : takes) {
    face::FapTrack animation;
    animation.framesPerSecond = kFps;
    animation.values.resize(0, take->numFrames());
    animation::addIdleMotion(animation, take->levelDb, {}, {});
    const Eigen::RowVectorXd lid = animation.values.row(animation.rowOf(19));
    const Eigen::RowVectorXd pauses = eval::pauseFrames(take->levelDb);
    // Frames at a pause: in one, or within 0.5 s after one begins.
    std::vector<bool> atPause(static_cast<std::size_t>(take->numFrames()), false);
    for (int t = 0; t < take->numFrames(); ++t)
      if (pauses[t] > 0.0 && (t == 0 || pauses[t - 1] == 0.0))
        for (int u = t; u < std::min(take->numFrames(), t + static_cast<int>(0.5 * kFps)); ++u)
          atPause[static_cast<std::size_t>(u)] = true;
    for (int t = 0; t < take->numFrames(); ++t)
      atPause[static_cast<std::size_t>(t)] = atPause[static_cast<std::size_t>(t)] || pauses[t] > 0.0;
    int blinks = 0, atPauses = 0, pauseFramesCount = 0;
    for (int t = 0; t < take->numFrames(); ++t) {
      pauseFramesCount += atPause[static_cast<std::size_t>(t)];
      if (t > 0 && lid[t] > 512.0 && lid[t - 1] <= 512.0) {
        ++blinks;
        atPauses += atPause[static_cast<std::size_t>(t)];
      }
    }
    const double minutes = take->numFrames() / kFps / 60.0;
    const double pauseShare = pauseFramesCount / static_cast<double>(take->numFrames());
    std::printf("  %-22s %5.1f s  %5.1f a minute;  at pauses %5.1f a minute (%4.1f s of such time), in speech %5.1f\n",
                take->name.c_str(), minutes * 60.0, blinks / minutes,
                pauseShare > 0.0 ? atPauses / (minutes * pauseShare) : 0.0, minutes * pauseShare * 60.0,
                (blinks - atPauses) / (minutes * (1.0 - pauseShare)));
    allMinutes += minutes;
    allBlinks += blinks;
    pauseMinutes += minutes * pauseShare;
    pauseBlinks += atPauses;
  }
  std::printf("  %-22s %5.1f s  %5.1f a minute;  at pauses %5.1f a minute, in speech %5.1f\n", "all", allMinutes * 60.0,
              allBlinks / allMinutes, pauseMinutes > 0.0 ? pauseBlinks / pauseMinutes : 0.0,
              (allBlinks - pauseBlinks) / (allMinutes - pauseMinutes));
}

void runEval(const HeadArguments& arguments) {
  // The model files first: a bad one fails at once, before the training.
  std::unique_ptr<HeadModel> compare;
  if (!arguments.compare.empty()) compare = std::make_unique<HeadModel>(animation::loadHeadModel(arguments.compare));
  std::unique_ptr<HeadModel> judged;
  if (!arguments.model.empty()) judged = std::make_unique<HeadModel>(animation::loadHeadModel(arguments.model));
  const HeadCorpus corpus = loadHeadCorpus(arguments.trainingFraction);
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
  // The old default: the paper's setting, one speaker (BEAT2's training part), its Viterbi states' poses.
  const HeadModel oneSpeaker = train({corpus.beat2Train}, arguments.options, nullptr);
  std::map<std::string, SpeakerResult> all;
  evaluateSpeaker(corpus, corpus.beat2Test.speaker, {&corpus.beat2Test}, arguments, compare.get(), oneSpeaker, all);
  std::vector<std::string> speakers;
  for (const auto& clip : corpus.styleTalk)
    if (std::find(speakers.begin(), speakers.end(), clip.speaker) == speakers.end()) speakers.push_back(clip.speaker);
  for (const auto& speaker : speakers) {
    std::vector<const HeadRecording*> heldOut;
    for (const auto& clip : corpus.styleTalk)
      if (clip.speaker == speaker) heldOut.push_back(&clip);
    evaluateSpeaker(corpus, speaker, heldOut, arguments, compare.get(), oneSpeaker, all);
  }
  printSummary(all);
  std::vector<const HeadRecording*> takes{&corpus.beat2Train, &corpus.beat2Test};
  for (const auto& clip : corpus.styleTalk) takes.push_back(&clip);
  reportBlinks(takes);
  if (judged) {
    const HeadModel& model = *judged;
    std::vector<JudgedClip> clips{{&corpus.beat2Test,
                                   corpus.beat2Test.rotations.colwise() - corpus.beat2Test.rotations.rowwise().mean(),
                                   eval::pauseFrames(corpus.beat2Test.levelDb)}};
    const SpeakerTruth truth = truthOf(clips);
    std::printf("\n%s on BEAT2's held-out part (trained on", arguments.model.c_str());
    for (const auto& s : model.speakers) std::printf(" %s", s.c_str());
    std::printf(")\n");
    printHeader(truth);
    printRow(judge("trajectory", clips, truth, [&](std::size_t) {
      return animation::synthesiseHead(model, corpus.beat2Test.prosody, corpus.beat2Test.voiced, {});
    }));
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
  head->callback([arguments] { runTrain(*arguments); });
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
  head->callback([arguments] { runEval(*arguments); });
}

}  // namespace th::app
