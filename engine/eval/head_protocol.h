// The head-motion model judged leave one speaker out (`talkinghead eval head`): for each speaker, the recipe
// trained on the others and judged on that speaker's speech beside baselines that show whether the voice
// matters (the mean pose, another speaker's real motion, a random walk with the training speakers' statistics),
// by the paper's error and by what a viewer sees (head_evaluation.h: speed, spread, stillness in pauses, the
// distribution of the motion, Beat Align).
//
//   th::eval::HeadCorpus corpus = th::eval::loadHeadCorpus(0.75);
//   th::eval::HeadProtocolResult result = th::eval::evaluateHeadLeaveOneSpeakerOut(corpus, {});
//   for (const auto& speaker : result.speakers) ... speaker.rows.front() is the default's row ...
//
// A row's measures are means over the speaker's clips weighted by their frames; the Fréchet distance is over
// all the clips' windows together. Poses are taken about each clip's own mean.
// Thread contract: pure functions of their arguments (the corpus loader reads files).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "animation/head_data.h"
#include "animation/head_model.h"
#include "animation/head_style.h"

namespace th::eval {

inline constexpr double kHeadFramesPerSecond = 30.0;  // the corpora's rate (head_corpus.h)

// Every recording with head pose: BEAT2's take split by time (its held-out part is never trained on) and
// StyleTalk's clips.
struct HeadCorpus {
  animation::HeadRecording beat2Train;
  animation::HeadRecording beat2Test;
  std::vector<animation::HeadRecording> styleTalk;
};

// The shared corpora; the first `trainingFraction` of BEAT2's take trains.
HeadCorpus loadHeadCorpus(double trainingFraction);
// animation::trainHeadModel, with the seconds it took in `seconds` if given.
animation::HeadModel trainHeadModelTimed(const std::vector<animation::HeadRecording>& parts,
                                         const animation::HeadModelOptions& options, double* seconds);
// The training recordings without speaker `heldOut` ("" keeps every speaker).
std::vector<animation::HeadRecording> headTrainingSet(const HeadCorpus& corpus, const std::string& heldOut);

// One held-out clip: its truth (about its own mean pose) and its pauses (pauseFrames).
struct HeadJudgedClip {
  const animation::HeadRecording* clip = nullptr;
  Eigen::MatrixXd truth;
  Eigen::RowVectorXd pauses;
};
HeadJudgedClip judgedClipOf(const animation::HeadRecording& clip);

// What the truth of a speaker's clips measures (the estimators' rows are read against it).
struct HeadSpeakerTruth {
  double speedP95 = 0.0;  // deg/s
  double pauseRatio = 0.0;
  bool pauses = false;  // a second of pauses at least (else a pause ratio means nothing)
  Eigen::Vector3d poseStd = Eigen::Vector3d::Zero();
  double beatAlign = 0.0;
  double chanceAlign = 0.0;
  double beatRate = 0.0;   // motion beats a second
  double diversity = 0.0;  // degrees
  double frames = 0.0;
};
HeadSpeakerTruth headTruthOf(const std::vector<HeadJudgedClip>& clips);

// The measures of one estimator over a speaker's clips.
struct HeadRow {
  std::string name;
  double error = 0.0;  // the paper's E
  Eigen::Vector3d correlation = Eigen::Vector3d::Zero();
  Eigen::Vector3d stdRatio = Eigen::Vector3d::Zero();  // per axis, over the truth's
  double speedRatio = 0.0;                             // p95 speed over the truth's
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

// estimate(clip index) → 3 x T rotations for that clip.
using HeadEstimate = std::function<Eigen::MatrixXd(std::size_t clip)>;
HeadRow judgeHead(const std::string& name, const std::vector<HeadJudgedClip>& clips, const HeadSpeakerTruth& truth,
                  const HeadEstimate& estimate);
// The mean of rows of one estimator under different seeds; beatAlignSpread is their sample standard deviation.
// `rows` must not be empty.
HeadRow meanHeadRow(const std::string& name, const std::vector<HeadRow>& rows);

// The targets a row is held to against the truth.
struct HeadTargets {
  double maxSpeedRatio = 1.25;
  double minStdRatio = 0.7;  // on every axis
  double maxStdRatio = 1.3;
  double maxPauseExcess = 0.15;  // pause ratio over the truth's (only where the truth has pauses)
};
struct HeadVerdict {
  bool speed = true;
  bool spread = true;
  bool pauses = true;
  bool meets() const { return speed && spread && pauses; }
  // "meets speed, spread and pauses" or "misses: speed spread ..."
  std::string text() const;
};
HeadVerdict headVerdict(const HeadRow& row, const HeadSpeakerTruth& truth, const HeadTargets& targets = {});

// A clip of another speaker's real motion about its own mean, `frames` long (repeated from its start when
// shorter).
Eigen::MatrixXd otherSpeakersMotion(const animation::HeadRecording& other, int frames);

// One speaker left out.
struct HeadSpeakerResult {
  std::string speaker;
  int frames = 0;
  std::size_t clips = 0;
  std::vector<std::string> trainedOn;  // the fold's model's speakers, sorted
  int states = 0;                      // the fold's model's
  double trainingSeconds = 0.0;
  HeadSpeakerTruth truth;
  // The default (trajectory, mean over seeds) first, then the online variant, the Viterbi state means, the
  // trajectory decoded on unvoiced frames too and, if given, the compared model.
  std::vector<HeadRow> rows;
  // The old default (one speaker, the paper's setting), the mean pose, another clip's real motion, the random
  // walk (mean over seeds).
  std::vector<HeadRow> baselines;
  HeadVerdict verdict;          // of the default
  bool belowBaselines = false;  // the default's Fréchet distance is below every baseline's
};

// The default over the held-out speakers, against the targets: per-axis spread 0.8-1.25 of the truth's on
// average (geometric mean over speakers and axes) and none below 0.6 or above 1.6; p95 speed at most 1.25;
// pauses at most the truth's + 0.15; Beat Align within 10 % of the truth's.
struct HeadSummary {
  struct Speaker {
    std::string speaker;
    double speedRatio = 0.0;
    bool pauses = false;           // the truth has pauses (pauseExcess means something)
    double pauseExcess = 0.0;      // the default's pause ratio less the truth's
    double beatAlignChange = 0.0;  // the default's Beat Align over the truth's, less 1
    double beatAlignSpread = 0.0;  // over seeds, over the truth's Beat Align
    double truthOverChance = 0.0;  // the truth's Beat Align over its chance, less 1
  };
  double spreadGeometricMean = 0.0;
  double spreadLowest = 0.0;
  double spreadHighest = 0.0;
  std::vector<Speaker> speakers;  // by name
};
HeadSummary summariseHeadSpeakers(const std::vector<HeadSpeakerResult>& speakers);

struct HeadProtocolOptions {
  animation::HeadModelOptions model;
  int lagFrames = animation::kLiveHeadLagFrames;  // the online variant's decoding lag
  const animation::HeadModel* compare = nullptr;  // judged beside the recipe with its own settings, if given
  unsigned seeds = 5;                             // the default's and the online variant's rows: mean over seeds
  unsigned walks = 10;                            // the random walk's row: mean over seeds
};

struct HeadProtocolResult {
  std::vector<HeadSpeakerResult> speakers;  // BEAT2's speaker first, then StyleTalk's in corpus order
  HeadSummary summary;
};

// Each speaker left out in turn; `onSpeaker`, if given, sees each result as soon as it is made (the folds
// train for a while).
HeadProtocolResult evaluateHeadLeaveOneSpeakerOut(const HeadCorpus& corpus, const HeadProtocolOptions& options,
                                                  const std::function<void(const HeadSpeakerResult&)>& onSpeaker = {});

// A person's head style judged (`eval head --style-from`): each held-out speaker's clips animated by the fold's
// model (trained without them) styled from another clip of the same speaker (animation/head_style.h), beside the
// same model unstyled, on the same clips. The style always comes from a clip that is not scored: BEAT2's speaker
// from the first part of his take (the held-out part is its last quarter), a StyleTalk speaker's clip from their
// next clip, and a speaker with one clip by halves, each half styled from the other.
struct HeadStyleSpeaker {
  std::string speaker;
  std::vector<std::string> scored;      // the clips scored, and for each
  std::vector<std::string> styledFrom;  // the clip its style came from
  std::vector<animation::HeadStyle> styles;
  HeadSpeakerTruth truth;
  HeadRow unstyled;  // the default (mean over seeds)
  HeadRow styled;
  int styledJumps = 0;            // the styled motion's steps longer than the person's longest in that clip, all seeds
  int steps = 0;                  // of which there are this many
  double longestStepRatio = 0.0;  // the styled motion's longest step over the person's longest
  // Against the truth: per-axis spread ratio (geometric mean over the axes), and the targets the styled row
  // meets: speed at most 1.25 of the truth's, pauses at most the truth's + 0.15, a Fréchet distance below the
  // unstyled one's, no jumps (no step longer than any the person makes; the row's jump% counts steps over the
  // person's 99th percentile, which the person's own motion has 1 % of).
  double styledSpread = 0.0;
  double unstyledSpread = 0.0;
  bool speedMet = false;
  bool pausesMet = false;
  bool frechetBelow = false;
  bool noJumps = false;
};

struct HeadStyleReport {
  std::vector<HeadStyleSpeaker> speakers;  // BEAT2's speaker first, then StyleTalk's
  double spreadGeometricMean = 0.0;        // of the styled per-speaker spread ratios
  double spreadLowest = 0.0;
  double spreadHighest = 0.0;
  double unstyledGeometricMean = 0.0;
};

// `onSpeaker`, if given, sees each speaker as soon as it is judged.
HeadStyleReport evaluateHeadStyles(const HeadCorpus& corpus, const HeadProtocolOptions& options,
                                   const std::function<void(const HeadStyleSpeaker&)>& onSpeaker = {});

// The idle behaviour's blinks on a take's sound, as animate and export add them: how many a minute, and how many
// start at a pause (in one, 30 dB under the loud frames, or within 0.5 s after one begins), per minute of such
// time, against those that start while the voice goes on.
struct HeadBlinkRow {
  std::string name;
  double seconds = 0.0;
  double perMinute = 0.0;
  double atPausesPerMinute = 0.0;  // per minute of time at pauses
  double pauseSeconds = 0.0;       // time at pauses
  double inSpeechPerMinute = 0.0;  // per minute of the rest
};
struct HeadBlinkReport {
  std::vector<HeadBlinkRow> takes;
  HeadBlinkRow all;  // name "all"
};
HeadBlinkReport reportHeadBlinks(const std::vector<const animation::HeadRecording*>& takes);

// A model file judged on BEAT2's held-out part (trajectory synthesis, its voiced frames only).
struct HeadModelJudgement {
  HeadSpeakerTruth truth;
  HeadRow row;
};
HeadModelJudgement judgeHeadModelOnBeat2(const HeadCorpus& corpus, const animation::HeadModel& model);

}  // namespace th::eval
