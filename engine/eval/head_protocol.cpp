#include "eval/head_protocol.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

#include "animation/head_measures.h"
#include "animation/head_style.h"
#include "animation/idle_motion.h"
#include "animation/time_split.h"
#include "eval/head_corpus.h"
#include "eval/head_evaluation.h"
#include "face/fap_track.h"

namespace th::eval {

using animation::HeadModel;
using animation::HeadRecording;
using animation::HeadSynthesisOptions;
using animation::HeadVariant;

namespace {

constexpr double kFps = kHeadFramesPerSecond;

// What the model must beat on a speaker's held-out clips: the paper's one-speaker model, the mean pose, another
// clip's real motion and a random walk with the training speakers' statistics.
std::vector<HeadRow> headBaselines(const HeadCorpus& corpus, const std::string& speaker,
                                   const std::vector<HeadRecording>& parts, const std::vector<HeadJudgedClip>& clips,
                                   const HeadSpeakerTruth& truth, const HeadModel& oneSpeaker,
                                   const HeadProtocolOptions& options) {
  std::vector<HeadRow> baselines;
  // The old default: the paper's model of one speaker (BEAT2's first part; for its speaker, not left out).
  baselines.push_back(judgeHead(
      std::string("old default (one speaker, paper") + (speaker == corpus.beat2Train.speaker ? "; his own)" : ")"),
      clips, truth, [&](std::size_t i) {
        return animation::synthesiseHead(oneSpeaker, clips[i].clip->prosody, Eigen::RowVectorXd(),
                                         {.variant = HeadVariant::kStateMeans, .voicedOnly = false});
      }));
  baselines.push_back(judgeHead("the mean pose", clips, truth, [&](std::size_t i) {
    return Eigen::MatrixXd::Zero(3, clips[i].clip->numFrames()).eval();
  }));
  // Another speaker's real motion: the longest training clip of a speaker other than this one.
  const HeadRecording* other = nullptr;
  for (const auto& part : parts)
    if (other == nullptr || part.numFrames() > other->numFrames()) other = &part;
  baselines.push_back(judgeHead("another clip's real motion (" + other->name + ")", clips, truth, [&](std::size_t i) {
    return otherSpeakersMotion(*other, clips[i].clip->numFrames());
  }));
  // A random walk with the training speakers' statistics (their mean pose std and step std), mean over seeds.
  Eigen::Vector3d poseStd = Eigen::Vector3d::Zero(), stepStd = Eigen::Vector3d::Zero();
  for (const auto& part : parts) {
    const HeadMetrics self = evaluateHead(part.rotations, part.rotations, 1e9);
    poseStd += self.truthPoseStd / static_cast<double>(parts.size());
    stepStd += self.truthVelocityStd / static_cast<double>(parts.size());
  }
  std::vector<HeadRow> walkRuns;
  for (unsigned seed = 1; seed <= options.walks; ++seed) {
    walkRuns.push_back(judgeHead("", clips, truth, [&](std::size_t i) {
      return matchedRandomWalk(poseStd, stepStd, clips[i].clip->numFrames(), seed * 100 + static_cast<unsigned>(i));
    }));
  }
  baselines.push_back(
      meanHeadRow("random walk, matched statistics (mean of " + std::to_string(options.walks) + ")", walkRuns));
  return baselines;
}

HeadSpeakerResult evaluateSpeaker(const HeadCorpus& corpus, const std::string& speaker,
                                  const std::vector<const HeadRecording*>& heldOut, const HeadProtocolOptions& options,
                                  const HeadModel& oneSpeaker) {
  HeadSpeakerResult result;
  result.speaker = speaker;
  const std::vector<HeadRecording> parts = headTrainingSet(corpus, speaker);
  const HeadModel model = trainHeadModelTimed(parts, options.model, &result.trainingSeconds);
  std::vector<HeadJudgedClip> clips;
  for (const HeadRecording* clip : heldOut) {
    clips.push_back(judgedClipOf(*clip));
    result.frames += clip->numFrames();
  }
  result.clips = heldOut.size();
  result.truth = headTruthOf(clips);
  const HeadSpeakerTruth& truth = result.truth;
  const std::set<std::string> trainedOn(model.speakers.begin(), model.speakers.end());
  result.trainedOn.assign(trainedOn.begin(), trainedOn.end());
  result.states = model.hmm.numStates();

  const auto synthesise = [&](const HeadModel& m, const HeadSynthesisOptions& synthesis) {
    return [&, synthesis](std::size_t i) {
      return animation::synthesiseHead(m, clips[i].clip->prosody, clips[i].clip->voiced, synthesis);
    };
  };
  // The residual motion is random: the trajectory's rows are the mean over seeds.
  const auto seeded = [&](const std::string& name, HeadSynthesisOptions synthesis) {
    std::vector<HeadRow> runs;
    for (unsigned seed = 1; seed <= options.seeds; ++seed) {
      synthesis.seed = seed;
      runs.push_back(judgeHead(name, clips, truth, synthesise(model, synthesis)));
    }
    return meanHeadRow(name + " (" + std::to_string(options.seeds) + " seeds)", runs);
  };
  std::vector<HeadRow>& rows = result.rows;
  rows.push_back(seeded("trajectory (the default)", {}));
  rows.push_back(
      seeded("online (live, lag " + std::to_string(options.lagFrames) + ")", {.maxLagFrames = options.lagFrames}));
  rows.push_back(
      judgeHead("Viterbi state means (paper)", clips, truth, synthesise(model, {.variant = HeadVariant::kStateMeans})));
  rows.push_back(
      judgeHead("trajectory, unvoiced frames decoded too", clips, truth, synthesise(model, {.voicedOnly = false})));
  if (options.compare != nullptr) {
    rows.push_back(judgeHead("compared model, its own settings", clips, truth, [&](std::size_t i) {
      return animation::synthesiseHead(*options.compare, clips[i].clip->prosody, Eigen::RowVectorXd(),
                                       {.voicedOnly = false});
    }));
  }

  result.baselines = headBaselines(corpus, speaker, parts, clips, truth, oneSpeaker, options);
  const std::vector<HeadRow>& baselines = result.baselines;

  double bestBaseline = 1e300;
  for (const auto& row : baselines) bestBaseline = std::min(bestBaseline, row.frechet);
  result.verdict = headVerdict(rows.front(), truth);
  result.belowBaselines = rows.front().frechet < bestBaseline;
  return result;
}

}  // namespace

HeadModel trainHeadModelTimed(const std::vector<HeadRecording>& parts, const animation::HeadModelOptions& options,
                              double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  HeadModel model = animation::trainHeadModel(parts, options);
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return model;
}

HeadCorpus loadHeadCorpus(double trainingFraction) {
  HeadCorpus corpus;
  std::tie(corpus.beat2Train, corpus.beat2Test) = animation::splitByTime(loadBeat2Head(), trainingFraction);
  corpus.styleTalk = loadStyleTalkHeads();
  return corpus;
}

std::vector<HeadRecording> headTrainingSet(const HeadCorpus& corpus, const std::string& heldOut) {
  std::vector<HeadRecording> parts;
  if (heldOut != corpus.beat2Train.speaker) parts.push_back(corpus.beat2Train);
  for (const auto& clip : corpus.styleTalk)
    if (clip.speaker != heldOut) parts.push_back(clip);
  return parts;
}

HeadJudgedClip judgedClipOf(const HeadRecording& clip) {
  return {&clip, clip.rotations.colwise() - clip.rotations.rowwise().mean(), animation::pauseFrames(clip.levelDb)};
}

HeadSpeakerTruth headTruthOf(const std::vector<HeadJudgedClip>& clips) {
  HeadSpeakerTruth truth;
  for (const auto& c : clips) truth.frames += c.clip->numFrames();
  for (const auto& c : clips) {
    const double w = c.clip->numFrames() / truth.frames;
    const animation::HeadMotionStatistics s = animation::motionStatistics(c.truth, c.pauses, kFps);
    truth.speedP95 += w * s.speedP95;
    truth.pauseRatio += w * s.pauseSpeechRatio;
    truth.poseStd += w * s.poseStd;
    const std::vector<int> speech = animation::speechBeats(c.clip->levelDb), motion = animation::motionBeats(c.truth);
    truth.beatAlign += w * beatAlign(speech, motion);
    truth.chanceAlign += w * chanceBeatAlign(speech, motion, c.clip->numFrames());
    truth.beatRate += static_cast<double>(motion.size()) / (truth.frames / kFps);
    truth.diversity += w * poseDiversity(c.truth);
    truth.pauses = truth.pauses || c.pauses.sum() >= kFps;  // a second of pauses at least
  }
  return truth;
}

HeadRow judgeHead(const std::string& name, const std::vector<HeadJudgedClip>& clips, const HeadSpeakerTruth& truth,
                  const HeadEstimate& estimate) {
  HeadRow row;
  row.name = name;
  row.pauses = truth.pauses;
  std::vector<Eigen::MatrixXd> predictions, truths;
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const HeadJudgedClip& c = clips[i];
    const double w = c.clip->numFrames() / truth.frames;
    const Eigen::MatrixXd predicted = estimate(i);
    const HeadMetrics m = evaluateHead(predicted, c.truth, stepQuantile(c.truth, 0.99));
    const animation::HeadMotionStatistics s = animation::motionStatistics(predicted, c.pauses, kFps);
    row.error += w * m.error;
    row.correlation += w * m.correlation;
    row.stdRatio += w * s.poseStd.cwiseQuotient(truth.poseStd);
    row.speedRatio += w * s.speedP95 / truth.speedP95;
    row.pauseRatio += w * s.pauseSpeechRatio;
    row.jumpPercent += w * 100.0 * m.jumpRate;
    const std::vector<int> speech = animation::speechBeats(c.clip->levelDb), motion = animation::motionBeats(predicted);
    row.beatAlign += w * beatAlign(speech, motion);
    row.chanceAlign += w * chanceBeatAlign(speech, motion, c.clip->numFrames());
    row.beatRate += static_cast<double>(motion.size()) / (truth.frames / kFps);
    row.diversity += w * poseDiversity(predicted);
    predictions.push_back(predicted);
    truths.push_back(c.truth);
  }
  row.frechet = frechetDistance(predictions, truths, kFps);
  return row;
}

