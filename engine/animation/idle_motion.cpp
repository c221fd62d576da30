#include "animation/idle_motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/portable_random.h"
#include "face/fap.h"

namespace th::animation {

namespace {

constexpr double kFullClose = 1024.0;  // FAPs 19/20: the top lid down by an iris diameter

double angleUnits(double degrees) {
  return degrees * std::numbers::pi / 180.0 / face::kAngleUnit;
}

// 0 → 1 with zero slope at both ends.
double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

}  // namespace

IdleMotion::IdleMotion(const IdleMotionOptions& options) : options_(options), random_(options.seed) {
  if (!(options.blinksPerMinute > 0.0) || !(options.minBlinkGapSeconds >= 0.0) || !(options.closeSeconds > 0.0) ||
      !(options.openSeconds > 0.0) || !(options.fixationMinSeconds > 0.0) ||
      !(options.fixationMaxSeconds >= options.fixationMinSeconds) || !(options.saccadeSeconds > 0.0) ||
      !(options.restSeconds > 0.0))
    throw Error("idle motion: rates and durations must be positive");
}

double IdleMotion::uniform(double low, double high) {
  return uniformDraw(random_, low, high);
}

void IdleMotion::scheduleBlink() {
  const double mean = 60.0 / options_.blinksPerMinute;
  blinkDue_ = gammaDraw(random_, 3.0, mean / 3.0);
}

void IdleMotion::startBlink(bool atBoundary) {
  blinkStart_ = now_;
  ++blinks_;
  if (atBoundary) ++boundaryBlinks_;
  boundaryBlink_ = -1.0;
  scheduleBlink();
}

void IdleMotion::scheduleFixation(double after) {
  nextFixation_ = after + uniform(options_.fixationMinSeconds, options_.fixationMaxSeconds);
}

void IdleMotion::apply(double seconds, double levelDb, const IdleSwitches& switches, face::FapFrame& faps) {
  if (!started_) {
    started_ = true;
    now_ = seconds;
    floorDb_ = levelDb;
    scheduleBlink();
    scheduleFixation(seconds);
  }
  const double elapsed = std::max(0.0, seconds - now_);
  now_ = std::max(now_, seconds);

  // Speech: the floor drops at once to a quieter level and rises slowly to a louder room.
  floorDb_ = std::min(levelDb, floorDb_ + options_.floorRiseDbPerSecond * elapsed);
  const bool voice = levelDb > floorDb_ + options_.speechMarginDb;
  if (voice) lastSpeech_ = now_;
  speaking_ = now_ - lastSpeech_ < options_.restAfterSeconds;
  const double target = speaking_ ? 1.0 : 0.0;
  headGain_ = target + (headGain_ - target) * std::exp(-elapsed / options_.restSeconds);
  if (switches.restHead) {
    for (int axis = 0; axis < 3; ++axis) {
      const double rest = angleUnits(options_.headRestDegrees[axis]);
      double& fap = faps[static_cast<std::size_t>(48 + axis)];
      // (A rest of 0 scales alone: adding it would turn a -0 into 0, and a file's text with it.)
      fap = rest == 0.0 ? headGain_ * fap : rest + headGain_ * (fap - rest);
    }
  }

  const double closure = blinkClosure(voice, elapsed);
  if (switches.blinks) {
    faps[19] = std::max(faps[19], kFullClose * closure);
    faps[20] = std::max(faps[20], kFullClose * closure);
  }

  followGaze();
  if (switches.gaze) {
    faps[23] += angleUnits(yaw_);
    faps[24] += angleUnits(yaw_);
    faps[25] += angleUnits(pitch_);
    faps[26] += angleUnits(pitch_);
  }
}

// Blinks: close, hold, open; spontaneous ones slower while the voice is on, one likely where a phrase ends. The
// lids' closure now, 0..1.
double IdleMotion::blinkClosure(bool voice, double elapsed) {
  if (voice) {
    if (voiceStart_ < 0.0) voiceStart_ = now_;
    lastVoice_ = now_;
    voicedRun_ = now_ - voiceStart_;
  } else if (voiceStart_ >= 0.0 && now_ - lastVoice_ >= options_.boundaryPauseSeconds) {
    voiceStart_ = -1.0;
    if (voicedRun_ >= options_.boundarySpeechSeconds && uniform(0.0, 1.0) < options_.boundaryBlinkProbability)
      boundaryBlink_ = now_ + uniform(0.0, 0.2);
  }
  blinkDue_ -= elapsed * (voice ? options_.speechBlinkFactor : 1.0);
  const bool gapOk = blinkStart_ < 0.0 || now_ - blinkStart_ >= options_.minBlinkGapSeconds;
  if (gapOk && boundaryBlink_ >= 0.0 && now_ >= boundaryBlink_) {
    startBlink(true);
  } else if (gapOk && blinkDue_ <= 0.0) {
    startBlink(false);
  }
  double closure = 0.0;
  if (blinkStart_ >= 0.0) {
    const double t = now_ - blinkStart_;
    if (t < options_.closeSeconds) {
      closure = smoothstep(t / options_.closeSeconds);
    } else if (t < options_.closeSeconds + options_.closedSeconds) {
      closure = 1.0;
    } else {
      closure = 1.0 - smoothstep((t - options_.closeSeconds - options_.closedSeconds) / options_.openSeconds);
    }
  }
  return closure;
}

// Gaze: fixations joined by saccades.
void IdleMotion::followGaze() {
  if (now_ >= nextFixation_) {
    fromYaw_ = yaw_;
    fromPitch_ = pitch_;
    const bool centre = uniform(0.0, 1.0) < 0.5;
    toYaw_ = centre ? 0.0 : uniform(-options_.gazeDegrees, options_.gazeDegrees);
    toPitch_ = centre ? 0.0 : uniform(-0.5 * options_.gazeDegrees, 0.5 * options_.gazeDegrees);
    saccadeStart_ = nextFixation_;
    scheduleFixation(nextFixation_ + options_.saccadeSeconds);
  }
  if (saccadeStart_ >= 0.0) {
    const double w = smoothstep((now_ - saccadeStart_) / options_.saccadeSeconds);
    yaw_ = fromYaw_ + w * (toYaw_ - fromYaw_);
    pitch_ = fromPitch_ + w * (toPitch_ - fromPitch_);
  }
}

void addIdleMotion(face::FapTrack& animation, const Eigen::RowVectorXd& levelDb, const IdleMotionOptions& options,
                   const IdleSwitches& switches) {
  if (levelDb.size() != 0 && levelDb.size() < animation.numFrames())
    throw Error("idle motion: fewer levels than animation frames");
  std::vector<int> numbers = animation.faps;
  for (const int fap : kIdleFaps)
    if (animation.rowOf(fap) < 0) numbers.push_back(fap);
  std::sort(numbers.begin(), numbers.end());
  Eigen::MatrixXd values = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(numbers.size()), animation.numFrames());
  for (std::size_t r = 0; r < numbers.size(); ++r) {
    const int from = animation.rowOf(numbers[r]);
    if (from >= 0) values.row(static_cast<Eigen::Index>(r)) = animation.values.row(from);
  }
  IdleMotion idle(options);
  // With no sound, a level that always counts as speech keeps the head where the animation has it.
  const bool hearing = levelDb.size() != 0;
  IdleSwitches used = switches;
  if (!hearing) used.restHead = false;
  for (int t = 0; t < animation.numFrames(); ++t) {
    face::FapFrame faps{};
    for (std::size_t r = 0; r < numbers.size(); ++r)
      faps[static_cast<std::size_t>(numbers[r])] = values(static_cast<Eigen::Index>(r), t);
    idle.apply(t / animation.framesPerSecond, hearing ? levelDb[t] : 0.0, used, faps);
    for (std::size_t r = 0; r < numbers.size(); ++r)
      values(static_cast<Eigen::Index>(r), t) = faps[static_cast<std::size_t>(numbers[r])];
  }
  animation.faps = std::move(numbers);
  animation.values = std::move(values);
}

}  // namespace th::animation