HeadRow meanHeadRow(const std::string& name, const std::vector<HeadRow>& rows) {
  HeadRow mean;
  mean.name = name;
  mean.pauses = rows.front().pauses;
  const double n = static_cast<double>(rows.size());
  for (const HeadRow& r : rows) {
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
  for (const HeadRow& r : rows) mean.beatAlignSpread += (r.beatAlign - mean.beatAlign) * (r.beatAlign - mean.beatAlign);
  mean.beatAlignSpread = rows.size() > 1 ? std::sqrt(mean.beatAlignSpread / (n - 1.0)) : 0.0;
  return mean;
}

std::string HeadVerdict::text() const {
  std::string missed;
  if (!speed) missed += " speed";
  if (!spread) missed += " spread";
  if (!pauses) missed += " pauses";
  return missed.empty() ? "meets speed, spread and pauses" : "misses:" + missed;
}

HeadVerdict headVerdict(const HeadRow& row, const HeadSpeakerTruth& truth, const HeadTargets& targets) {
  HeadVerdict verdict;
  verdict.speed = !(row.speedRatio > targets.maxSpeedRatio);
  verdict.spread = !(row.stdRatio.minCoeff() < targets.minStdRatio || row.stdRatio.maxCoeff() > targets.maxStdRatio);
  verdict.pauses = !(truth.pauses && row.pauseRatio > truth.pauseRatio + targets.maxPauseExcess);
  return verdict;
}

Eigen::MatrixXd otherSpeakersMotion(const HeadRecording& other, int frames) {
  const Eigen::MatrixXd centred = other.rotations.colwise() - other.rotations.rowwise().mean();
  Eigen::MatrixXd out(3, frames);
  for (int t = 0; t < frames; ++t) out.col(t) = centred.col(t % centred.cols());
  return out;
}

HeadSummary summariseHeadSpeakers(const std::vector<HeadSpeakerResult>& speakers) {
  std::vector<const HeadSpeakerResult*> byName;
  for (const HeadSpeakerResult& s : speakers) byName.push_back(&s);
  std::sort(byName.begin(), byName.end(),
            [](const HeadSpeakerResult* a, const HeadSpeakerResult* b) { return a->speaker < b->speaker; });
  HeadSummary summary;
  double logSpread = 0.0, lowest = 1e300, highest = 0.0;
  int axes = 0;
  for (const HeadSpeakerResult* result : byName) {
    const HeadRow& shipped = result->rows.front();
    const HeadSpeakerTruth& truth = result->truth;
    for (int axis = 0; axis < 3; ++axis) {
      logSpread += std::log(shipped.stdRatio[axis]);
      lowest = std::min(lowest, shipped.stdRatio[axis]);
      highest = std::max(highest, shipped.stdRatio[axis]);
      ++axes;
    }
    summary.speakers.push_back({.speaker = result->speaker,
                                .speedRatio = shipped.speedRatio,
                                .pauses = truth.pauses,
                                .pauseExcess = shipped.pauseRatio - truth.pauseRatio,
                                .beatAlignChange = shipped.beatAlign / truth.beatAlign - 1.0,
                                .beatAlignSpread = shipped.beatAlignSpread / truth.beatAlign,
                                .truthOverChance = truth.beatAlign / truth.chanceAlign - 1.0});
  }
  summary.spreadGeometricMean = axes > 0 ? std::exp(logSpread / axes) : 0.0;
  summary.spreadLowest = lowest;
  summary.spreadHighest = highest;
  return summary;
}

HeadProtocolResult evaluateHeadLeaveOneSpeakerOut(const HeadCorpus& corpus, const HeadProtocolOptions& options,
                                                  const std::function<void(const HeadSpeakerResult&)>& onSpeaker) {
  // The old default: the paper's setting, one speaker (BEAT2's training part), its Viterbi states' poses.
  const HeadModel oneSpeaker = trainHeadModelTimed({corpus.beat2Train}, options.model, nullptr);
  HeadProtocolResult result;
  const auto add = [&](const std::string& speaker, const std::vector<const HeadRecording*>& heldOut) {
    result.speakers.push_back(evaluateSpeaker(corpus, speaker, heldOut, options, oneSpeaker));
    if (onSpeaker) onSpeaker(result.speakers.back());
  };
  add(corpus.beat2Test.speaker, {&corpus.beat2Test});
  std::vector<std::string> speakers;
  for (const auto& clip : corpus.styleTalk)
    if (std::find(speakers.begin(), speakers.end(), clip.speaker) == speakers.end()) speakers.push_back(clip.speaker);
  for (const auto& speaker : speakers) {
    std::vector<const HeadRecording*> heldOut;
    for (const auto& clip : corpus.styleTalk)
      if (clip.speaker == speaker) heldOut.push_back(&clip);
    add(speaker, heldOut);
  }
  result.summary = summariseHeadSpeakers(result.speakers);
  return result;
}

namespace {

// A clip scored, and the other clip of the same person its style is fitted on.
struct StyleClipPair {
  HeadRecording scored;
  HeadRecording style;
};

// Each speaker's pairs: BEAT2's held-out part styled from its training part; each talking-head speaker's clips
// each styled from the next, or a single clip's halves each from the other.
std::vector<std::pair<std::string, std::vector<StyleClipPair>>> styleClipPairs(const HeadCorpus& corpus) {
  std::vector<std::pair<std::string, std::vector<StyleClipPair>>> speakers;
  {
    StyleClipPair beat2{corpus.beat2Test, corpus.beat2Train};
    beat2.scored.name += " (held-out part)";
    beat2.style.name += " (training part)";
    speakers.push_back({corpus.beat2Test.speaker, {beat2}});
  }
  std::vector<std::string> names;
  for (const auto& clip : corpus.styleTalk)
    if (std::find(names.begin(), names.end(), clip.speaker) == names.end()) names.push_back(clip.speaker);
  for (const std::string& name : names) {
    std::vector<const HeadRecording*> own;
    for (const auto& clip : corpus.styleTalk)
      if (clip.speaker == name) own.push_back(&clip);
    std::vector<StyleClipPair> pairs;
    if (own.size() >= 2) {
      for (std::size_t i = 0; i < own.size(); ++i) pairs.push_back({*own[i], *own[(i + 1) % own.size()]});
    } else {
      const HeadRecording& only = *own.front();
      const int half = only.numFrames() / 2;
      HeadRecording first = animation::framesOf(only, 0, half);
      HeadRecording second = animation::framesOf(only, half, only.numFrames() - half);
      first.name += " (first half)";
      second.name += " (second half)";
      pairs.push_back({first, second});
      pairs.push_back({second, first});
    }
    speakers.push_back({name, std::move(pairs)});
  }
  return speakers;
}

}  // namespace

HeadStyleReport evaluateHeadStyles(const HeadCorpus& corpus, const HeadProtocolOptions& options,
                                   const std::function<void(const HeadStyleSpeaker&)>& onSpeaker) {
  auto speakers = styleClipPairs(corpus);

  // A single clip's halves are shorter than a user's 20-60 s: the fit takes them down to 8 s.
  animation::HeadStyleFitOptions fit;
  fit.minSeconds = 8.0;
  HeadStyleReport report;
  double logSum = 0.0, unstyledLogSum = 0.0;
  report.spreadLowest = std::numeric_limits<double>::infinity();
  report.spreadHighest = 0.0;
  for (auto& [speaker, pairs] : speakers) {
    HeadStyleSpeaker result;
    result.speaker = speaker;
    const HeadModel model = trainHeadModelTimed(headTrainingSet(corpus, speaker), options.model, nullptr);
    std::vector<HeadJudgedClip> clips;
    std::vector<HeadSynthesisOptions> styled;
    for (const StyleClipPair& pair : pairs) {
      clips.push_back(judgedClipOf(pair.scored));
      result.scored.push_back(pair.scored.name);
      result.styledFrom.push_back(pair.style.name);
      result.styles.push_back(animation::fitHeadStyle(model, pair.style, fit));
      HeadSynthesisOptions synthesis;
      animation::applyHeadStyle(result.styles.back(), synthesis);
      styled.push_back(synthesis);
    }
    result.truth = headTruthOf(clips);
    // A jump: a step (frame to frame) longer than the person's longest in that clip.
    int steps = 0;
    const auto seeded = [&](const std::string& name, bool withStyle, int* jumps) {
      std::vector<HeadRow> runs;
      for (unsigned seed = 1; seed <= options.seeds; ++seed) {
        runs.push_back(judgeHead(name, clips, result.truth, [&](std::size_t i) {
          HeadSynthesisOptions synthesis = withStyle ? styled[i] : HeadSynthesisOptions{};
          synthesis.seed = seed;
          Eigen::MatrixXd motion =
              animation::synthesiseHead(model, clips[i].clip->prosody, clips[i].clip->voiced, synthesis);
          const double longest = animation::longestStep(clips[i].truth);
          for (Eigen::Index t = 1; t < motion.cols(); ++t) {
            const double step = (motion.col(t) - motion.col(t - 1)).norm();
            *jumps += step > longest;
            if (withStyle) result.longestStepRatio = std::max(result.longestStepRatio, step / longest);
            ++steps;
          }
          return motion;
        }));
      }
      return meanHeadRow(name + " (" + std::to_string(options.seeds) + " seeds)", runs);
    };
    int unstyledJumps = 0;
    result.unstyled = seeded("unstyled (the default)", false, &unstyledJumps);
    steps = 0;
    result.styled = seeded("styled from another clip", true, &result.styledJumps);
    result.steps = steps;
    const auto geometricMean = [](const Eigen::Vector3d& ratios) { return std::exp(ratios.array().log().mean()); };
    result.styledSpread = geometricMean(result.styled.stdRatio);
    result.unstyledSpread = geometricMean(result.unstyled.stdRatio);
    const HeadTargets targets;
    result.speedMet = result.styled.speedRatio <= targets.maxSpeedRatio;
    result.pausesMet =
        !result.truth.pauses || result.styled.pauseRatio <= result.truth.pauseRatio + targets.maxPauseExcess;
    result.frechetBelow = result.styled.frechet < result.unstyled.frechet;
    result.noJumps = result.styledJumps == 0;
    logSum += std::log(result.styledSpread);
    unstyledLogSum += std::log(result.unstyledSpread);
    report.spreadLowest = std::min(report.spreadLowest, result.styledSpread);
    report.spreadHighest = std::max(report.spreadHighest, result.styledSpread);
    if (onSpeaker) onSpeaker(result);
    report.speakers.push_back(std::move(result));
  }
  report.spreadGeometricMean = std::exp(logSum / static_cast<double>(report.speakers.size()));
  report.unstyledGeometricMean = std::exp(unstyledLogSum / static_cast<double>(report.speakers.size()));
  return report;
}

HeadBlinkReport reportHeadBlinks(const std::vector<const HeadRecording*>& takes) {
  HeadBlinkReport report;
  double allMinutes = 0.0, allBlinks = 0.0, pauseMinutes = 0.0, pauseBlinks = 0.0;
  for (const HeadRecording* take : takes) {
    face::FapTrack animation;
    animation.framesPerSecond = kFps;
    animation.values.resize(0, take->numFrames());
    animation::addIdleMotion(animation, take->levelDb, {}, {});
    const Eigen::RowVectorXd lid = animation.values.row(animation.rowOf(19));
    const Eigen::RowVectorXd pauses = animation::pauseFrames(take->levelDb);
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
    report.takes.push_back({.name = take->name,
                            .seconds = minutes * 60.0,
                            .perMinute = blinks / minutes,
                            .atPausesPerMinute = pauseShare > 0.0 ? atPauses / (minutes * pauseShare) : 0.0,
                            .pauseSeconds = minutes * pauseShare * 60.0,
                            .inSpeechPerMinute = (blinks - atPauses) / (minutes * (1.0 - pauseShare))});
    allMinutes += minutes;
    allBlinks += blinks;
    pauseMinutes += minutes * pauseShare;
    pauseBlinks += atPauses;
  }
  report.all = {.name = "all",
                .seconds = allMinutes * 60.0,
                .perMinute = allBlinks / allMinutes,
                .atPausesPerMinute = pauseMinutes > 0.0 ? pauseBlinks / pauseMinutes : 0.0,
                .pauseSeconds = pauseMinutes * 60.0,
                .inSpeechPerMinute = (allBlinks - pauseBlinks) / (allMinutes - pauseMinutes)};
  return report;
}

HeadModelJudgement judgeHeadModelOnBeat2(const HeadCorpus& corpus, const HeadModel& model) {
  const std::vector<HeadJudgedClip> clips{judgedClipOf(corpus.beat2Test)};
  HeadModelJudgement judgement;
  judgement.truth = headTruthOf(clips);
  judgement.row = judgeHead("trajectory", clips, judgement.truth, [&](std::size_t) {
    return animation::synthesiseHead(model, corpus.beat2Test.prosody, corpus.beat2Test.voiced, {});
  });
  return judgement;
}

}  // namespace th::eval
